// core/scene/value.h: the typed values a .ma `setAttr` can carry, as plain data.
// Values are immutable once stored in a Graph; large payloads are shared, never copied.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "core/scene/packed_ints.h"

namespace pushpin::scene {

// Numbers of any `setAttr` form: scalars, tuples (double3 …), numeric arrays and matrices.
// `kind` records the declared layout; `values` holds all numbers flat.
struct Numbers {
    enum class Kind : unsigned char {
        Plain,        // no -type: scalars/bools/enums, or a flat list for a range of elements
        Tuple,        // double2/3/4, float2/3, long2/3, short2/3 (also repeated for ranges)
        Int32Array,   // N values
        DoubleArray,  // N values
        PointArray,   // N × (x y z w)
        VectorArray,  // N × (x y z)
        Matrix,       // 16 values, row-major, translation in the 4th row
    };
    Kind kind = Kind::Plain;
    int tupleSize = 1;  // components per element for Tuple (2..4), 4 for PointArray, 3 for VectorArray
    std::vector<double> values;
    // A long run of a multi attribute's elements may be kept smaller instead (Graph::setValue,
    // compactNumbers): `floats` for an attribute Maya itself stores in single precision (float,
    // float2, float3: mesh points, uvs, normals), `ints` packed for an integer attribute whose values
    // are all 32-bit integers (mesh edges). At most one of the three is in use.
    std::vector<float> floats;
    PackedInts ints;

    enum class Storage : unsigned char { Doubles, Floats, Ints };
    // Which of the three holds the numbers (Doubles when there are none).
    Storage storage() const { return !floats.empty() ? Storage::Floats : !ints.empty() ? Storage::Ints : Storage::Doubles; }
    size_t size() const { return values.size() + floats.size() + ints.size(); }
    bool empty() const { return size() == 0; }
    double at(size_t i) const {
        if (!floats.empty()) return double(floats[i]);
        if (!ints.empty()) return double(ints[i]);
        return values[i];
    }
    // Numbers [first, first + n) as doubles into out.
    void copyTo(size_t first, size_t n, double* out) const {
        if (!floats.empty()) {
            for (size_t i = 0; i < n; ++i) out[i] = double(floats[first + i]);
        } else if (!ints.empty()) {
            int32_t part[256];
            for (size_t done = 0; done < n;) {
                const size_t take = std::min(n - done, std::size(part));
                ints.read(first + done, take, part);
                for (size_t i = 0; i < take; ++i) out[done + i] = double(part[i]);
                done += take;
            }
        } else {
            std::copy(values.begin() + std::ptrdiff_t(first), values.begin() + std::ptrdiff_t(first + n), out);
        }
    }
    // Numbers [first, first + n) in the same storage (packed integers come out as doubles).
    Numbers slice(size_t first, size_t n) const {
        Numbers out{kind, tupleSize, {}, {}, {}};
        if (!ints.empty()) {
            out.values.resize(n);
            copyTo(first, n, out.values.data());
        } else if (!floats.empty()) {
            out.floats.assign(floats.begin() + std::ptrdiff_t(first), floats.begin() + std::ptrdiff_t(first + n));
        } else {
            out.values.assign(values.begin() + std::ptrdiff_t(first), values.begin() + std::ptrdiff_t(first + n));
        }
        return out;
    }
    // Appends `more`'s numbers; false (nothing appended) when the two are kept in different storage
    // or either is packed.
    bool append(const Numbers& more) {
        if (more.empty()) return true;
        if (!ints.empty() || !more.ints.empty()) return false;
        if (!empty() && !more.empty() && storage() != more.storage()) return false;
        values.insert(values.end(), more.values.begin(), more.values.end());
        floats.insert(floats.end(), more.floats.begin(), more.floats.end());
        return true;
    }
    size_t heapBytes() const { return values.capacity() * sizeof(double) + floats.capacity() * sizeof(float) + ints.heapBytes(); }
};

// The widest element a compact run holds (Numbers::floats, Numbers::ints).
constexpr size_t kMaxCompactWidth = 16;
// Runs shorter than this many numbers stay doubles.
constexpr size_t kMinCompactNumbers = 64;

// Keeps a run of `count` elements of a multi attribute smaller when it may be: as floats when
// `singlePrecision` and every number is finite within float range (the attribute's own storage in
// Maya), as packed 32-bit integers (PackedInts, predicted one element back) when `integral` and
// every number is one. Runs of fewer than kMinCompactNumbers numbers, of elements wider than
// kMaxCompactWidth, or not in doubles are left.
inline void compactNumbers(Numbers& n, size_t count, bool singlePrecision, bool integral) {
    const size_t size = n.values.size();
    if (size < kMinCompactNumbers || count == 0 || size % count != 0 || size / count > kMaxCompactWidth) return;
    if (singlePrecision) {
        constexpr double kFloatMax = 3.4028234663852886e38;
        for (double v : n.values)
            if (!(std::abs(v) <= kFloatMax)) return;
        n.floats.assign(n.values.begin(), n.values.end());
    } else if (integral) {
        for (double v : n.values)
            if (!(v >= -2147483648.0 && v <= 2147483647.0 && v == std::trunc(v))) return;
        std::vector<int32_t> ints(size);
        for (size_t i = 0; i < size; ++i) ints[i] = int32_t(n.values[i]);
        n.ints = PackedInts(ints, size / count);
    } else {
        return;
    }
    std::vector<double>().swap(n.values);
}

struct StringValue { std::string text; };
struct StringArray { std::vector<std::string> items; };

// `-type "componentList" N "f[0:5]" "vtx[3]" …`
struct ComponentList { std::vector<std::string> items; };

// The indices first, first + 1, …, last - 1, usable in a range-for.
struct LoopRange {
    size_t first = 0, last = 0;

