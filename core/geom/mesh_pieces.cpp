#include "core/geom/mesh_pieces.h"

#include "core/util/parallel_runs.h"
#include "core/util/release.h"

#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_sort.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pushpin::geom {

namespace {

constexpr uint32_t kNotLocal = 0xffffffffu;
// Runs of faces or edges around a piece closer than this are joined (the faces or edges between
// come along and are passed over): fewer runs to read for a few more elements.
constexpr uint32_t kRunGap = 8;
// A piece whose faces or edges around it take more runs than this gets one run from the first to
// the last instead: its window then reads what lies between, but the table stays small whatever
// the order of the mesh's faces and edges.
constexpr size_t kMostRunsAround = 1024;

// The 10 low bits of v spread to every third bit.
uint32_t spreadBits(uint32_t v) {
    v &= 0x3ffu;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
}

// Adds element `i` (given in ascending order) to `runs`, joining it to the last run when at most
// kRunGap elements lie between. `start` makes a new run of it.
template <class Run, class Start>
void addToRuns(std::vector<Run>& runs, uint32_t i, Start&& start) {
    if (!runs.empty() && runs.back().end > i) return;
    if (!runs.empty() && i - runs.back().end <= kRunGap) {
        runs.back().end = i + 1;
        return;
    }
    runs.push_back(start());
}

// One run from the first to the last, when there are too many.
template <class Run>
void boundRuns(std::vector<Run>& runs) {
    if (runs.size() <= kMostRunsAround) return;
    Run one = runs.front();
    one.end = runs.back().end;
    runs.assign(1, one);
    runs.shrink_to_fit();
}

// The pieces of each point: `first` the first piece seen there, `more` (point << 32 | piece,
// sorted, each once) the others, `shared` whether `more` holds any for the point (most points are
// inside one piece and need no search).
struct PointPieces {
    std::vector<uint32_t> first;
    std::vector<uint64_t> more;
    std::vector<bool> shared;

    template <class Visit>
    void forEach(uint32_t q, Visit&& visit) const {
        if (q >= first.size() || first[q] == kNotLocal) return;
        visit(first[q]);
        if (!shared[q]) return;
        auto it = std::lower_bound(more.begin(), more.end(), uint64_t(q) << 32);
        for (; it != more.end() && uint32_t(*it >> 32) == q; ++it) visit(uint32_t(*it));
    }
};

// Each kept face's piece (kNotLocal for the others), cutting the kept faces in `order` into
// groups of at most maxSlots triangle ids. Returns the number of pieces.
template <class Order>
uint32_t cutPieces(std::vector<uint32_t>& pieceOf, uint32_t maxSlots, Order&& order) {
    uint32_t count = 0;
    uint64_t inPiece = 0;
    order([&](uint32_t f, uint32_t n) {
        if (inPiece > 0 && inPiece + n > maxSlots) {
            ++count;
            inPiece = 0;
        }
        pieceOf[f] = count;
        inPiece += n;
    });
    return inPiece > 0 ? count + 1 : count;
}

// Each kept face's piece from `keys` (Morton code << 32 | face, sorted): the cell of the 1024³
// grid holding every face is split into its eight children while it holds more than maxSlots
// triangle ids, and consecutive children are gathered into one piece while they fit, so that a
// piece lies within one cell of the octree and is as compact as the cell. A cell of the finest
// level that still holds too many is cut in the keys' order. Returns the number of pieces.
template <class Bound>
uint32_t cutCells(const std::vector<uint64_t>& keys, std::vector<uint32_t>& pieceOf, uint32_t maxSlots, Bound&& bound) {
    auto slotsOf = [&](size_t i) { return uint64_t(bound(uint32_t(keys[i]))); };
    uint32_t count = 0;
    auto emit = [&](size_t lo, size_t hi) {
        if (lo == hi) return;
        for (size_t i = lo; i < hi; ++i) pieceOf[uint32_t(keys[i])] = count;
        ++count;
    };
    // Keys [lo, hi) share their code above `level`'s three bits and hold `total` triangle ids.
    auto cut = [&](auto&& self, size_t lo, size_t hi, int level, uint64_t total) -> void {
        if (total <= maxSlots) return emit(lo, hi);
        if (level == 0) {
            size_t start = lo;
            uint64_t held = 0;
            for (size_t i = lo; i < hi; ++i) {
                const uint64_t n = slotsOf(i);
                if (i > start && held + n > maxSlots) {
                    emit(start, i);
                    start = i;
                    held = 0;
                }
                held += n;
            }
            return emit(start, hi);
        }
        const int shift = 32 + 3 * (level - 1);
        size_t groupLo = lo, groupHi = lo;
        uint64_t groupSlots = 0;
        for (size_t childLo = lo; childLo < hi;) {
            const uint64_t child = (keys[childLo] >> shift) & 7;
            size_t childHi = childLo;
            uint64_t childSlots = 0;
            for (; childHi < hi && ((keys[childHi] >> shift) & 7) == child; ++childHi) childSlots += slotsOf(childHi);
            if (childSlots > maxSlots) {
                emit(groupLo, groupHi);
                self(self, childLo, childHi, level - 1, childSlots);
                groupLo = groupHi = childHi;
                groupSlots = 0;
            } else if (groupSlots + childSlots > maxSlots) {
                emit(groupLo, groupHi);
                groupLo = childLo;
                groupHi = childHi;
                groupSlots = childSlots;
            } else {
                groupHi = childHi;
                groupSlots += childSlots;
            }
            childLo = childHi;
        }
        emit(groupLo, groupHi);
    };
    uint64_t total = 0;
    for (size_t i = 0; i < keys.size(); ++i) total += slotsOf(i);
    cut(cut, 0, keys.size(), 10, total);
    return count;
}

}  // namespace

