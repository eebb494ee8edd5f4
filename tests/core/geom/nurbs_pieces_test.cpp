// Tests for core/geom/nurbs_pieces: the grid of a NURBS surface, rectangles of its cells made on
// their own, and surfaces cut into pieces.
#include "core/geom/geometry_handle.h"
#include "core/geom/nurbs_pieces.h"
#include "core/geom/nurbs_primitives.h"

#include <gtest/gtest.h>

#include <bit>
#include <memory>
#include <string>
#include <vector>

namespace pushpin::geom {
namespace {

struct NamedSurface {
    std::string name;
    NurbsSurface surface;
    int divU, divV;
};

// A sphere (two poles and a seam), a torus (two seams), an open plane, a cone (one apex, one seam)
// and an exact rational sphere.
std::vector<NamedSurface> surfaces() {
    std::string error;
    std::vector<NamedSurface> out;
    NurbsSphereParams sphere;
    sphere.sections = 8;
    sphere.spans = 4;
    out.push_back({"sphere", *makeNurbSphere(sphere, &error), 3, 4});
    NurbsTorusParams torus;
    out.push_back({"torus", *makeNurbTorus(torus, &error), 2, 3});
    NurbsPlaneParams plane;
    plane.patchesU = 5;
    plane.patchesV = 3;
    out.push_back({"plane", *makeNurbPlane(plane, &error), 4, 3});
    NurbsConeParams cone;
    cone.sections = 6;
    cone.spans = 3;
    out.push_back({"cone", *makeNurbCone(cone, &error), 3, 3});
    out.push_back({"rational sphere", *makeRationalSphere(sphere, &error), 3, 3});
    return out;
}

bool same(const glm::vec3& a, const glm::vec3& b) { return std::bit_cast<glm::uvec3>(a) == std::bit_cast<glm::uvec3>(b); }
bool same(const glm::vec2& a, const glm::vec2& b) { return std::bit_cast<glm::uvec2>(a) == std::bit_cast<glm::uvec2>(b); }

TEST(NurbsGrid, HasTwoTrianglesACellAndWeldsPolesAndSeams) {
    NurbsSphereParams p;
    p.sections = 8;
    p.spans = 4;
    const NurbsSurface s = *makeNurbSphere(p, nullptr);
    std::string problem;
    const std::optional<NurbsGrid> g = makeNurbsGrid(s, 3, 2, problem);
    ASSERT_TRUE(g) << problem;
    EXPECT_EQ(g->cellCount() * 2, nurbsTriangleCount(s, 3, 2));
    const std::optional<Tessellation> t = tessellateNurbs(s, 3, 2, problem);
    ASSERT_TRUE(t) << problem;
    ASSERT_EQ(t->triangleCount(), nurbsTriangleCount(s, 3, 2));
    // The poles' triangles keep their ids with their corners on one vertex; every other triangle
    // of the closed sphere has a neighbour across each edge.
    size_t poles = 0;
    for (size_t i = 0; i < t->triangleCount(); ++i) {
        const uint32_t* c = &t->corners[3 * i];
        if (c[0] == c[1] && c[1] == c[2]) {
            ++poles;
            for (int k = 0; k < 3; ++k) EXPECT_EQ(t->neighbors[3 * i + size_t(k)], kNoNeighbor);
            continue;
        }
        for (int k = 0; k < 3; ++k) EXPECT_NE(t->neighbors[3 * i + size_t(k)], kNoNeighbor) << "triangle " << i;
    }
    EXPECT_GT(poles, 0u);
    EXPECT_LE(poles, size_t(2 * 8 * 3));
    EXPECT_FALSE(g->welds.empty());
    for (const auto& [point, root] : g->welds) EXPECT_LT(root, point);
}

TEST(NurbsGrid, ASurfaceCollapsedToAPointGivesZeroAreaTrianglesFacingZ) {
    // Every CV at one point: no normal anywhere to borrow, no area anywhere. A 200 × 200 grid
    // finishes, each point looking a few rings around itself only.
    std::string error;
    const std::optional<NurbsSurface> s = NurbsSurface::create(1, 1, NurbsForm::Open, NurbsForm::Open, {0, 0, 1, 1},
                                                               {0, 0, 1, 1}, 2, 2, std::vector<glm::dvec4>(4, {1, 2, 3, 1}),
                                                               false, &error);
    ASSERT_TRUE(s) << error;
    std::string problem;
    const std::optional<Tessellation> t = tessellateNurbs(*s, 200, 200, problem);
    ASSERT_TRUE(t) << problem;
    ASSERT_EQ(t->triangleCount(), 2u * 200u * 200u);
    for (size_t i = 0; i < t->triangleCount(); ++i) {
        EXPECT_EQ(t->corners[3 * i], t->corners[3 * i + 1]);
        EXPECT_EQ(t->corners[3 * i], t->corners[3 * i + 2]);
    }
    for (uint32_t n : t->neighbors) EXPECT_EQ(n, kNoNeighbor);
    for (const glm::vec3& n : t->normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST(NurbsPieces, EveryPieceIsTheWholeGridCutToItsCells) {
    for (const NamedSurface& n : surfaces()) {
        SCOPED_TRACE(n.name);
        std::string problem;
        const std::optional<NurbsGrid> g = makeNurbsGrid(n.surface, n.divU, n.divV, problem);
        ASSERT_TRUE(g) << problem;
        const std::optional<Tessellation> whole = tessellateNurbs(n.surface, n.divU, n.divV, problem);
        ASSERT_TRUE(whole) << problem;
        for (uint32_t size : {2u, 16u, 50u, 256u}) {
            SCOPED_TRACE("pieces of " + std::to_string(size));
            const NurbsPieces pieces = NurbsPieces::split(n.surface, *g, size);
            std::vector<int> seen(whole->triangleCount(), 0);
            for (size_t k = 0; k < pieces.pieces().size(); ++k) {
                const NurbsPieces::Piece& piece = pieces.pieces()[k];
                EXPECT_LE(2 * piece.cells.count(), std::max<uint64_t>(size, 2));
                const std::optional<Tessellation> t = tessellateNurbsCells(n.surface, *g, piece.cells, problem);
                ASSERT_TRUE(t) << problem;
                ASSERT_EQ(t->triangleCount(), 2 * piece.cells.count());
                const std::span<const SlotRun> runs = pieces.pieceSlotRuns(k);
                size_t run = 0;
                for (uint32_t local = 0; local < t->triangleCount(); ++local) {
                    while (run + 1 < runs.size() && runs[run + 1].local <= local) ++run;
                    const uint32_t slot = runs[run].firstSlot + (local - runs[run].local);
                    ASSERT_LT(slot, whole->triangleCount());
                    ++seen[slot];
                    EXPECT_EQ(t->face[local], whole->face[slot]);
                    EXPECT_EQ(t->material[local], whole->material[slot]);
                    for (int c = 0; c < 3; ++c) {
                        const size_t a = 3 * size_t(local) + size_t(c), b = 3 * size_t(slot) + size_t(c);
                        EXPECT_TRUE(same(t->position(a), whole->position(b))) << "slot " << slot;
                        EXPECT_TRUE(same(t->normal(a), whole->normal(b))) << "slot " << slot;
                        EXPECT_TRUE(same(t->uv(a), whole->uv(b))) << "slot " << slot;
                        EXPECT_EQ(t->neighbors[a], whole->neighbors[b]) << "slot " << slot << " edge " << c;
                        // The cells lie inside the hull of the control points that shape them.
                        const glm::dvec3 p(t->position(a));
                        for (int d = 0; d < 3; ++d) {
                            const double slack = 1e-6 * (1.0 + std::abs(p[d]));
                            EXPECT_GE(p[d], piece.bounds.lo[d] - slack);
                            EXPECT_LE(p[d], piece.bounds.hi[d] + slack);
                        }
                    }
                }
            }
            for (size_t slot = 0; slot < seen.size(); ++slot) EXPECT_EQ(seen[slot], 1) << "slot " << slot;
            // slotRuns() finds every slot's piece and place.
            const std::vector<SlotRun>& all = pieces.slotRuns();
            for (size_t i = 1; i < all.size(); ++i) EXPECT_LT(all[i - 1].firstSlot, all[i].firstSlot);
        }
    }
}

TEST(NurbsPieces, AHandleInPiecesCountsAndPlacesEveryTriangle) {
    NurbsSphereParams p;
    p.sections = 8;
    p.spans = 4;
    const auto surface = std::make_shared<const NurbsSurface>(*makeNurbSphere(p, nullptr));
    const auto whole = GeometryHandle::fromNurbs(surface, 10, 10);
    ASSERT_EQ(whole->pieceCount(), 1u);
    const auto h = GeometryHandle::fromNurbs(surface, 10, 10, 400);
    EXPECT_EQ(h->triangleCount(), whole->triangleCount());
    ASSERT_GE(h->pieceCount(), h->triangleCount() / 400);
    EXPECT_GT(h->sourceBytes(), whole->sourceBytes());
    uint64_t total = 0;
    for (size_t k = 0; k < h->pieceCount(); ++k) {
        total += h->pieceTriangleCount(k);
        const Tessellation t = h->tessellatePiece(k);
        ASSERT_EQ(t.triangleCount(), h->pieceTriangleCount(k));
        // The estimates are within a factor of two of what the piece holds.
        EXPECT_GT(h->pieceBytesEstimate(k), t.bytes() / 2);
        EXPECT_LT(h->pieceBytesEstimate(k), t.bytes() * 2);
        EXPECT_LT(h->pieceWorkBytesEstimate(k), whole->tessellationWorkBytesEstimate());
        const std::span<const SlotRun> runs = h->pieceSlotRuns(k);
        for (const SlotRun& r : runs) {
            const GeometryHandle::PiecePlace place = h->placeOf(r.firstSlot);
            EXPECT_EQ(place.piece, k);
            EXPECT_EQ(place.local, r.local);
        }
    }
    EXPECT_EQ(total, h->triangleCount());
    // withPieces re-cuts a surface too.
    EXPECT_EQ(h->withPieces(0)->pieceCount(), 1u);
    EXPECT_EQ(whole->withPieces(400)->pieceCount(), h->pieceCount());
}

}  // namespace
}  // namespace pushpin::geom
