// Tests for core/geom/mesh_pieces.h: a mesh tessellated piece by piece gives the whole
// tessellation's triangles, corner values and neighbours bit for bit, under the whole shape's
// triangle ids, whatever the piece size.
#include "core/geom/geometry_handle.h"
#include "core/geom/mesh_pieces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <random>
#include <vector>

namespace pushpin::geom {
namespace {

bool sameBits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(const glm::vec2& a, const glm::vec2& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Case {
    Mesh mesh;
    std::vector<uint16_t> material;
    std::vector<bool> degenerate;
};

// A bumpy grid of W × H quads in row order with everything that changes a triangle's neighbours
// or corner values: random hard edges (one edge listed twice, the second listing deciding), three
// materials and faces in none, faces dropped as degenerate, a uv seam in the current (second)
// uv set, corners with stored normals, a pentagon with a point on an edge, one with a point given
// twice in a row (ear clipping makes two triangles of the three it promises), a face with a hole,
// and a fin sharing a grid edge (an edge of three faces).
Case bumpyGrid(int W, int H, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    Case c;
    Mesh& m = c.mesh;
    auto height = [](double i, double j) { return 0.05 * i * j + 0.3 * std::sin(0.7 * i) * std::cos(0.4 * j); };
    auto pointAt = [&](int i, int j) { return uint32_t(j * (W + 1) + i); };
    for (int j = 0; j <= H; ++j)
        for (int i = 0; i <= W; ++i) m.points.push_back(glm::vec3(float(i), float(height(i, j)), float(j)));
    const int pentI = W / 3, pentJ = H / 2, holeI = 2 * W / 3, holeJ = H / 3, finI = W / 2, finJ = 2 * H / 3;
    std::vector<int32_t> uvIds;
    uint32_t finA = 0, finB = 0;
    for (int j = 0; j < H; ++j) {
        for (int i = 0; i < W; ++i) {
            const uint32_t a = pointAt(i, j), b = pointAt(i, j + 1), cc = pointAt(i + 1, j + 1), d = pointAt(i + 1, j);
            if (i == pentI && j == pentJ) {
                // A point halfway along the edge a–b, on the straight line between them.
                const glm::vec3 pa = m.points[a], pb = m.points[b];
                const uint32_t mid = uint32_t(m.points.size());
                m.points.push_back(glm::vec3(pa.x, 0.5f * (pa.y + pb.y), 0.5f * (pa.z + pb.z)));
                m.addFace({a, mid, b, cc, d});
            } else if (i == pentI + 1 && j == pentJ) {
                m.addFace({a, b, b, cc, d});  // a point given twice in a row
            } else if (i == holeI && j == holeJ) {
                m.addFace({a, b, cc, d});
                const uint32_t h0 = uint32_t(m.points.size());
                const glm::vec3 o = m.points[a];
                for (const auto& [du, dv] : {std::pair{0.3f, 0.3f}, {0.7f, 0.3f}, {0.7f, 0.7f}, {0.3f, 0.7f}})
                    m.points.push_back(glm::vec3(o.x + du, o.y, o.z + dv));
                const uint32_t hole[4] = {h0, h0 + 1, h0 + 2, h0 + 3};
                m.addHole(hole);
            } else {
                m.addFace({a, b, cc, d});
            }
            if (i == finI && j == finJ) {
                finA = a;
                finB = b;
            }
        }
    }
    // The fin: a triangle standing on the grid edge finA–finB.
    const uint32_t top = uint32_t(m.points.size());
    m.points.push_back(m.points[finA] + glm::vec3(0.0f, 1.0f, 0.5f));
    m.addFace({finA, finB, top});

    m.edges = deriveEdges(m, true);
    for (MeshEdge& e : m.edges) e.smooth = uni(rng) > 0.3;
    MeshEdge again = m.edges[m.edges.size() / 2];
    again.smooth = !again.smooth;
    m.edges.push_back(again);

    const size_t faces = m.faceCount();
    for (size_t f = 0; f < faces; ++f) {
        const double r = uni(rng);
        c.material.push_back(r < 0.08 ? kNoFaceMaterial : uint16_t(r < 0.5 ? 0 : r < 0.8 ? 1 : 2));
        c.degenerate.push_back(uni(rng) < 0.04);
    }
    // Keep the special faces.
    for (size_t f = 0; f < faces; ++f)
        if (m.faceVertexEnd(f) - m.faceVertexBegin(f) != 4 || m.holeCount(f) > 0) {
            c.material[f] = 1;
            c.degenerate[f] = false;
        }

    // Uv sets: the first unused, the second current with a seam down column W/2.
    UvSet unused{"unused", {glm::vec2(0.5f)}, std::vector<int32_t>(m.faceVertexCount(), 0)};
    UvSet current{"map2", {}, {}};
    const uint32_t gridPoints = uint32_t((W + 1) * (H + 1));
    for (const glm::vec3& p : m.points) current.uvs.push_back(glm::vec2(p.x / float(W), p.z / float(H)));
    for (uint32_t p = 0; p < gridPoints; ++p) current.uvs.push_back(glm::vec2(m.points[p].x / float(W) + 0.5f, 0.1f));
    for (size_t f = 0; f < faces; ++f)
        for (uint32_t k = m.faceVertexBegin(f); k < m.faceVertexEnd(f); ++k) {
            const uint32_t p = m.faceVertices[k];
            const bool right = m.points[m.faceVertices[m.faceVertexBegin(f)]].x >= float(W / 2);
            current.faceVertexUvs.push_back(right && p < gridPoints ? int32_t(m.points.size() + p) : int32_t(p));
        }
    m.uvSets = {unused, current};
    m.currentUvSet = 1;
    m.normals.assign(m.faceVertexCount(), glm::vec3(0.0f));
    for (size_t k = 0; k < m.normals.size(); k += 37) m.normals[k] = glm::vec3(0.0f, 1.0f, 0.0f);
    EXPECT_TRUE(m.validate().ok());
    return c;
}

// The first triangle id of every face (and the total after the last).
std::vector<uint32_t> faceSlots(const Case& c) {
    std::vector<uint32_t> slots(c.mesh.faceCount() + 1, 0);
    for (size_t f = 0; f < c.mesh.faceCount(); ++f)
        slots[f + 1] = slots[f] + faceTriangleBound(c.mesh, c.material, c.degenerate, f);
    return slots;
}

// Checks the tables of `pieces` split from `c` at `maxSlots`: every kept face in the own runs of
// exactly one piece, each piece's triangle ids counted, placed by slotRuns, and no more than
// maxSlots unless it is a single face; every face around a piece's points in its around runs.
void expectPieceTables(const Case& c, const MeshPieces& pieces, uint32_t maxSlots) {
    const Mesh& m = c.mesh;
    const std::vector<uint32_t> slot = faceSlots(c);
    auto bound = [&](size_t f) { return faceTriangleBound(m, c.material, c.degenerate, f); };
    EXPECT_EQ(pieces.slotCount(), slot.back());
    std::vector<int> owner(m.faceCount(), -1);
    for (size_t k = 0; k < pieces.pieces().size(); ++k) {
        const MeshPiece& p = pieces.pieces()[k];
        uint32_t slots = 0, keptFaces = 0;
        const std::span<const FaceRun> runs = pieces.faceRuns(k);
        const std::span<const SlotRun> places = pieces.pieceSlotRuns(k);
        ASSERT_EQ(runs.size(), places.size());
        ASSERT_FALSE(runs.empty());
        for (size_t r = 0; r < runs.size(); ++r) {
            EXPECT_LT(runs[r].first, runs[r].end);
            if (r > 0) {
                EXPECT_LT(runs[r - 1].end, runs[r].first);
            }
            EXPECT_GT(bound(runs[r].first), 0u);
            EXPECT_GT(bound(runs[r].end - 1), 0u);
            EXPECT_EQ(runs[r].firstSlot, slot[runs[r].first]);
            EXPECT_EQ(runs[r].firstFaceVertex, m.faceVertexBegin(runs[r].first));
            EXPECT_EQ(places[r].firstSlot, runs[r].firstSlot);
            EXPECT_EQ(places[r].piece, k);
            EXPECT_EQ(places[r].local, slots);
            for (uint32_t f = runs[r].first; f < runs[r].end; ++f) {
                if (bound(f) == 0) continue;
                EXPECT_EQ(owner[f], -1) << "face " << f;
                owner[f] = int(k);
                slots += bound(f);
                ++keptFaces;
            }
        }
        EXPECT_EQ(slots, p.slotCount);
        EXPECT_TRUE(p.slotCount <= maxSlots || keptFaces == 1);
        // Every face with a corner at a point of the piece's kept faces is in its around runs.
        std::vector<bool> mine(m.points.size(), false), around(m.faceCount(), false);
        for (uint32_t f = 0; f < m.faceCount(); ++f)
            if (owner[f] == int(k))
                for (uint32_t i = m.faceVertexBegin(f); i < m.faceVertexEnd(f); ++i) mine[m.faceVertices[i]] = true;
        for (const FaceRun& r : pieces.aroundRuns(k)) {
            EXPECT_EQ(r.firstSlot, slot[r.first]);
            EXPECT_EQ(r.firstFaceVertex, m.faceVertexBegin(r.first));
            for (uint32_t f = r.first; f < r.end; ++f) around[f] = true;
        }
        for (uint32_t f = 0; f < m.faceCount(); ++f)
            for (uint32_t i = m.faceVertexBegin(f); i < m.faceVertexEnd(f); ++i)
                if (mine[m.faceVertices[i]]) {
                    EXPECT_TRUE(around[f]) << "piece " << k << " face " << f;
                }
    }
    for (size_t f = 0; f < m.faceCount(); ++f) EXPECT_EQ(owner[f] >= 0, bound(f) > 0) << "face " << f;
    // The id runs cover every id once, in order.
    const std::vector<SlotRun>& runs = pieces.slotRuns();
    ASSERT_FALSE(runs.empty());
    EXPECT_EQ(runs.front().firstSlot, 0u);
    for (size_t r = 1; r < runs.size(); ++r) EXPECT_LT(runs[r - 1].firstSlot, runs[r].firstSlot);
    for (uint32_t f = 0; f < m.faceCount(); ++f) {
        if (bound(f) == 0) continue;
        const SlotRun* run = findSlotRun(runs.data(), runs.size(), slot[f]);
        ASSERT_NE(run, nullptr);
        EXPECT_EQ(int(run->piece), owner[f]) << "face " << f;
    }
}

// Checks that the pieces of `c` at `maxSlots` give `whole`'s triangles under their slots.
void expectPiecesMatchWhole(const Case& c, bool smooth, uint32_t maxSlots,
                            MeshPieces::Layout layout = MeshPieces::Layout::Spatial) {
    SCOPED_TRACE("maxSlots " + std::to_string(maxSlots) + (smooth ? " smooth" : " faceted") +
                 (layout == MeshPieces::Layout::Spatial ? " spatial" : " face order"));
    const Mesh& m = c.mesh;
    const Tessellation whole = triangulateValidMesh(m, c.material, smooth, c.degenerate);
    const MeshPieces pieces = MeshPieces::split(m, c.material, c.degenerate, maxSlots, layout);
    ASSERT_FALSE(pieces.pieces().empty());
    expectPieceTables(c, pieces, maxSlots);

    std::vector<Tessellation> made;
    for (size_t k = 0; k < pieces.pieces().size(); ++k) {
        made.push_back(triangulateMeshPiece(m, c.material, smooth, c.degenerate, pieces, k));
        const MeshPiece& p = pieces.pieces()[k];
        // Made from its window alone, the piece is the same bit for bit.
        const MeshWindow window = cutMeshWindow(m, pieces, k);
        EXPECT_EQ(window.mesh.faceCount(), p.windowFaces);
        EXPECT_EQ(window.mesh.faceVertexCount(), p.windowFaceVertices);
        EXPECT_EQ(window.mesh.points.size(), p.windowPoints);
        EXPECT_EQ(window.mesh.edges.size(), p.windowEdges);
        if (pieces.mapsUvs()) {
            EXPECT_EQ(window.mesh.uvSets.at(0).uvs.size(), p.windowUvs);
        }
        const Tessellation alone = triangulateMeshPiece(window, c.material, smooth, c.degenerate, pieces, k);
        const Tessellation& t = made.back();
        EXPECT_EQ(alone.corners, t.corners) << "piece " << k;
        EXPECT_EQ(alone.neighbors, t.neighbors) << "piece " << k;
        EXPECT_EQ(alone.face, t.face) << "piece " << k;
        EXPECT_EQ(alone.material, t.material) << "piece " << k;
        ASSERT_EQ(alone.positions.size(), t.positions.size());
        ASSERT_EQ(alone.uvs.size(), t.uvs.size());
        for (size_t v = 0; v < t.positions.size(); ++v) {
            EXPECT_TRUE(sameBits(alone.positions[v], t.positions[v])) << "piece " << k << " vertex " << v;
            EXPECT_TRUE(sameBits(alone.normals[v], t.normals[v])) << "piece " << k << " vertex " << v;
            if (!t.uvs.empty()) {
                EXPECT_TRUE(sameBits(alone.uvs[v], t.uvs[v])) << "piece " << k << " vertex " << v;
            }
        }
        ASSERT_EQ(made.back().triangleCount(), p.slotCount);
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(made.back().bounds.lo[a], p.bounds.lo[a]);
            EXPECT_LE(made.back().bounds.hi[a], p.bounds.hi[a]);
        }
    }
    const std::vector<SlotRun>& runs = pieces.slotRuns();
    auto find = [&](uint32_t slot) -> std::pair<const Tessellation*, uint32_t> {
        const SlotRun* r = findSlotRun(runs.data(), runs.size(), slot);
        if (!r || slot >= pieces.slotCount()) return {nullptr, 0};
        return {&made[r->piece], r->local + (slot - r->firstSlot)};
    };
    // The slot of each whole triangle: its face's first slot plus its place within the face.
    const std::vector<uint32_t> faceSlot = faceSlots(c);
    std::vector<uint32_t> slotOf(whole.triangleCount());
    for (size_t t = 0; t < whole.triangleCount(); ++t) {
        const uint32_t f = whole.face[t];
        slotOf[t] = t > 0 && whole.face[t - 1] == f ? slotOf[t - 1] + 1 : faceSlot[f];
    }
    std::vector<uint8_t> used(pieces.slotCount(), 0);
    for (size_t t = 0; t < whole.triangleCount(); ++t) {
        const auto [g, i] = find(slotOf[t]);
        ASSERT_NE(g, nullptr);
        used[slotOf[t]] = 1;
        EXPECT_EQ(g->face[i], whole.face[t]);
        EXPECT_EQ(g->material[i], whole.material[t]);
        for (int k = 0; k < 3; ++k) {
            const size_t wc = 3 * t + size_t(k), pc = 3 * size_t(i) + size_t(k);
            EXPECT_TRUE(sameBits(g->position(pc), whole.position(wc))) << "triangle " << t;
            EXPECT_TRUE(sameBits(g->normal(pc), whole.normal(wc))) << "triangle " << t;
            EXPECT_TRUE(sameBits(g->uv(pc), whole.uv(wc))) << "triangle " << t;
            const uint32_t nb = whole.neighbors[wc];
            const uint32_t want =
                nb == kNoNeighbor ? kNoNeighbor : slotOf[nb & ~kHardNeighborBit] | (nb & kHardNeighborBit);
            EXPECT_EQ(g->neighbors[pc], want) << "triangle " << t << " edge " << k;
        }
    }
    // Slots no whole triangle took: point-sized, without neighbours.
    size_t spare = 0;
    for (uint32_t s = 0; s < pieces.slotCount(); ++s) {
        if (used[s]) continue;
        ++spare;
        const auto [g, i] = find(s);
        ASSERT_NE(g, nullptr);
        EXPECT_EQ(g->corners[3 * i], g->corners[3 * i + 1]);
        EXPECT_EQ(g->corners[3 * i], g->corners[3 * i + 2]);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(g->neighbors[3 * i + k], kNoNeighbor);
    }
    EXPECT_EQ(spare, pieces.slotCount() - whole.triangleCount());
}

// The same mesh with its faces in another order (`order[k]` is the old index of new face k).
Case reorderFaces(const Case& c, const std::vector<uint32_t>& order) {
    Case out;
    Mesh& m = out.mesh;
    m.points = c.mesh.points;
    m.edges = c.mesh.edges;
    m.loopStarts.clear();
    m.faceLoopStarts.clear();
    for (const UvSet& s : c.mesh.uvSets) m.uvSets.push_back(UvSet{s.name, s.uvs, {}});
    m.currentUvSet = c.mesh.currentUvSet;
    for (uint32_t f : order) {
        m.faceLoopStarts.push_back(uint32_t(m.loopStarts.size()));
        for (uint32_t l = c.mesh.faceLoopStarts[f]; l < c.mesh.faceLoopStarts[f + 1]; ++l) {
            m.loopStarts.push_back(uint32_t(m.faceVertices.size()));
            for (uint32_t i = c.mesh.loopStarts[l]; i < c.mesh.loopStarts[l + 1]; ++i) {
                m.faceVertices.push_back(c.mesh.faceVertices[i]);
                if (!c.mesh.normals.empty()) m.normals.push_back(c.mesh.normals[i]);
                for (size_t s = 0; s < m.uvSets.size(); ++s)
                    m.uvSets[s].faceVertexUvs.push_back(c.mesh.uvSets[s].faceVertexUvs[i]);
            }
        }
        out.material.push_back(c.material[f]);
        out.degenerate.push_back(c.degenerate[f]);
    }
    m.loopStarts.push_back(uint32_t(m.faceVertices.size()));
    m.faceLoopStarts.push_back(uint32_t(m.loopStarts.size() - 1));
    EXPECT_TRUE(m.validate().ok());
    return out;
}

TEST(MeshPieces, PiecesGiveTheWholeTessellationUnderItsTriangleIds) {
    const Case c = bumpyGrid(23, 17, 5);
    // The pentagon with a point given twice promises three triangles and makes two.
    const Tessellation whole = triangulateValidMesh(c.mesh, c.material, true, c.degenerate);
    ASSERT_GE(meshTriangleCount(c.mesh, c.material, c.degenerate), whole.triangleCount() + 1);
    size_t hard = 0, none = 0;
    for (uint32_t nb : whole.neighbors) {
        hard += nb != kNoNeighbor && (nb & kHardNeighborBit);
        none += nb == kNoNeighbor;
    }
    EXPECT_GT(hard, 100u);
    EXPECT_GT(none, 50u);
    for (uint32_t maxSlots : {1u, 2u, 7u, 40u, 333u, 100000u})
        for (bool smooth : {true, false}) {
            expectPiecesMatchWhole(c, smooth, maxSlots);
            expectPiecesMatchWhole(c, smooth, maxSlots, MeshPieces::Layout::FaceOrder);
        }
    EXPECT_TRUE(MeshPieces::split(c.mesh, c.material, c.degenerate, 40).spatial());
    EXPECT_FALSE(MeshPieces::split(c.mesh, c.material, c.degenerate, 40, MeshPieces::Layout::FaceOrder).spatial());
}

TEST(MeshPieces, ASplitKeepsWholeFacesAndLeavesOutFacesWithoutTriangles) {
    Case c = bumpyGrid(6, 5, 9);
    // Faces 0..9 not rendered: they belong to no piece, and every piece has triangles.
    for (size_t f = 0; f < 10; ++f) c.material[f] = kNoFaceMaterial;
    for (const MeshPieces::Layout layout : {MeshPieces::Layout::Spatial, MeshPieces::Layout::FaceOrder}) {
        const MeshPieces pieces = MeshPieces::split(c.mesh, c.material, c.degenerate, 6, layout);
        ASSERT_FALSE(pieces.pieces().empty());
        expectPieceTables(c, pieces, 6);
        for (size_t k = 0; k < pieces.pieces().size(); ++k) {
            EXPECT_GT(pieces.pieces()[k].slotCount, 0u);
            for (const FaceRun& r : pieces.faceRuns(k)) EXPECT_GE(r.first, 10u);
        }
        expectPiecesMatchWhole(c, true, 6, layout);
    }
}

TEST(MeshPieces, PiecesOfAGridStoredRowByRowAreCompact) {
    // 200 × 100 quads in pieces of 4000 triangle ids: along the Morton curve each piece is a patch
    // of about 45 × 45 quads, a few dozen runs of faces; in face order each is a band of ten rows
    // across the whole grid. (The grid's heights, up to 1000, are scaled down so that it lies nearly
    // flat: pieces are compact in space, and a steep surface would make them so along it.)
    Case c = bumpyGrid(200, 100, 3);
    for (glm::vec3& p : c.mesh.points) p.y *= 0.001f;
    const MeshPieces spatial = MeshPieces::split(c.mesh, c.material, c.degenerate, 4000);
    const MeshPieces bands = MeshPieces::split(c.mesh, c.material, c.degenerate, 4000, MeshPieces::Layout::FaceOrder);
    ASSERT_TRUE(spatial.spatial());
    ASSERT_GE(spatial.pieces().size(), 9u);
    double spatialWidth = 0.0, bandWidth = 0.0;
    size_t runs = 0;
    for (size_t k = 0; k < spatial.pieces().size(); ++k) {
        const Bounds3& b = spatial.pieces()[k].bounds;
        spatialWidth = std::max(spatialWidth, b.hi.x - b.lo.x);
        EXPECT_LE(b.hi.z - b.lo.z, 70.0) << "piece " << k;
        runs += spatial.faceRuns(k).size();
    }
    for (const MeshPiece& p : bands.pieces()) bandWidth = std::min(bandWidth == 0.0 ? 1e9 : bandWidth, p.bounds.hi.x - p.bounds.lo.x);
    EXPECT_LE(spatialWidth, 70.0);
    EXPECT_GE(bandWidth, 199.0);
    EXPECT_LE(runs, 60 * spatial.pieces().size());
    expectPieceTables(c, spatial, 4000);
}

TEST(MeshPieces, FacesInNoSpatialOrderAreCutInFaceOrder) {
    // The same grid with its faces shuffled: along the Morton curve every face would be a run of its
    // own, so the split falls back to face order, and the runs around each piece stay bounded.
    const Case grid = bumpyGrid(60, 40, 11);
    std::vector<uint32_t> order(grid.mesh.faceCount());
    for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
    std::shuffle(order.begin(), order.end(), std::mt19937(4));
    const Case c = reorderFaces(grid, order);
    const MeshPieces pieces = MeshPieces::split(c.mesh, c.material, c.degenerate, 500);
    EXPECT_FALSE(pieces.spatial());
    for (size_t k = 0; k < pieces.pieces().size(); ++k) {
        EXPECT_EQ(pieces.faceRuns(k).size(), 1u);
        EXPECT_LE(pieces.aroundRuns(k).size(), 1024u);
    }
    expectPiecesMatchWhole(c, true, 500);
}

TEST(MeshPieces, APieceNeedsOnlyTheFacesAroundIt) {
    // A 200 × 100 grid in pieces of 4000 triangle ids: each piece makes only the vertices of its
    // own triangles.
    const Case c = bumpyGrid(200, 100, 3);
    const MeshPieces pieces = MeshPieces::split(c.mesh, c.material, c.degenerate, 4000);
    ASSERT_GE(pieces.pieces().size(), 9u);
    const Tessellation whole = triangulateValidMesh(c.mesh, c.material, true, c.degenerate);
    size_t vertices = 0;
    for (size_t k = 0; k < pieces.pieces().size(); ++k) {
        const Tessellation t = triangulateMeshPiece(c.mesh, c.material, true, c.degenerate, pieces, k);
        EXPECT_LE(t.vertexCount(), 3 * t.triangleCount());
        vertices += t.vertexCount();
    }
    // A piece's window holds the faces around it, not the grid: over all pieces a little more than
    // the grid (the odd faces at the end, which touch points of every row, widen some windows).
    size_t windowFaces = 0, windowPoints = 0, windowEdges = 0;
    for (size_t k = 0; k < pieces.pieces().size(); ++k) {
        const MeshWindow window = cutMeshWindow(c.mesh, pieces, k);
        windowFaces += window.mesh.faceCount();
        windowPoints += window.mesh.points.size();
        windowEdges += window.mesh.edges.size();
    }
    EXPECT_LT(windowFaces, 2 * c.mesh.faceCount());
    EXPECT_LT(windowPoints, 2 * c.mesh.points.size());
    EXPECT_LT(windowEdges, 2 * c.mesh.edges.size());
    // Vertices on the piece borders are made on both sides: under a tenth more than the whole.
    EXPECT_GE(vertices, whole.vertexCount());
    EXPECT_LT(double(vertices), 1.1 * double(whole.vertexCount()));
}

TEST(MeshPieces, PiecesAreSmallerUnderASmallerCap) {
    constexpr uint64_t MB = uint64_t(1) << 20;
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(0), GeometryHandle::kPieceTriangles);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(64 * 1024 * MB), GeometryHandle::kPieceTriangles);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(4096 * MB), 1u << 18);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(2048 * MB), 1u << 17);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(1024 * MB), 1u << 16);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(512 * MB), 1u << 15);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(256 * MB), 1u << 14);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(1 * MB), 1u << 14);
    EXPECT_EQ(GeometryHandle::pieceTrianglesFor(1), 1u << 14);
    // Making a piece takes at most a sixty-fourth of any cap that is not below the smallest piece's.
    for (uint64_t cap = 256 * MB; cap <= 8192 * MB; cap += 37 * MB) {
        const uint32_t n = GeometryHandle::pieceTrianglesFor(cap);
        EXPECT_TRUE(std::has_single_bit(n)) << cap;
        EXPECT_LE(uint64_t(n) * GeometryHandle::kPieceMakingBytes, cap / 64) << cap;
        if (n < GeometryHandle::kPieceTriangles) {
            EXPECT_GT(uint64_t(2 * n) * GeometryHandle::kPieceMakingBytes, cap / 64) << cap;
        }
    }
}

}  // namespace
}  // namespace pushpin::geom