uint64_t MeshPieces::bytes() const {
    return uint64_t(m_pieces.capacity()) * sizeof(MeshPiece) +
           uint64_t(m_faceRuns.capacity() + m_aroundRuns.capacity()) * sizeof(FaceRun) +
           uint64_t(m_edgeRuns.capacity()) * sizeof(EdgeRun) +
           uint64_t(m_slotRuns.capacity() + m_pieceSlotRuns.capacity()) * sizeof(SlotRun);
}

MeshPieces MeshPieces::split(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                             const std::vector<bool>& degenerate, uint32_t maxSlots, Layout layout) {
    MeshPieces out;
    maxSlots = std::max<uint32_t>(maxSlots, 1);
    const size_t faces = mesh.faceCount(), points = mesh.points.size();
    // Each face's triangle-id bound, worked out once on all threads (a byte a face; a face of 255
    // or more is worked out again where it is read).
    constexpr size_t kRun = 16384;
    const size_t runCount = util::runCount(faces, kRun);
    auto eachRun = [&](auto&& body) { util::forEachRun(faces, kRun, body); };
    std::vector<uint8_t> boundOf(faces);
    eachRun([&](size_t, size_t lo, size_t hi) {
        for (size_t f = lo; f < hi; ++f)
            boundOf[f] = uint8_t(std::min<uint32_t>(faceTriangleBound(mesh, faceMaterial, degenerate, f), 255));
    });
    auto bound = [&](size_t f) -> uint32_t {
        return boundOf[f] < 255 ? boundOf[f] : faceTriangleBound(mesh, faceMaterial, degenerate, f);
    };

    // Each kept face's piece.
    std::vector<uint32_t> pieceOf(faces, kNotLocal);
    auto inFaceOrder = [&](auto&& visit) {
        for (size_t f = 0; f < faces; ++f)
            if (boundOf[f] > 0) visit(uint32_t(f), bound(f));
    };
    uint32_t pieceCount = 0;
    bool spatial = false;
    if (layout == Layout::Spatial) {
        // Face centres (the mean of the outer loop's points) on a 1024³ grid over the cube around
        // them, ordered along the Morton curve, ties by face. Runs of faces on all threads: each
        // run's box and count of kept faces, then each run's keys at its place.
        auto centre = [&](size_t f) {
            glm::dvec3 c(0.0);
            const std::span<const uint32_t> loop = mesh.faceOuterLoop(f);
            for (uint32_t q : loop) c += glm::dvec3(mesh.points[q]);
            return c / double(std::max<size_t>(loop.size(), 1));
        };
        std::vector<Bounds3> runBox(runCount);
        std::vector<size_t> runKeys(runCount + 1, 0);
        eachRun([&](size_t r, size_t lo, size_t hi) {
            for (size_t f = lo; f < hi; ++f)
                if (boundOf[f] > 0) {
                    runBox[r].extend(centre(f));
                    ++runKeys[r + 1];
                }
        });
        Bounds3 box;
        for (size_t r = 0; r < runCount; ++r) {
            box.extend(runBox[r]);
            runKeys[r + 1] += runKeys[r];
        }
        double extent = 0.0;
        for (int a = 0; a < 3; ++a) extent = std::max(extent, box.hi[a] - box.lo[a]);
        const double scale = extent > 0.0 && std::isfinite(extent) ? 1024.0 / extent : 0.0;
        std::vector<uint64_t> keys(runKeys[runCount]);
        eachRun([&](size_t r, size_t lo, size_t hi) {
            size_t at = runKeys[r];
            for (size_t f = lo; f < hi; ++f) {
                if (boundOf[f] == 0) continue;
                const glm::dvec3 c = (centre(f) - box.lo) * scale;
                uint32_t code = 0;
                for (int a = 0; a < 3; ++a)
                    code |= spreadBits(uint32_t(std::clamp(c[a], 0.0, 1023.0))) << a;
                keys[at++] = uint64_t(code) << 32 | f;
            }
        });
        // The keys are distinct: any sort gives the same order.
        tbb::this_task_arena::isolate([&] { tbb::parallel_sort(keys.begin(), keys.end()); });
        const size_t kept = keys.size();
        pieceCount = cutCells(keys, pieceOf, maxSlots, bound);
        util::release(keys);
        // A mesh whose faces lie in no spatial order gives runs of a face or two: cut in face
        // order then.
        size_t runs = 0;
        uint32_t last = kNotLocal;
        for (size_t f = 0; f < faces; ++f)
            if (pieceOf[f] != kNotLocal) {
                runs += pieceOf[f] != last;
                last = pieceOf[f];
            }
        spatial = runs <= std::max<size_t>(size_t(pieceCount) * 8, kept / 4);
        if (!spatial) std::fill(pieceOf.begin(), pieceOf.end(), kNotLocal);
    }
    if (!spatial) pieceCount = cutPieces(pieceOf, maxSlots, inFaceOrder);
    out.m_spatial = spatial;
    out.m_pieces.resize(pieceCount);

    // Each piece's own runs (a kept face whose last kept predecessor is of the same piece extends
    // that piece's run over the faces between, which give no triangles), its triangle ids, its
    // bounds; and the pieces of each point of a kept face.
    std::vector<std::vector<FaceRun>> own(pieceCount);
    std::vector<std::vector<SlotRun>> ownSlots(pieceCount);
    PointPieces at;
    at.first.assign(points, kNotLocal);
    at.shared.assign(points, false);
    {
        uint64_t slot = 0;
        uint32_t lastPiece = kNotLocal;
        for (size_t f = 0; f < faces; ++f) {
            const uint32_t p = pieceOf[f];
            if (p == kNotLocal) continue;
            const uint32_t n = bound(f);
            MeshPiece& piece = out.m_pieces[p];
            if (p == lastPiece) {
                own[p].back().end = uint32_t(f) + 1;
            } else {
                own[p].push_back({uint32_t(f), uint32_t(f) + 1, uint32_t(slot), mesh.faceVertexBegin(f)});
                ownSlots[p].push_back({uint32_t(slot), p, piece.slotCount});
            }
            lastPiece = p;
            piece.slotCount += n;
            for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c) {
                const uint32_t q = mesh.faceVertices[c];
                piece.bounds.extend(glm::dvec3(mesh.points[q]));
                if (at.first[q] == kNotLocal) at.first[q] = p;
                else if (at.first[q] != p) {
                    at.more.push_back(uint64_t(q) << 32 | p);
                    at.shared[q] = true;
                }
            }
            slot += n;
        }
        out.m_slots = slot;
    }
    util::release(pieceOf);
    std::sort(at.more.begin(), at.more.end());
    at.more.erase(std::unique(at.more.begin(), at.more.end()), at.more.end());
    at.more.shrink_to_fit();

    // The faces around each piece (every face with a corner at one of its points), and the edges
    // with an end at a point of each piece, side by side.
    std::vector<std::vector<FaceRun>> around(pieceCount);
    std::vector<std::vector<EdgeRun>> edgesAround(pieceCount);
    auto facesAround = [&] {
        uint64_t slot = 0;
        for (size_t f = 0; f < faces; ++f) {
            for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c)
                at.forEach(mesh.faceVertices[c], [&](uint32_t p) {
                    addToRuns(around[p], uint32_t(f), [&] {
                        return FaceRun{uint32_t(f), uint32_t(f) + 1, uint32_t(slot), mesh.faceVertexBegin(f)};
                    });
                });
            slot += bound(f);
        }
    };
    auto edgesAroundPieces = [&] {
        for (size_t e = 0; e < mesh.edges.size(); ++e)
            for (const uint32_t q : {uint32_t(mesh.edges[e].v0), uint32_t(mesh.edges[e].v1)})
                at.forEach(q, [&](uint32_t p) {
                    addToRuns(edgesAround[p], uint32_t(e), [&] { return EdgeRun{uint32_t(e), uint32_t(e) + 1}; });
                });
    };
    if (runCount > 4) tbb::this_task_arena::isolate([&] { tbb::parallel_invoke(facesAround, edgesAroundPieces); });
    else {
        facesAround();
        edgesAroundPieces();
    }
    util::release(at.more);
    util::release(at.shared);

    // Flat tables.
    for (uint32_t p = 0; p < pieceCount; ++p) {
        MeshPiece& piece = out.m_pieces[p];
        boundRuns(around[p]);
        boundRuns(edgesAround[p]);
        piece.faceRunBegin = uint32_t(out.m_faceRuns.size());
        out.m_faceRuns.insert(out.m_faceRuns.end(), own[p].begin(), own[p].end());
        out.m_pieceSlotRuns.insert(out.m_pieceSlotRuns.end(), ownSlots[p].begin(), ownSlots[p].end());
        piece.faceRunEnd = uint32_t(out.m_faceRuns.size());
        piece.aroundRunBegin = uint32_t(out.m_aroundRuns.size());
        out.m_aroundRuns.insert(out.m_aroundRuns.end(), around[p].begin(), around[p].end());
        piece.aroundRunEnd = uint32_t(out.m_aroundRuns.size());
        piece.edgeRunBegin = uint32_t(out.m_edgeRuns.size());
        out.m_edgeRuns.insert(out.m_edgeRuns.end(), edgesAround[p].begin(), edgesAround[p].end());
        piece.edgeRunEnd = uint32_t(out.m_edgeRuns.size());
        util::release(own[p]);
        util::release(ownSlots[p]);
        util::release(around[p]);
        util::release(edgesAround[p]);
    }
    out.m_slotRuns = out.m_pieceSlotRuns;
    std::sort(out.m_slotRuns.begin(), out.m_slotRuns.end(),
              [](const SlotRun& a, const SlotRun& b) { return a.firstSlot < b.firstSlot; });

    // What each piece's window holds: its faces, face-vertices and promised triangles, and the
    // points, uvs and edges among them, counted with a stamp per point and uv.
    const UvSet* uvSet = currentFaceUvSet(mesh);
    out.m_mapsUvs = uvSet != nullptr;
    std::vector<uint32_t>& pointStamp = at.first;
    std::fill(pointStamp.begin(), pointStamp.end(), kNotLocal);
    std::vector<uint32_t> uvStamp(uvSet ? uvSet->uvs.size() : 0, kNotLocal);
    for (uint32_t p = 0; p < pieceCount; ++p) {
        MeshPiece& piece = out.m_pieces[p];
        for (const FaceRun& r : out.aroundRuns(p)) {
            const uint64_t fv = mesh.faceVertexBegin(r.end) - mesh.faceVertexBegin(r.first);
            const uint64_t loops = mesh.faceLoopStarts[r.end] - mesh.faceLoopStarts[r.first];
            const uint64_t runFaces = r.end - r.first;
            piece.windowFaces += runFaces;
            piece.windowFaceVertices += fv;
            // n + 2h − 2 a face: face-vertices, twice the loops, less four times the faces.
            piece.windowTriangles += fv + 2 * loops - std::min<uint64_t>(fv + 2 * loops, 4 * runFaces);
            for (uint32_t c = mesh.faceVertexBegin(r.first); c < mesh.faceVertexBegin(r.end); ++c) {
                uint32_t& stamp = pointStamp[mesh.faceVertices[c]];
                if (stamp != p) {
                    stamp = p;
                    ++piece.windowPoints;
                }
                if (uvSet && uvSet->faceVertexUvs[c] >= 0) {
                    uint32_t& uvMark = uvStamp[size_t(uvSet->faceVertexUvs[c])];
                    if (uvMark != p) {
                        uvMark = p;
                        ++piece.windowUvs;
                    }
                }
            }
        }
        for (const EdgeRun& r : out.edgeRuns(p))
            for (uint32_t e = r.first; e < r.end; ++e) {
                const MeshEdge& edge = mesh.edges[e];
                piece.windowEdges += edge.v0 < points && edge.v1 < points && pointStamp[edge.v0] == p &&
                                     pointStamp[edge.v1] == p;
            }
    }
    return out;
}

