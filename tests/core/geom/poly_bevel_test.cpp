// Tests for core/geom/poly_bevel.h: chamfered cubes and planes against closed forms.
#include "core/geom/poly_bevel.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <map>

namespace pushpin::geom {
namespace {

std::vector<bool> all(const Mesh& m) { return std::vector<bool>(m.edges.size(), true); }

// A unit cube with every edge chamfered by d along each face: 12 prisms of section d²/2 and length
// 1 − 2d go, and at each corner the part of the d-cube below the plane x + y + z = 2d, 5/6 of it.
double chamferedCubeVolume(double d) { return 1.0 - 12 * 0.5 * d * d * (1 - 2 * d) - 8 * (5.0 / 6.0) * d * d * d; }

double totalArea(const Mesh& m) {
    double a = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) a += glm::length(m.faceAreaVector(f));
    return a;
}

// Every edge of a closed mesh is used by exactly two faces, once each way.
void expectClosedAndConsistent(const Mesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t f = 0; f < m.faceCount(); ++f) {
        const auto lp = m.faceOuterLoop(f);
        for (size_t k = 0; k < lp.size(); ++k) ++directed[{lp[k], lp[(k + 1) % lp.size()]}];
    }
    for (const auto& [e, count] : directed) {
        EXPECT_EQ(count, 1) << e.first << "→" << e.second;
        EXPECT_EQ(directed.count({e.second, e.first}), 1u) << e.first << "→" << e.second;
    }
}

TEST(Bevel, EveryEdgeOfACubeChamfersToTheClosedFormVolume) {
    Mesh m = test::unitCube();
    completeEdges(m, false);
    BevelParams p;
    p.edges = all(m);
    p.offset = 0.1;
    BevelResult r;
    ASSERT_TRUE(bevelEdges(m, p, &r));
    EXPECT_EQ(r.bevelledEdges, 12u);
    EXPECT_EQ(r.newFaces, 12u + 8u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_EQ(m.faceCount(), 26u);
    EXPECT_EQ(m.points.size(), 24u);
    expectClosedAndConsistent(m);
    EXPECT_NEAR(m.signedVolume(), chamferedCubeVolume(0.1), 1e-6);
    const Bounds3 b = m.bounds();
    EXPECT_NEAR(b.lo.x, -0.5, 1e-6);
    EXPECT_NEAR(b.hi.z, 0.5, 1e-6);
    // The cube's edges were hard; the chamfer's new edges meet its faces at 45°: hard too.
    for (const MeshEdge& e : m.edges) EXPECT_FALSE(e.smooth);
}

TEST(Bevel, OneEdgeCutsAPrismAlongItsWholeLength) {
    Mesh m = test::unitCube();
    completeEdges(m, true);
    BevelParams p;
    p.edges.assign(m.edges.size(), false);
    p.edges[0] = true;  // 0→1, along X at the front bottom
    p.offset = 0.25;
    BevelResult r;
    ASSERT_TRUE(bevelEdges(m, p, &r));
    EXPECT_EQ(m.faceCount(), 7u);
    EXPECT_EQ(m.points.size(), 10u);
    ASSERT_TRUE(m.validate().ok());
    expectClosedAndConsistent(m);
    EXPECT_NEAR(m.signedVolume(), 1.0 - 0.5 * 0.25 * 0.25, 1e-6);
    // The two end faces (±X) became pentagons.
    size_t pentagons = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) pentagons += m.faceOuterLoop(f).size() == 5;
    EXPECT_EQ(pentagons, 2u);
}

TEST(Bevel, AFractionIsOfHalfTheShortestEdgeAndOffsetsStopThere) {
    Mesh frac = test::unitCube(), big = test::unitCube();
    completeEdges(frac, true);
    completeEdges(big, true);
    BevelParams p;
    p.edges = all(frac);
    p.offsetAsFraction = true;
    p.offset = 0.5;  // a quarter of the unit edges
    ASSERT_TRUE(bevelEdges(frac, p));
    EXPECT_NEAR(frac.signedVolume(), chamferedCubeVolume(0.25), 1e-6);
    // An absolute offset past half an edge stops at half.
    p.offsetAsFraction = false;
    p.offset = 7.0;
    ASSERT_TRUE(bevelEdges(big, p));
    ASSERT_TRUE(big.validate().ok());
    EXPECT_GT(big.signedVolume(), 0.0);
}

TEST(Bevel, AnInnerEdgeOfAPlaneBevelsAndItsBordersDoNot) {
    const Mesh plane = test::unitPlane(2, 1);  // two quads side by side
    Mesh m = plane;
    completeEdges(m, true);
    BevelParams p;
    p.edges = all(m);
    p.offset = 0.1;
    BevelResult r;
    ASSERT_TRUE(bevelEdges(m, p, &r));
    EXPECT_EQ(r.bevelledEdges, 1u);
    EXPECT_EQ(r.skippedEdges, 6u);
    EXPECT_EQ(m.faceCount(), 3u);
    EXPECT_EQ(m.points.size(), 8u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_NEAR(totalArea(m), totalArea(plane), 1e-6);
}

TEST(Bevel, BadOffsetsAreRefusedAndNothingSelectedChangesNothing) {
    Mesh m = test::unitCube();
    completeEdges(m, true);
    const Mesh before = m;
    BevelParams p;
    ASSERT_TRUE(bevelEdges(m, p));
    EXPECT_EQ(m.faceVertices, before.faceVertices);
    p.edges = all(m);
    for (double bad : {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        p.offset = bad;
        std::string error;
        EXPECT_FALSE(bevelEdges(m, p, nullptr, &error));
        EXPECT_FALSE(error.empty());
        EXPECT_EQ(m.faceVertices, before.faceVertices);
    }
}

}  // namespace
}  // namespace pushpin::geom
