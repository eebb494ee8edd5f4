// core/geom/mesh.h: polygon meshes as Maya models them: points, faces made of one outer loop and
// any number of hole loops, per-face-vertex UVs for several UV sets, optional per-face-vertex
// normals, hard/soft edges and colour sets. Plain data with free-standing queries and edits.
// Thread safety: a Mesh is a value; concurrent const use is safe, edits need exclusive access.
// Memory: owned by the caller (scene evaluation charges finished meshes to the MemoryBudget).
//
// Points are single-precision (glm::vec3): Maya itself keeps mesh points as floats and writes
// them with float precision, so doubles would double the memory of the largest arrays without
// adding information; Embree consumes float vertices too. Derived quantities (bounds, normals,
// areas, volume, transforms) are computed in double.
//
// Layout (compressed rows): loops are stored back to back in `faceVertices`; loop l covers
// faceVertices[loopStarts[l], loopStarts[l+1]); face f owns loops [faceLoopStarts[f],
// faceLoopStarts[f+1]), the first being its outer boundary and the rest holes. A "face-vertex"
// is a position in faceVertices; every per-face-vertex array (normals, UV ids, colour ids) is
// parallel to it. Outer loops wind counter-clockwise seen from outside; holes wind the other way.
#pragma once

#include "core/geom/bounds.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pushpin::geom {

// One UV set (`uvSet[k]` of a Maya mesh): its name, its UV values and, per face-vertex, an index
// into `uvs` (-1 where the face-vertex has no UV). An empty `faceVertexUvs` maps no face.
struct UvSet {
    std::string name;
    std::vector<glm::vec2> uvs;
    std::vector<int32_t> faceVertexUvs;
};

// One colour set: RGBA values and per-face-vertex indices into them (-1 = none).
struct ColorSet {
    std::string name;
    std::vector<glm::vec4> colors;
    std::vector<int32_t> faceVertexColors;
};

// An edge between two points; `smooth` is Maya's soft-edge flag (false = hard edge).
// Points of a mesh are numbered below this (validate() refuses more), so that an edge fits in 8
// bytes: meshes hold millions of edges.
constexpr uint64_t kMaxMeshPoints = uint64_t(1) << 31;

struct MeshEdge {
    uint32_t v0 = 0;
    uint32_t v1 : 31 = 0;
    uint32_t smooth : 1 = 1;
};
static_assert(sizeof(MeshEdge) == 8);

// What validate() found. `errors` are structural (an index out of range, inconsistent offsets,
// a non-finite point): such a mesh must not be rendered. Degenerate faces (fewer than three
// distinct vertices, zero area) are listed but the mesh stays usable; renderers skip them.
struct MeshValidation {
    std::vector<std::string> errors;
    std::vector<uint32_t> degenerateFaces;
    bool ok() const { return errors.empty(); }
};

struct Mesh {
    std::vector<glm::vec3> points;
    std::vector<uint32_t> faceVertices;       // point index per face-vertex
    std::vector<uint32_t> loopStarts{0};      // loopCount() + 1 offsets into faceVertices
    std::vector<uint32_t> faceLoopStarts{0};  // faceCount() + 1 offsets into the loops
    // Per face-vertex normals, or empty. A zero vector means "not set, compute" (Maya's 1e20).
    std::vector<glm::vec3> normals;
    // Edges with their hard/soft flags. May be empty: every edge is then soft. When present,
    // edge indices are the ones component strings ("e[3]") refer to.
    std::vector<MeshEdge> edges;
    std::vector<UvSet> uvSets;
    int currentUvSet = 0;  // index into uvSets (Maya's `currentUVSet`)
    std::vector<ColorSet> colorSets;

    size_t faceCount() const { return faceLoopStarts.empty() ? 0 : faceLoopStarts.size() - 1; }
    size_t loopCount() const { return loopStarts.empty() ? 0 : loopStarts.size() - 1; }
    size_t faceVertexCount() const { return faceVertices.size(); }
    bool empty() const { return faceCount() == 0; }