uint64_t meshPieceWorkBytes(const MeshPiece& piece, uint64_t sourcePoints, bool smoothShading, bool normals, bool uvs) {
    const uint64_t fv = piece.windowFaceVertices, points = piece.windowPoints, t = piece.windowTriangles;
    const uint64_t faces = piece.windowFaces;
    // The point map; the piece's mesh (points, face-vertices with their normals and uv ids, loop
    // and face starts, edges, uvs, and the uv map as large as the uvs); its tessellation (vertices
    // of position, normal and uv; corners, face, material, neighbours, cluster bounds); the
    // slot and vertex maps.
    const uint64_t pointMap = sourcePoints * sizeof(uint32_t);
    const uint64_t uvBytes = uvs ? 2 * sizeof(glm::vec2) + sizeof(int32_t) : 0;
    const uint64_t mesh = points * (sizeof(glm::vec3) + 3 * sizeof(MeshEdge) + uvBytes) +
                          fv * (sizeof(uint32_t) + (uvs ? sizeof(int32_t) : 0) + (normals ? sizeof(glm::vec3) : 0)) +
                          2 * (faces + 1) * sizeof(uint32_t);
    const uint64_t vertices = points + points / 8;
    const uint64_t tessellation = vertices * (uvs ? 32 : 24) + t * (7 * sizeof(uint32_t) + sizeof(uint16_t) + 1);
    // triangulateValidMesh's working memory, phase by phase (GeometryHandle's estimate).
    const uint64_t edges = 3 * points;
    const uint64_t normalsPhase =
        smoothShading ? std::max(16 * fv + 24 * faces + 8 * points + 5 * edges, 24 * fv + 24 * faces + 4 * points) : 0;
    const uint64_t cornerPhase = (smoothShading ? 12 * fv : 0) + 24 * t + 4 * points;
    const uint64_t adjacencyPhase = 24 * t + 4 * points + (smoothShading ? 4 * points + 5 * edges : 0);
    // The sub-mesh's faces (index, slot and own flag) and the slot and vertex maps.
    const uint64_t maps = vertices * sizeof(uint32_t) + 4 * faces * sizeof(uint32_t);
    return pointMap + mesh + tessellation + std::max({normalsPhase, cornerPhase, adjacencyPhase}) + maps;
}

