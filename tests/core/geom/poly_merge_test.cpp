// Tests for core/geom/poly_merge.h.
#include "core/geom/poly_merge.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

namespace pushpin::geom {
namespace {

Mesh plane(int sw, int sh) { return test::unitPlane(sw, sh); }

std::vector<bool> pick(size_t n, std::initializer_list<uint32_t> points) {
    std::vector<bool> mask(n, false);
    for (uint32_t p : points) mask[p] = true;
    return mask;
}

TEST(MergeVertices, ToATargetKeepsTheLowestIndexAtTheTargetsPosition) {
    // A 1×1 plane: points 0 1 / 2 3. Merging 1 into 3 makes the quad a triangle.
    Mesh m = plane(1, 1);
    const glm::vec3 at3 = m.points[3];
    MergeVerticesParams p;
    p.points = pick(4, {1, 3});
    p.target = 3;
    MergeVerticesResult r;
    ASSERT_TRUE(mergeVertices(m, p, &r));
    EXPECT_EQ(r.removedPoints, 1u);
    ASSERT_EQ(m.points.size(), 3u);
    EXPECT_NEAR(glm::length(m.points[1] - at3), 0.0, 1e-7);  // the survivor is index 1
    ASSERT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.faceOuterLoop(0).size(), 3u);
    EXPECT_EQ(m.uvSets[0].faceVertexUvs.size(), 3u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_EQ(m.edges.size(), 3u);
}

TEST(MergeVertices, ByDistanceGroupsNearPointsAtTheirAverage) {
    Mesh m = plane(2, 1);  // points 0 1 2 / 3 4 5, 0.5 apart along x
    m.points[1].x = m.points[0].x + 0.01f;  // 1 close to 0
    MergeVerticesParams p;
    p.points = std::vector<bool>(m.points.size(), true);
    p.distance = 0.05;
    MergeVerticesResult r;
    ASSERT_TRUE(mergeVertices(m, p, &r));
    EXPECT_EQ(r.removedPoints, 1u);
    EXPECT_EQ(m.points.size(), 5u);
    EXPECT_NEAR(m.points[0].x, -0.5 + 0.005, 1e-6);
    ASSERT_TRUE(m.validate().ok());
    // The face between 0 and 1 became a triangle; the other stays a quad.
    EXPECT_EQ(m.faceOuterLoop(0).size(), 3u);
    EXPECT_EQ(m.faceOuterLoop(1).size(), 4u);
}

TEST(MergeVertices, DistanceIsMeasuredInTheMoveSpace) {
    Mesh m = plane(2, 1);
    MergeVerticesParams p;
    p.points = std::vector<bool>(m.points.size(), true);
    p.distance = 0.1;  // object-space spacing 0.5, world spacing 0.05
    p.space = glm::dmat4(0.1);
    p.space[3][3] = 1.0;
    MergeVerticesResult r;
    ASSERT_TRUE(mergeVertices(m, p, &r));
    EXPECT_EQ(r.removedPoints, 5u);  // every point within reach of its neighbour: one group
    EXPECT_EQ(m.faceCount(), 0u);
    EXPECT_EQ(r.removedFaces, 2u);
}

TEST(MergeVertices, AlwaysMergeTwoIgnoresTheDistance) {
    Mesh m = plane(1, 1);
    MergeVerticesParams p;
    p.points = pick(4, {0, 1});  // a whole edge apart
    p.alwaysMergeTwo = true;
    MergeVerticesResult r;
    ASSERT_TRUE(mergeVertices(m, p, &r));
    EXPECT_EQ(r.removedPoints, 1u);
    EXPECT_NEAR(m.points[0].x, 0.0, 1e-7);  // the average of the edge's ends
    ASSERT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.faceOuterLoop(0).size(), 3u);
    // Without it, the same two points are too far apart.
    Mesh again = plane(1, 1);
    p.alwaysMergeTwo = false;
    ASSERT_TRUE(mergeVertices(again, p, &r));
    EXPECT_EQ(r.removedPoints, 0u);
}

TEST(MergeVertices, BadRequestsAreRefusedAndChangeNothing) {
    Mesh m = plane(1, 1);
    MergeVerticesParams p;
    p.points = pick(4, {0, 1});
    p.target = 9;
    std::string error;
    EXPECT_FALSE(mergeVertices(m, p, nullptr, &error));
    EXPECT_NE(error.find("vtx[9]"), std::string::npos);
    p.target.reset();
    p.distance = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(mergeVertices(m, p, nullptr, &error));
    EXPECT_EQ(m.points.size(), 4u);
    // Nothing selected, or nothing near: unchanged.
    p.distance = 1e-6;
    ASSERT_TRUE(mergeVertices(m, p));
    EXPECT_EQ(m.points.size(), 4u);
}

TEST(MergeVertices, ManyCoincidentPointsMergeInNearLinearWork) {
    // 200×200 quads split into separate faces: every interior point appears four times.
    Mesh m;
    const int n = 200;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t base = uint32_t(m.points.size());
            m.points.push_back({float(x), 0, float(y)});
            m.points.push_back({float(x + 1), 0, float(y)});
            m.points.push_back({float(x + 1), 0, float(y + 1)});
            m.points.push_back({float(x), 0, float(y + 1)});
            m.addFace({base, base + 3, base + 2, base + 1});
        }
    MergeVerticesParams p;
    p.points = std::vector<bool>(m.points.size(), true);
    p.distance = 1e-3;
    ASSERT_TRUE(mergeVertices(m, p));
    EXPECT_EQ(m.points.size(), size_t((n + 1) * (n + 1)));
    EXPECT_EQ(m.faceCount(), size_t(n * n));
    ASSERT_TRUE(m.validate().ok());
}

}  // namespace
}  // namespace pushpin::geom