    class iterator {
    public:
        explicit iterator(size_t i) : m_i(i) {}
        size_t operator*() const { return m_i; }
        iterator& operator++() {
            ++m_i;
            return *this;
        }
        bool operator==(const iterator&) const = default;

    private:
        size_t m_i;
    };
    iterator begin() const { return iterator(first); }
    iterator end() const { return iterator(last); }
    size_t size() const { return last - first; }
    bool empty() const { return last == first; }
    size_t front() const { return first; }
    size_t operator[](size_t k) const { return first + k; }
};

// `-type "polyFaces"`: face records with edge loops (signed edge ids, see reference/ma-format.md).
// A face is one or more loops: its outer loop, then its holes. A loop has its edges (signed; e < 0
// walks edge ~e backwards), any number of uv records (`mu`, `mf`, `mh`: a uv set index and one uv id
// per edge, in file order) and at most one colour record (`fc`: one colour id per edge). Faces and
// loops are numbered from 0 in file order. The ids sit in a few packed arrays (PackedInts, predicted
// one loop back): read them through the accessors, write them through PolyFaces::Builder.
class PolyFaces {
public:
    // One uv record of a loop.
    struct Uv {
        int32_t set = 0;               // uv set index
        std::span<const int32_t> ids;  // one uv id per edge of the loop
    };
    struct UvCopy {
        int32_t set = 0;
        std::vector<int32_t> ids;
    };
    class Builder;

    size_t faceCount() const { return m_faceLoops.empty() ? loopCount() : m_faceLoops.size() - 1; }
    size_t loopCount() const { return m_loopEdges.empty() ? 0 : m_loopEdges.size() - 1; }
    // The loops of `face`: the outer loop first, then the holes.
    LoopRange loops(size_t face) const {
        if (m_faceLoops.empty()) return {face, face + 1};
        return {size_t(m_faceLoops[face]), size_t(m_faceLoops[face + 1])};
    }
    size_t edgeCount(size_t loop) const { return edgeBegin(loop + 1) - edgeBegin(loop); }
    // The edges of `loop`, read into `scratch`; the span lives as long as scratch is not changed.
    std::span<const int32_t> edges(size_t loop, std::vector<int32_t>& scratch) const {
        return readInto(m_edges, edgeBegin(loop), edgeCount(loop), scratch);
    }
    std::vector<int32_t> edges(size_t loop) const {
        std::vector<int32_t> out;
        edges(loop, out);
        return out;
    }
    size_t uvCount(size_t loop) const {
        return m_loopUvs.empty() ? m_sharedUvSets.size() : m_loopUvs[loop + 1] - m_loopUvs[loop];
    }
    // Uv record `k` (< uvCount(loop)) of `loop`, its ids read into `scratch`.
    Uv uv(size_t loop, size_t k, std::vector<int32_t>& scratch) const {
        const size_t first = edgeBegin(loop), n = edgeBegin(loop + 1) - first;
        if (m_loopUvs.empty())
            return {m_sharedUvSets[k], readInto(m_uvIds, m_sharedUvSets.size() * first + k * n, n, scratch)};
        const UvRecord& r = m_uvRecords[m_loopUvs[loop] + k];
        return {r.set, readInto(m_uvIds, r.firstId, n, scratch)};
    }
    UvCopy uv(size_t loop, size_t k) const {
        std::vector<int32_t> ids;
        const int32_t set = uv(loop, k, ids).set;
        return {set, std::move(ids)};
    }
    // The colour ids of `loop`, one per edge, read into `scratch`; empty when it has none.
    std::span<const int32_t> colors(size_t loop, std::vector<int32_t>& scratch) const {
        if (m_loopColors.empty()) return {};
        return readInto(m_colors, m_loopColors[loop], m_loopColors[loop + 1] - m_loopColors[loop], scratch);
    }
    std::vector<int32_t> colors(size_t loop) const {
        std::vector<int32_t> out;
        colors(loop, out);
        return out;
    }
    // Bytes of the arrays' storage, for memory figures.
    size_t heapBytes() const {
        return 4 * (m_faceLoops.capacity() + m_sharedUvSets.capacity() + m_loopUvs.capacity() + m_loopColors.capacity()) +
               m_loopEdges.heapBytes() + m_edges.heapBytes() + m_uvIds.heapBytes() + m_colors.heapBytes() +
               sizeof(UvRecord) * m_uvRecords.capacity();
    }

private:
    struct UvRecord {
        int32_t set;
        uint32_t firstId;  // into m_uvIds
    };
    size_t edgeBegin(size_t loop) const { return size_t(uint32_t(m_loopEdges[loop])); }
    static std::span<const int32_t> readInto(const PackedInts& from, size_t first, size_t n, std::vector<int32_t>& scratch) {
        scratch.resize(n);
        from.read(first, n, scratch.data());
        return scratch;
    }