MeshWindow cutMeshWindow(const Mesh& mesh, const MeshPieces& pieces, size_t piece) {
    MeshWindow w;
    w.window = true;
    Mesh& m = w.mesh;
    const std::span<const FaceRun> around = pieces.aroundRuns(piece);
    // Calls visit(c) for every face-vertex of the window's faces, in order.
    auto forEachCorner = [&](auto&& visit) {
        for (const FaceRun& r : around)
            for (uint32_t c = mesh.faceVertexBegin(r.first); c < mesh.faceVertexBegin(r.end); ++c) visit(c);
    };
    std::vector<uint32_t> used;
    forEachCorner([&](uint32_t c) { used.push_back(mesh.faceVertices[c]); });
    const WindowIds points(std::move(used));
    m.points.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) m.points.push_back(mesh.points[points[i]]);
    const bool normals = mesh.normals.size() == mesh.faceVertexCount();
    m.loopStarts.clear();
    m.faceLoopStarts.clear();
    for (const FaceRun& r : around)
        for (uint32_t f = r.first; f < r.end; ++f) {
            m.faceLoopStarts.push_back(uint32_t(m.loopStarts.size()));
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                m.loopStarts.push_back(uint32_t(m.faceVertices.size()));
                for (uint32_t c = mesh.loopStarts[l]; c < mesh.loopStarts[l + 1]; ++c) {
                    m.faceVertices.push_back(points.place(mesh.faceVertices[c]));
                    if (normals) m.normals.push_back(mesh.normals[c]);
                }
            }
        }
    m.loopStarts.push_back(uint32_t(m.faceVertices.size()));
    m.faceLoopStarts.push_back(uint32_t(m.loopStarts.size() - 1));
    if (const UvSet* from = currentFaceUvSet(mesh)) {
        std::vector<uint32_t> ids;
        forEachCorner([&](uint32_t c) {
            if (from->faceVertexUvs[c] >= 0) ids.push_back(uint32_t(from->faceVertexUvs[c]));
        });
        const WindowIds uvs(std::move(ids));
        UvSet set;
        set.name = from->name;
        set.uvs.reserve(uvs.size());
        for (size_t i = 0; i < uvs.size(); ++i) set.uvs.push_back(from->uvs[uvs[i]]);
        set.faceVertexUvs.reserve(m.faceVertices.size());
        forEachCorner([&](uint32_t c) {
            const int32_t id = from->faceVertexUvs[c];
            set.faceVertexUvs.push_back(id >= 0 ? int32_t(uvs.place(uint32_t(id))) : -1);
        });
        m.uvSets.push_back(std::move(set));
        m.currentUvSet = 0;
    }
    for (const EdgeRun& r : pieces.edgeRuns(piece))
        for (uint32_t e = r.first; e < r.end; ++e) {
            const MeshEdge& edge = mesh.edges[e];
            if (points.contains(edge.v0) && points.contains(edge.v1))
                m.edges.push_back({points.place(edge.v0), points.place(edge.v1), edge.smooth});
        }
    return w;
}