    // Point indices of loop `l` (l < loopCount()).
    std::span<const uint32_t> loop(size_t l) const {
        return {faceVertices.data() + loopStarts[l], loopStarts[l + 1] - loopStarts[l]};
    }
    // Point indices of the outer loop of face `f` (f < faceCount()).
    std::span<const uint32_t> faceOuterLoop(size_t f) const { return loop(faceLoopStarts[f]); }
    // Number of hole loops of face `f`.
    size_t holeCount(size_t f) const { return faceLoopStarts[f + 1] - faceLoopStarts[f] - 1; }
    // First face-vertex of face `f` and one past its last (holes included).
    uint32_t faceVertexBegin(size_t f) const { return loopStarts[faceLoopStarts[f]]; }
    uint32_t faceVertexEnd(size_t f) const { return loopStarts[faceLoopStarts[f + 1]]; }

    // Appends a face whose outer loop is `loop`; returns its index. Per-face-vertex arrays that
    // are in use are extended (normals with zero, UV/colour ids with -1).
    uint32_t addFace(std::span<const uint32_t> loop);
    uint32_t addFace(std::initializer_list<uint32_t> loop) { return addFace(std::span(loop.begin(), loop.size())); }
    // Appends a hole loop to the last face. Precondition: faceCount() > 0.
    void addHole(std::span<const uint32_t> loop);

    // Axis-aligned bounds of every point (used or not); empty for a mesh without points.
    Bounds3 bounds() const;
    // Newell area vector of face `f` (outer loop plus holes): direction = face normal, length =
    // area for a planar face. Indices must be valid (see validate()).
    glm::dvec3 faceAreaVector(size_t f) const;
    // Unit normal of face `f` by Newell's method; (0,0,0) for a degenerate face.
    glm::dvec3 faceNormal(size_t f) const;
    std::vector<glm::vec3> faceNormals() const;
    // Signed enclosed volume (divergence theorem over the fan-triangulated loops). Positive for a
    // closed mesh whose faces point outward; meaningless for open meshes.
    double signedVolume() const;
    // Checks every index and offset; never throws.
    MeshValidation validate() const;
    // Per face-vertex shading normals: the stored normal where set, otherwise the area-weighted
    // average of the normals of the faces around the point that are joined to this face through
    // soft edges (hard edges split the average). Requires a valid mesh.
    std::vector<glm::vec3> shadingNormals() const;
};

// The mesh's current uv set when it maps faces (a uv id, or -1, for every face-vertex), else null.
const UvSet* currentFaceUvSet(const Mesh& mesh);

// The key of the undirected edge between points a and b (either order): the lower index in the
// high 32 bits. For hash maps of edges.
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

// Whether the mesh lists the edge between two points as smooth or hard, for meshes with millions
// of edges: the listed edges filed under their lower point (4 bytes a point and 5 an edge, where
// a hash map takes about 40 an edge). Of an edge listed twice, the last entry decides; edges with
// a point out of range are left out. Immutable once built; thread-safe to read.
class EdgeSmoothness {
public:
    explicit EdgeSmoothness(const Mesh& mesh);
    enum class Kind : uint8_t { Unlisted, Smooth, Hard };
    Kind find(uint32_t a, uint32_t b) const;

private:
    std::vector<uint32_t> m_start;  // lower point → first entry (+1 end)
    std::vector<uint32_t> m_upper;  // entries by lower point, in edge order
    std::vector<uint8_t> m_smooth;
};

// Edge key → index, for the edge lists of meshes with millions of edges: open addressing with
// linear probing in flat arrays (a node-based hash map spends most of its time allocating).
// Keys are edgeKey()s of two distinct points, so never ~0. Not thread-safe.
class EdgeIndex {
public:
    explicit EdgeIndex(size_t expected = 0) { rehash(expected); }
    // The index stored for `key`, inserting `index` first when there is none; `inserted` tells.
    uint32_t emplace(uint64_t key, uint32_t index, bool* inserted = nullptr) {
        if (2 * (m_count + 1) > m_keys.size()) rehash(2 * m_count + 2);
        size_t i = slot(key);
        while (m_keys[i] != kEmpty) {
            if (m_keys[i] == key) {
                if (inserted) *inserted = false;
                return m_values[i];
            }
            i = (i + 1) & m_mask;
        }
        m_keys[i] = key;
        m_values[i] = index;
        ++m_count;
        if (inserted) *inserted = true;
        return index;
    }
    // The index stored for `key`, or `missing`.
    uint32_t find(uint64_t key, uint32_t missing) const {
        for (size_t i = slot(key); m_keys[i] != kEmpty; i = (i + 1) & m_mask)
            if (m_keys[i] == key) return m_values[i];
        return missing;
    }

private:
    static constexpr uint64_t kEmpty = ~uint64_t(0);
    size_t slot(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> m_shift) & m_mask; }
    void rehash(size_t expected) {
        size_t capacity = 16;
        int bits = 4;
        while (capacity < 2 * expected) capacity <<= 1, ++bits;
        std::vector<uint64_t> keys(capacity, kEmpty);
        std::vector<uint32_t> values(capacity);
        const size_t mask = capacity - 1;
        const int shift = 64 - bits;
        for (size_t i = 0; i < m_keys.size(); ++i) {
            if (m_keys[i] == kEmpty) continue;
            size_t j = size_t((m_keys[i] * 0x9E3779B97F4A7C15ull) >> shift) & mask;
            while (keys[j] != kEmpty) j = (j + 1) & mask;
            keys[j] = m_keys[i];
            values[j] = m_values[i];
        }
        m_keys.swap(keys);
        m_values.swap(values);
        m_mask = mask;
        m_shift = shift;
    }
    std::vector<uint64_t> m_keys;
    std::vector<uint32_t> m_values;
    size_t m_mask = 0, m_count = 0;
    int m_shift = 60;
};