    // Face f's loops are [m_faceLoops[f], m_faceLoops[f + 1]); empty while no face has a hole, when
    // face f is loop f.
    std::vector<uint32_t> m_faceLoops;
    // Loop l's edges are m_edges[m_loopEdges[l] .. m_loopEdges[l + 1]) (offsets as uint32 bits).
    PackedInts m_loopEdges;
    PackedInts m_edges;
    // While m_loopUvs is empty, every loop has uv records of the sets m_sharedUvSets, in that order,
    // and the ids of loop l's record k start at m_sharedUvSets.size() × m_loopEdges[l] + k × (its
    // edge count). Otherwise loop l's records are m_uvRecords[m_loopUvs[l] .. m_loopUvs[l + 1]).
    std::vector<int32_t> m_sharedUvSets;
    std::vector<uint32_t> m_loopUvs;
    std::vector<UvRecord> m_uvRecords;
    PackedInts m_uvIds;
    // Loop l's colour ids are m_colors[m_loopColors[l] .. m_loopColors[l + 1]); empty while no loop
    // has any.
    std::vector<uint32_t> m_loopColors;
    PackedInts m_colors;
};

// Appends faces to a PolyFaces in file order. The records of the last face may come in any order
// (`mf` after `h` names its outer loop again): the face is stored when the next one begins or at
// finish(). Loops of the last face are numbered from 0, its outer loop. Calls that break the rules
// below throw std::logic_error.
class PolyFaces::Builder {
public:
    // Ids (edges, uv and colour ids together) one value can hold.
    static constexpr size_t kMaxIds = UINT32_MAX;

