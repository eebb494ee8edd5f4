// Tests for core/geom/poly_dissolve.h.
#include "core/geom/poly_dissolve.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>

namespace pushpin::geom {
namespace {

Mesh plane(int sw, int sh) {
    Mesh m = test::unitPlane(sw, sh);
    completeEdges(m, true);
    return m;
}

std::vector<bool> only(size_t n, size_t i) {
    std::vector<bool> mask(n, false);
    mask[i] = true;
    return mask;
}

int64_t sharedEdge(const Mesh& m) {
    // The edge both faces of a 2×1 plane use.
    for (size_t e = 0; e < m.edges.size(); ++e) {
        int uses = 0;
        for (size_t f = 0; f < m.faceCount(); ++f) {
            const auto lp = m.faceOuterLoop(f);
            for (size_t k = 0; k < lp.size(); ++k) {
                const uint32_t a = lp[k], b = lp[(k + 1) % lp.size()];
                uses += (a == m.edges[e].v0 && b == m.edges[e].v1) || (a == m.edges[e].v1 && b == m.edges[e].v0);
            }
        }
        if (uses == 2) return int64_t(e);
    }
    return -1;
}

TEST(DissolveEdges, TheTwoFacesOfAnEdgeMerge) {
    Mesh m = plane(2, 1);
    const int64_t e = sharedEdge(m);
    ASSERT_GE(e, 0);
    const DissolveResult r = dissolveEdges(m, only(m.edges.size(), size_t(e)));
    EXPECT_EQ(r.dissolvedEdges, 1u);
    ASSERT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.faceOuterLoop(0).size(), 6u);  // the edge's ends stay, on two edges each
    EXPECT_EQ(m.points.size(), 6u);
    EXPECT_EQ(m.edges.size(), 6u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_NEAR(glm::length(m.faceAreaVector(0)), 1.0, 1e-6);
    EXPECT_EQ(m.uvSets[0].faceVertexUvs.size(), 6u);

    // Those two points are now winged: deleting them leaves a quad.
    std::vector<bool> winged(m.points.size(), false);
    std::vector<int> valence(m.points.size(), 0);
    for (const MeshEdge& edge : m.edges) {
        ++valence[edge.v0];
        ++valence[edge.v1];
    }
    const auto loop = m.faceOuterLoop(0);
    for (uint32_t p : loop) {
        const glm::vec3 q = m.points[p];
        winged[p] = std::abs(q.x) < 1e-6f;  // the middle column
    }
    const DissolveResult w = removeWingedPoints(m, winged);
    EXPECT_EQ(w.keptPoints, 0u);
    ASSERT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.faceOuterLoop(0).size(), 4u);
    EXPECT_EQ(m.points.size(), 4u);
    EXPECT_EQ(m.edges.size(), 4u);
    ASSERT_TRUE(m.validate().ok());
}

TEST(DissolveEdges, ACubeEdgeMergesTwoSidesAndTheLowerIndexKeepsThem) {
    PolyCubeParams cp;
    Mesh m = *makePolyCube(cp);
    // e0 is 0-1, shared by the front (f0) and the bottom (f3).
    const DissolveResult r = dissolveEdges(m, only(m.edges.size(), 0));
    EXPECT_EQ(r.dissolvedEdges, 1u);
    ASSERT_EQ(m.faceCount(), 5u);
    EXPECT_EQ(m.faceOuterLoop(0).size(), 6u);
    EXPECT_EQ(m.faceOuterLoop(0)[0], 0u);  // starts where the front face started
    EXPECT_EQ(m.edges.size(), 11u);
    ASSERT_TRUE(m.validate().ok());
}

TEST(DissolveEdges, ABorderEdgeTakesItsFace) {
    Mesh m = plane(2, 1);
    size_t border = 0;
    for (size_t e = 0; e < m.edges.size(); ++e)
        if (int64_t(e) != sharedEdge(m)) {
            border = e;
            break;
        }
    const DissolveResult r = dissolveEdges(m, only(m.edges.size(), border));
    EXPECT_EQ(r.dissolvedEdges, 0u);
    EXPECT_EQ(r.removedFaces, 1u);
    EXPECT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.points.size(), 4u);
}

TEST(RemoveWingedPoints, PointsOnMoreThanTwoEdgesStay) {
    Mesh m = plane(2, 2);
    std::vector<bool> centre(m.points.size(), false);
    centre[4] = true;  // on four edges
    const DissolveResult r = removeWingedPoints(m, centre);
    EXPECT_EQ(r.keptPoints, 1u);
    EXPECT_EQ(m.points.size(), 9u);
    EXPECT_EQ(m.faceCount(), 4u);
}

TEST(CloseBorders, ACubeWithoutItsTopIsClosedAgainFacingOut) {
    PolyCubeParams cp;
    Mesh m = *makePolyCube(cp);
    std::vector<bool> top(m.faceCount(), false);
    top[1] = true;
    deleteFaces(m, top);
    ASSERT_EQ(m.faceCount(), 5u);
    completeEdges(m, true);
    const size_t added = closeBorders(m, std::vector<bool>(m.edges.size(), true));
    EXPECT_EQ(added, 1u);
    ASSERT_EQ(m.faceCount(), 6u);
    EXPECT_EQ(m.faceOuterLoop(5).size(), 4u);
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-6);  // closed and outward-facing
    EXPECT_GT(m.faceNormal(5).y, 0.99);
    // Nothing left to close.
    EXPECT_EQ(closeBorders(m, std::vector<bool>(m.edges.size(), true)), 0u);
    // Only some of a border's edges selected: the loop stays open.
    Mesh open = *makePolyCube(cp);
    deleteFaces(open, top);
    completeEdges(open, true);
    std::vector<bool> some(open.edges.size(), false);
    for (size_t e = 0; e < open.edges.size() && e < 2; ++e) some[e] = true;
    EXPECT_EQ(closeBorders(open, some), 0u);
}

}  // namespace
}  // namespace pushpin::geom