namespace {

// triangulateMeshPiece on `mesh`: the whole mesh, or the piece's window (`window`). Faces are named
// by their whole-mesh index f and by their index in `mesh` (f itself, or their place among the
// window's faces).
Tessellation triangulatePieceIn(const Mesh& mesh, bool window, const std::vector<uint16_t>& faceMaterial,
                                bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                size_t pieceIndex) {
    const MeshPiece& piece = pieces.pieces()[pieceIndex];
    const std::span<const FaceRun> own = pieces.faceRuns(pieceIndex);
    // Every face of the around runs in order: visit(f, its index in `mesh`, whether it is the
    // piece's own, its first slot, the slots it promises).
    auto forEachAround = [&](auto&& visit) {
        size_t o = 0;
        uint32_t place = 0;
        for (const FaceRun& r : pieces.aroundRuns(pieceIndex)) {
            uint32_t slot = r.firstSlot;
            for (uint32_t f = r.first; f < r.end; ++f, ++place) {
                while (o < own.size() && own[o].end <= f) ++o;
                const bool mine = o < own.size() && f >= own[o].first;
                const uint32_t meshFace = window ? place : f;
                const uint32_t n = faceTriangleBound(mesh, meshFace, faceMaterial, degenerate, f);
                visit(f, meshFace, mine, slot, n);
                slot += n;
            }
        }
    };

    // The points of the piece's kept faces, marked; then every face with a corner at a marked point
    // (the piece's kept faces among them), in face order: the piece's own mesh. Every face around a
    // marked point is in it, so the smoothing groups and sums at those points, and the triangles
    // across the edges of the piece's triangles, are the whole mesh's.
    std::vector<uint32_t> local(mesh.points.size(), kNotLocal);
    constexpr uint32_t kMarked = kNotLocal - 1;
    forEachAround([&](uint32_t, uint32_t mf, bool mine, uint32_t, uint32_t n) {
        if (mine && n > 0)
            for (uint32_t c = mesh.faceVertexBegin(mf); c < mesh.faceVertexEnd(mf); ++c) local[mesh.faceVertices[c]] = kMarked;
    });
    struct SubFace {
        uint32_t face, meshFace, slot;
        uint32_t ownSlots;  // the triangle ids it promises when it is the piece's own, else 0
    };
    std::vector<SubFace> subFaces;
    forEachAround([&](uint32_t f, uint32_t mf, bool mine, uint32_t slot, uint32_t n) {
        bool touches = false;
        for (uint32_t c = mesh.faceVertexBegin(mf); c < mesh.faceVertexEnd(mf) && !touches; ++c)
            touches = local[mesh.faceVertices[c]] == kMarked;
        if (touches) subFaces.push_back({f, mf, slot, mine ? n : 0});
    });
    // Local point ids in ascending order of the source's.
    for (const SubFace& s : subFaces)
        for (uint32_t c = mesh.faceVertexBegin(s.meshFace); c < mesh.faceVertexEnd(s.meshFace); ++c)
            if (local[mesh.faceVertices[c]] == kNotLocal) local[mesh.faceVertices[c]] = kMarked;
    Mesh sub;
    std::vector<uint32_t> sourcePoint;
    for (size_t p = 0; p < local.size(); ++p)
        if (local[p] == kMarked) {
            local[p] = uint32_t(sourcePoint.size());
            sourcePoint.push_back(uint32_t(p));
        }
    sub.points.reserve(sourcePoint.size());
    for (uint32_t p : sourcePoint) sub.points.push_back(mesh.points[p]);
    util::release(sourcePoint);

    const UvSet* uvSet = currentFaceUvSet(mesh);
    std::vector<int32_t> localUv;
    if (uvSet) {
        sub.uvSets.resize(1);
        sub.uvSets[0].name = uvSet->name;
        localUv.assign(uvSet->uvs.size(), -1);
    }
    const bool explicitNormals = mesh.normals.size() == mesh.faceVertexCount();
    std::vector<uint16_t> subMaterial;
    std::vector<bool> subDegenerate;
    subMaterial.reserve(subFaces.size());
    subDegenerate.reserve(subFaces.size());
    sub.loopStarts.clear();
    sub.faceLoopStarts.clear();
    for (const SubFace& s : subFaces) {
        const uint32_t f = s.face;
        sub.faceLoopStarts.push_back(uint32_t(sub.loopStarts.size()));
        for (uint32_t l = mesh.faceLoopStarts[s.meshFace]; l < mesh.faceLoopStarts[s.meshFace + 1]; ++l) {
            sub.loopStarts.push_back(uint32_t(sub.faceVertices.size()));
            for (uint32_t c = mesh.loopStarts[l]; c < mesh.loopStarts[l + 1]; ++c) {
                sub.faceVertices.push_back(local[mesh.faceVertices[c]]);
                if (explicitNormals) sub.normals.push_back(mesh.normals[c]);
                if (uvSet) {
                    const int32_t id = uvSet->faceVertexUvs[c];
                    if (id >= 0 && localUv[size_t(id)] < 0) {
                        localUv[size_t(id)] = int32_t(sub.uvSets[0].uvs.size());
                        sub.uvSets[0].uvs.push_back(uvSet->uvs[size_t(id)]);
                    }
                    sub.uvSets[0].faceVertexUvs.push_back(id >= 0 ? localUv[size_t(id)] : -1);
                }
            }
        }
        subMaterial.push_back(f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0));
        subDegenerate.push_back(f < degenerate.size() && degenerate[f]);
    }
    sub.loopStarts.push_back(uint32_t(sub.faceVertices.size()));
    sub.faceLoopStarts.push_back(uint32_t(sub.loopStarts.size() - 1));
    util::release(localUv);
    // The mesh's edges between points of the piece's mesh, in their order (the last listing of an
    // edge decides its smoothness, as in the whole mesh). Those that matter have an end at a point
    // of the piece's kept faces, so they lie in the piece's edge runs (a window holds only those).
    auto addEdge = [&](const MeshEdge& e) {
        if (e.v0 < local.size() && e.v1 < local.size() && local[e.v0] != kNotLocal && local[e.v1] != kNotLocal)
            sub.edges.push_back({local[e.v0], local[e.v1], e.smooth});
    };
    if (window) {
        for (const MeshEdge& e : mesh.edges) addEdge(e);
    } else {
        for (const EdgeRun& r : pieces.edgeRuns(pieceIndex))
            for (uint32_t k = r.first; k < r.end; ++k) addEdge(mesh.edges[k]);
    }
    util::release(local);