    // Room for about `faces` faces.
    void reserve(size_t faces) {
        m_out.loopEdges.reserve(faces + 1);
        m_out.edges.reserve(4 * faces);
    }
    // Whether `ids` more ids fit under kMaxIds.
    bool fits(size_t ids) const { return ids <= kMaxIds - std::min(m_ids, kMaxIds); }
    // A new face with this outer loop (at least one edge).
    void addFace(std::span<const int32_t> edges) {
        store();
        ++m_faces;
        addLoop(edges);
    }
    // A hole of the last face (at least one edge).
    void addHole(std::span<const int32_t> edges) {
        if (m_faces == 0) throw std::logic_error("PolyFaces::Builder: a hole before any face");
        addLoop(edges);
    }
    size_t faceCount() const { return m_faces; }
    // Loops of the last face: 0 before the first face, else 1 + its holes.
    size_t loopCount() const { return m_openLoopEdges.size() - 1; }
    size_t edgeCount(size_t loop) const { return m_openLoopEdges.at(loop + 1) - m_openLoopEdges[loop]; }
    bool hasColors(size_t loop) const { return m_openColors.at(loop) != kNone; }
    // A uv record of `loop` of the last face: one id per edge.
    void addUvs(size_t loop, int32_t set, std::span<const int32_t> ids) {
        checkIds(loop, ids);
        m_openUvs.push_back({uint32_t(loop), set, uint32_t(m_openIds.size())});
        appendIds(ids);
    }
    // The colour record of `loop` of the last face (at most one): one id per edge.
    void setColors(size_t loop, std::span<const int32_t> ids) {
        checkIds(loop, ids);
        if (hasColors(loop)) throw std::logic_error("PolyFaces::Builder: a second colour record");
        m_openColors[loop] = uint32_t(m_openIds.size());
        appendIds(ids);
    }
    // The faces added, packed. The builder is empty afterwards.
    PolyFaces finish() {
        store();
        Plain& o = m_out;
        PolyFaces out;
        const size_t hint = o.loopCount() > 0 ? size_t(o.loopEdges[1]) : 1;
        auto pack = [](const std::vector<uint32_t>& v) {
            return PackedInts(std::span<const int32_t>(reinterpret_cast<const int32_t*>(v.data()), v.size()), 1);
        };
        out.m_faceLoops = std::move(o.faceLoops);
        out.m_faceLoops.shrink_to_fit();
        out.m_loopEdges = pack(o.loopEdges);
        out.m_edges = PackedInts(o.edges, hint);
        out.m_sharedUvSets = std::move(o.sharedUvSets);
        out.m_sharedUvSets.shrink_to_fit();
        out.m_loopUvs = std::move(o.loopUvs);
        out.m_loopUvs.shrink_to_fit();
        out.m_uvRecords = std::move(o.uvRecords);
        out.m_uvRecords.shrink_to_fit();
        out.m_uvIds = PackedInts(o.uvIds, hint * std::max<size_t>(1, out.m_sharedUvSets.size()));
        out.m_loopColors = std::move(o.loopColors);
        out.m_loopColors.shrink_to_fit();
        out.m_colors = PackedInts(o.colors, hint);
        *this = Builder();
        return out;
    }

private:
    static constexpr uint32_t kNone = UINT32_MAX;
    struct OpenUv {
        uint32_t loop;
        int32_t set;
        uint32_t firstId;  // into m_openIds
    };
    // The stored faces, unpacked: the arrays of PolyFaces as plain vectors.
    struct Plain {
        std::vector<uint32_t> faceLoops;
        std::vector<uint32_t> loopEdges{0};
        std::vector<int32_t> edges;
        std::vector<int32_t> sharedUvSets;
        std::vector<uint32_t> loopUvs;
        std::vector<UvRecord> uvRecords;
        std::vector<int32_t> uvIds;
        std::vector<uint32_t> loopColors;
        std::vector<int32_t> colors;
        size_t loopCount() const { return loopEdges.size() - 1; }
    };

