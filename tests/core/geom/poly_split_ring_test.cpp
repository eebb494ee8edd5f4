// Tests for core/geom/poly_split_ring.h.
#include "core/geom/poly_split_ring.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <map>

namespace pushpin::geom {
namespace {

Mesh cube(double depth = 1.0) { return test::unitCube(depth); }

std::vector<bool> ring(const Mesh& m, std::initializer_list<uint32_t> edges) {
    std::vector<bool> mask(m.edges.size(), false);
    for (uint32_t e : edges) mask[e] = true;
    return mask;
}

TEST(PolyCube, EdgesAreNumberedAsMayaNumbersThem) {
    const Mesh m = cube();
    const uint32_t maya[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                  {2, 4}, {3, 5}, {4, 6}, {5, 7}, {6, 0}, {7, 1}};
    ASSERT_EQ(m.edges.size(), 12u);
    for (size_t e = 0; e < 12; ++e) {
        EXPECT_EQ(m.edges[e].v0, maya[e][0]) << e;
        EXPECT_EQ(m.edges[e].v1, maya[e][1]) << e;
    }
}

TEST(PolyCylinder, EdgesGoRoundEachRingThenUpEachBand) {
    PolyCylinderParams p;
    p.subdivisionsAxis = 8;
    const Mesh m = *makePolyCylinder(p);
    ASSERT_EQ(m.edges.size(), 40u);
    for (uint32_t j = 0; j < 8; ++j) {
        EXPECT_EQ(m.edges[j].v0, j);                 // bottom ring
        EXPECT_EQ(m.edges[j].v1, (j + 1) % 8);
        EXPECT_EQ(m.edges[8 + j].v0, 8 + j);         // top ring
        EXPECT_EQ(m.edges[16 + j].v0, j);            // up the side
        EXPECT_EQ(m.edges[16 + j].v1, 8 + j);
    }
}

TEST(SplitRing, AClosedRingRoundACubeAddsALoop) {
    // The four edges along Z (e6 2→4, e7 3→5, e10 6→0, e11 7→1), from e7 at 0.25 of its length.
    Mesh m = cube(8.0);
    SplitRingParams p;
    p.edges = ring(m, {6, 7, 10, 11});
    p.rootEdge = 7;
    p.weight = 0.25;
    SplitRingResult r;
    ASSERT_TRUE(splitRing(m, p, &r));
    EXPECT_TRUE(r.closed);
    EXPECT_EQ(r.newPoints, 4u);
    EXPECT_EQ(r.newFaces, 4u);
    ASSERT_EQ(m.points.size(), 12u);
    ASSERT_EQ(m.faceCount(), 10u);
    ASSERT_EQ(m.edges.size(), 20u);
    // Points in walk order: the root (3→5) first, then through the top face to e6, e10 and e11;
    // every one a quarter of the way from the end joined to the root's first point (z = +4).
    const glm::vec3 expected[4] = {{0.5f, 0.5f, 2.0f}, {-0.5f, 0.5f, 2.0f}, {-0.5f, -0.5f, 2.0f}, {0.5f, -0.5f, 2.0f}};
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(glm::length(m.points[8 + i] - expected[i]), 0.0, 1e-6) << i;
    // A split edge keeps its index for its first half; the second halves and the cuts follow in
    // the order of a sequential split: e12 the root's half, e13 e6's, e14 the cut across the top, …
    EXPECT_EQ(m.edges[7].v0, 3u);
    EXPECT_EQ(m.edges[7].v1, 8u);
    EXPECT_EQ(m.edges[12].v0, 8u);
    EXPECT_EQ(m.edges[12].v1, 5u);
    EXPECT_EQ(m.edges[13].v0, 9u);
    EXPECT_EQ(m.edges[13].v1, 4u);
    EXPECT_EQ(std::min(m.edges[14].v0, m.edges[14].v1), 8u);
    EXPECT_EQ(std::max(m.edges[14].v0, m.edges[14].v1), 9u);
    EXPECT_EQ(m.edges[15].v0, 10u);  // e10's second half: 10 → 0
    EXPECT_EQ(m.edges[15].v1, 0u);
    EXPECT_EQ(m.edges[17].v0, 11u);  // e11's second half: 11 → 1
    // The appended faces are the parts from the earlier point forward to the later one: beyond
    // the loop from the root's first point (towards z = -4) here; the kept faces the rest.
    for (size_t f = 6; f < 10; ++f) {
        double z = 0;
        for (uint32_t v : m.faceOuterLoop(f)) z += m.points[v].z;
        EXPECT_LT(z / 4.0, 2.0) << f;
    }
    ASSERT_TRUE(m.validate().ok());
    EXPECT_NEAR(m.signedVolume(), 8.0, 1e-5);
    // Every new face-vertex has a UV.
    for (int32_t id : m.uvSets[0].faceVertexUvs) EXPECT_GE(id, 0);
}

TEST(SplitRing, AnOpenRingAcrossAStripGivesItsEndFacesTheNewPoints) {
    // A 3×1 plane: the ring of the three quads' shared and end edges across the strip.
    PolyPlaneParams pp;
    pp.subdivisionsWidth = 3;
    pp.subdivisionsHeight = 1;
    Mesh m = *makePolyPlane(pp);
    completeEdges(m, true);
    std::vector<bool> across(m.edges.size(), false);
    size_t count = 0;
    for (size_t e = 0; e < m.edges.size(); ++e) {
        const glm::vec3 d = m.points[m.edges[e].v1] - m.points[m.edges[e].v0];
        across[e] = std::abs(d.x) < 1e-6;  // the edges along Z
        count += across[e];
    }
    ASSERT_EQ(count, 4u);
    SplitRingParams p;
    p.edges = across;
    p.weight = 0.5;
    SplitRingResult r;
    ASSERT_TRUE(splitRing(m, p, &r));
    EXPECT_FALSE(r.closed);
    EXPECT_EQ(r.newPoints, 4u);
    EXPECT_EQ(r.newFaces, 3u);
    EXPECT_EQ(m.points.size(), 12u);
    EXPECT_EQ(m.faceCount(), 6u);
    ASSERT_TRUE(m.validate().ok());
    double area = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) area += glm::length(m.faceAreaVector(f));
    EXPECT_NEAR(area, 1.0, 1e-6);
    for (size_t f = 0; f < m.faceCount(); ++f) EXPECT_EQ(m.faceOuterLoop(f).size(), 4u) << f;
}

TEST(SplitRing, BadRequestsAreRefusedAndChangeNothing) {
    Mesh m = cube();
    const size_t points = m.points.size();
    SplitRingParams p;
    p.edges = ring(m, {6, 7, 10, 11});
    p.rootEdge = 0;  // not in the ring
    std::string error;
    EXPECT_FALSE(splitRing(m, p, nullptr, &error));
    EXPECT_NE(error.find("e[0]"), std::string::npos) << error;
    p.rootEdge = 7;
    p.weight = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(splitRing(m, p, nullptr, &error));
    p.weight = 0.5;
    p.rootEdge = 99;
    EXPECT_FALSE(splitRing(m, p, nullptr, &error));
    EXPECT_EQ(m.points.size(), points);
    // Nothing selected: unchanged.
    p.edges.assign(m.edges.size(), false);
    p.rootEdge = -1;
    ASSERT_TRUE(splitRing(m, p));
    EXPECT_EQ(m.points.size(), points);
}

TEST(SplitRing, AWeightOutsideTheEdgeIsClampedToIt) {
    Mesh m = cube();
    SplitRingParams p;
    p.edges = ring(m, {6, 7, 10, 11});
    p.rootEdge = 7;
    p.weight = 7.0;
    ASSERT_TRUE(splitRing(m, p));
    EXPECT_NEAR(m.points[8].z, -0.5, 1e-6);  // at the root's far end
}

}  // namespace
}  // namespace pushpin::geom