    Tessellation whole = triangulateValidMesh(sub, subMaterial, smoothShading, subDegenerate);
    util::release(sub.faceVertices);
    util::release(sub.normals);
    util::release(sub.edges);
    util::release(sub.uvSets);

    // Triangle ranges per local face (triangles come in face order).
    const size_t subFaceCount = subFaces.size();
    std::vector<uint32_t> firstTriangle(subFaceCount + 1, 0);
    for (uint32_t lf : whole.face) ++firstTriangle[lf + 1];
    for (size_t lf = 0; lf < subFaceCount; ++lf) firstTriangle[lf + 1] += firstTriangle[lf];
    auto slotOf = [&](uint32_t t) {
        const uint32_t lf = whole.face[t];
        return subFaces[lf].slot + (t - firstTriangle[lf]);
    };

    // The piece's triangles in slot order, their vertices renumbered in order of first use, and
    // a zero-area triangle for each slot its face left unused.
    Tessellation out;
    out.corners.reserve(3 * size_t(piece.slotCount));
    out.face.reserve(piece.slotCount);
    out.material.reserve(piece.slotCount);
    out.neighbors.reserve(3 * size_t(piece.slotCount));
    std::vector<uint32_t> vertexOf(whole.positions.size(), kNotLocal);
    auto vertex = [&](uint32_t v) {
        if (vertexOf[v] == kNotLocal) {
            vertexOf[v] = uint32_t(out.positions.size());
            out.positions.push_back(whole.positions[v]);
            out.normals.push_back(whole.normals[v]);
            if (!whole.uvs.empty()) out.uvs.push_back(whole.uvs[v]);
        }
        return vertexOf[v];
    };
    for (size_t lf = 0; lf < subFaceCount; ++lf) {
        const uint32_t promised = subFaces[lf].ownSlots;
        if (promised == 0) continue;
        const uint32_t f = subFaces[lf].face, mf = subFaces[lf].meshFace;
        const uint32_t made = firstTriangle[lf + 1] - firstTriangle[lf];
        for (uint32_t t = firstTriangle[lf]; t < firstTriangle[lf + 1]; ++t) {
            for (int k = 0; k < 3; ++k) {
                out.corners.push_back(vertex(whole.corners[3 * size_t(t) + k]));
                const uint32_t nb = whole.neighbors[3 * size_t(t) + k];
                out.neighbors.push_back(nb == kNoNeighbor ? kNoNeighbor
                                                          : slotOf(nb & ~kHardNeighborBit) | (nb & kHardNeighborBit));
            }
            out.face.push_back(f);
            out.material.push_back(whole.material[t]);
        }
        uint32_t spare = made > 0 ? out.corners.back() : kNotLocal;
        for (uint32_t k = made; k < promised; ++k) {
            // A slot the face left unused: a point-sized triangle at one of the face's corners.
            if (spare == kNotLocal) {
                spare = uint32_t(out.positions.size());
                out.positions.push_back(mesh.points[mesh.faceOuterLoop(mf)[0]]);
                out.normals.push_back(glm::vec3(0.0f, 0.0f, 1.0f));
                if (!whole.uvs.empty()) out.uvs.push_back(glm::vec2(0.0f));
            }
            out.corners.insert(out.corners.end(), {spare, spare, spare});
            out.neighbors.insert(out.neighbors.end(), {kNoNeighbor, kNoNeighbor, kNoNeighbor});
            out.face.push_back(f);
            out.material.push_back(f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0));
        }
    }
    out.positions.shrink_to_fit();
    out.normals.shrink_to_fit();
    out.uvs.shrink_to_fit();
    computeTessellationBounds(out);
    return out;
}

}  // namespace

Tessellation triangulateMeshPiece(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate, const MeshPieces& pieces, size_t piece) {
    return triangulatePieceIn(mesh, false, faceMaterial, smoothShading, degenerate, pieces, piece);
}

Tessellation triangulateMeshPiece(const MeshWindow& source, const std::vector<uint16_t>& faceMaterial,
                                  bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                  size_t piece) {
    return triangulatePieceIn(source.mesh, source.window, faceMaterial, smoothShading, degenerate, pieces, piece);
}

}  // namespace pushpin::geom