// The start of a mesh rebuilt from `source`'s face-vertices: `points`, `source`'s UV and colour
// values, set names and current UV set, and no faces, edges or normals yet.
Mesh facelessCopy(const Mesh& source, std::vector<glm::vec3> points);
// Appends face-vertex `fv` of `source` to `out` (begun by facelessCopy(source, …)) at `point`: its
// normal and its UV and colour ids, for the per-face-vertex arrays `source` has. Loops and faces
// are closed by the caller (loopStarts, faceLoopStarts).
void copyFaceVertex(Mesh& out, const Mesh& source, uint32_t fv, uint32_t point);
inline void copyFaceVertex(Mesh& out, const Mesh& source, uint32_t fv) {
    copyFaceVertex(out, source, fv, source.faceVertices[fv]);
}

// Unique edges of the mesh's loops in first-use order, every edge with the given smoothness.
std::vector<MeshEdge> deriveEdges(const Mesh& mesh, bool smooth);
// Makes `mesh.edges` cover every loop edge: keeps the existing entries (and their flags) and
// appends the missing ones with `smoothForNew`.
void completeEdges(Mesh& mesh, bool smoothForNew);
// Index of the edge joining a and b in `mesh.edges` (either direction), or -1.
int64_t findEdge(const Mesh& mesh, uint32_t a, uint32_t b);

// Applies an affine transform (column-vector convention) to the points; stored normals are
// transformed by the inverse transpose and renormalised. Loop winding is kept, as Maya's
// transformGeometry keeps it: a mirroring transform turns the faces inside out.
void transformMesh(Mesh& mesh, const glm::dmat4& m);

// Removes the faces whose entry in `removeFace` is true (the mask has faceCount() entries; a
// shorter mask leaves the rest in place), then drops points no remaining face uses and renumbers
// the rest. Edges are kept when both points survive and some remaining loop still uses them.
// UV and colour values are kept; only their per-face-vertex ids are filtered.
void deleteFaces(Mesh& mesh, const std::vector<bool>& removeFace);

// Splits every face of more than three vertices (those marked in `only`, when given) into
// triangles, as polyTriangulate does: ear clipping in the face's plane, so concave faces stay
// inside their outline. Triangles take the place of their face, in order. Per-face-vertex normals,
// UV and colour ids follow their corners; the new inner edges are soft. Faces with holes are left
// whole; their count is returned.
size_t triangulateFaces(Mesh& mesh, const std::vector<bool>* only = nullptr);

// Drops points no face uses and renumbers the loops and edges. Returns how many were dropped.
size_t removeUnusedPoints(Mesh& mesh);

// The mesh's shells (faces joined through shared points), as a shell number per face; shells are
// numbered in the order of their lowest face. Returns the number of shells.
size_t faceShells(const Mesh& mesh, std::vector<uint32_t>& shellOfFace);

// Appends `part` with its points taken through the affine transform `m` (column vectors): its
// points, faces, edges, normals and colour sets follow the existing ones; its UV sets join the
// sets of the same name (new names are added, faces without a set get no UVs). Returns false,
// leaving `into` unchanged, when the result would pass 2^32 face-vertices.
bool appendMesh(Mesh& into, const Mesh& part, const glm::dmat4& m);

}  // namespace pushpin::geom