    void checkIds(size_t loop, std::span<const int32_t> ids) const {
        if (ids.size() != edgeCount(loop)) throw std::logic_error("PolyFaces::Builder: ids do not match the edges");
    }
    void appendIds(std::span<const int32_t> ids) {
        if (!fits(ids.size())) throw std::logic_error("PolyFaces::Builder: more than kMaxIds ids");
        m_ids += ids.size();
        m_openIds.insert(m_openIds.end(), ids.begin(), ids.end());
    }
    void addLoop(std::span<const int32_t> edges) {
        if (edges.empty()) throw std::logic_error("PolyFaces::Builder: a loop without edges");
        if (!fits(edges.size())) throw std::logic_error("PolyFaces::Builder: more than kMaxIds ids");
        m_ids += edges.size();
        m_openEdges.insert(m_openEdges.end(), edges.begin(), edges.end());
        m_openLoopEdges.push_back(uint32_t(m_openEdges.size()));
        m_openColors.push_back(kNone);
    }
    // Moves the last face into m_out.
    void store() {
        Plain& o = m_out;
        const size_t loops = loopCount();
        if (loops == 0) return;
        if (loops > 1 && o.faceLoops.empty()) {
            // The first face with a hole: every face so far is one loop.
            o.faceLoops.resize(o.loopCount() + 1);
            for (size_t f = 0; f < o.faceLoops.size(); ++f) o.faceLoops[f] = uint32_t(f);
        }
        if (loops > 1 && !std::is_sorted(m_openUvs.begin(), m_openUvs.end(),
                                         [](const OpenUv& a, const OpenUv& b) { return a.loop < b.loop; }))
            std::stable_sort(m_openUvs.begin(), m_openUvs.end(),
                             [](const OpenUv& a, const OpenUv& b) { return a.loop < b.loop; });
        size_t nextUv = 0;
        for (size_t l = 0; l < loops; ++l) {
            const size_t loop = o.loopCount();
            const size_t first = m_openLoopEdges[l], n = m_openLoopEdges[l + 1] - first;
            o.edges.insert(o.edges.end(), m_openEdges.begin() + first, m_openEdges.begin() + first + n);
            o.loopEdges.push_back(uint32_t(o.edges.size()));

            const size_t uvBegin = nextUv;
            while (nextUv < m_openUvs.size() && m_openUvs[nextUv].loop == l) ++nextUv;
            const std::span<const OpenUv> uvs(m_openUvs.data() + uvBegin, nextUv - uvBegin);
            if (o.loopUvs.empty()) {
                if (loop == 0) {
                    for (const OpenUv& r : uvs) o.sharedUvSets.push_back(r.set);
                    o.uvIds.reserve(uvs.size() * o.edges.capacity());
                } else if (!std::equal(uvs.begin(), uvs.end(), o.sharedUvSets.begin(), o.sharedUvSets.end(),
                                       [](const OpenUv& r, int32_t set) { return r.set == set; })) {
                    recordUvsPerLoop(loop);
                }
            }
            for (const OpenUv& r : uvs) {
                if (!o.loopUvs.empty()) o.uvRecords.push_back({r.set, uint32_t(o.uvIds.size())});
                o.uvIds.insert(o.uvIds.end(), m_openIds.begin() + r.firstId, m_openIds.begin() + r.firstId + n);
            }
            if (!o.loopUvs.empty()) o.loopUvs.push_back(uint32_t(o.uvRecords.size()));

            if (const uint32_t c = m_openColors[l]; c != kNone) {
                if (o.loopColors.empty()) o.loopColors.assign(loop + 1, 0);
                o.colors.insert(o.colors.end(), m_openIds.begin() + c, m_openIds.begin() + c + n);
            }
            if (!o.loopColors.empty()) o.loopColors.push_back(uint32_t(o.colors.size()));
        }
        if (!o.faceLoops.empty()) o.faceLoops.push_back(uint32_t(o.loopCount()));
        m_openLoopEdges.resize(1);
        m_openEdges.clear();
        m_openUvs.clear();
        m_openColors.clear();
        m_openIds.clear();
    }
    // Leaves the shared uv layout: loops [0, loops) get records of their own.
    void recordUvsPerLoop(size_t loops) {
        Plain& o = m_out;
        const size_t k = o.sharedUvSets.size();
        o.loopUvs.reserve(o.loopEdges.capacity());
        o.loopUvs.push_back(0);
        for (size_t l = 0; l < loops; ++l) {
            const size_t n = o.loopEdges[l + 1] - o.loopEdges[l];
            for (size_t r = 0; r < k; ++r)
                o.uvRecords.push_back({o.sharedUvSets[r], uint32_t(k * o.loopEdges[l] + r * n)});
            o.loopUvs.push_back(uint32_t(o.uvRecords.size()));
        }
        o.sharedUvSets.clear();
    }

    Plain m_out;
    size_t m_faces = 0;
    size_t m_ids = 0;  // ids added, stored or open
    // The last face, not yet stored: its loops' edges, uv records and colour records.
    std::vector<uint32_t> m_openLoopEdges{0};
    std::vector<int32_t> m_openEdges;
    std::vector<OpenUv> m_openUvs;
    std::vector<uint32_t> m_openColors;  // per loop: where its colour ids start in m_openIds, or kNone
    std::vector<int32_t> m_openIds;
};

// `-type "nurbsCurve"`: degree spans form rational dimension / knots / CVs.
struct NurbsCurveData {
    int degree = 3;
    int spans = 0;
    int form = 0;  // 0 open, 1 closed, 2 periodic
    bool rational = false;
    int dimension = 3;          // 2 or 3
    std::vector<double> knots;  // Maya's knot vector (two fewer than the textbook one)
    std::vector<double> cvs;    // dimension (+1 weight if rational) numbers per CV
};

// `-type "nurbsSurface"`: CVs U-major (V varies fastest), see reference/ma-format.md.
struct NurbsSurfaceData {
    int degreeU = 3, degreeV = 3;
    int formU = 0, formV = 0;  // 0 open, 1 closed, 2 periodic
    bool rational = false;
    bool trimmed = false;  // TRIM token present
    std::vector<double> knotsU, knotsV;
    int cvCountU = 0, cvCountV = 0;  // derived: knots + 1 − degree
    std::vector<double> cvs;         // 3 (or 4 when rational) numbers per CV
};

// Any `-type` the reader keeps as tokens without interpreting them (dataPolyComponent, mesh, …).
struct RawData {
    std::string type;
    std::vector<std::string> tokens;
};

using Value = std::variant<std::monostate, Numbers, StringValue, StringArray, ComponentList,
                           std::shared_ptr<const PolyFaces>, std::shared_ptr<const NurbsCurveData>,
                           std::shared_ptr<const NurbsSurfaceData>, RawData>;

}  // namespace pushpin::scene
