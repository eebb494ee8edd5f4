// Tests for core/geom/subdivide.h.
#include "core/geom/subdivide.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>

namespace pushpin::geom {
namespace {

Mesh cube() { return test::unitCube(); }
Mesh plane(int sw, int sh) { return test::unitPlane(sw, sh); }

TEST(Subdivide, OneLevelOfACubeHasCatmullClarksCounts) {
    Mesh m = cube();
    std::vector<uint32_t> origin;
    ASSERT_TRUE(subdivideMesh(m, {}, &origin));
    EXPECT_EQ(m.points.size(), 8u + 12u + 6u);
    ASSERT_EQ(m.faceCount(), 24u);
    EXPECT_EQ(m.edges.size(), 48u);
    ASSERT_TRUE(m.validate().ok());
    for (size_t f = 0; f < m.faceCount(); ++f) EXPECT_EQ(m.faceOuterLoop(f).size(), 4u);
    // Faces come grouped by the face they came from, in its order.
    ASSERT_EQ(origin.size(), 24u);
    for (size_t f = 0; f < 24; ++f) EXPECT_EQ(origin[f], f / 4) << f;
    // Smoothing pulls a cube inside itself but keeps it closed and outward-facing.
    const double volume = m.signedVolume();
    EXPECT_GT(volume, 0.4);
    EXPECT_LT(volume, 1.0);
    EXPECT_LE(m.bounds().hi.x, 0.5f + 1e-6f);
    for (int32_t id : m.uvSets[0].faceVertexUvs) EXPECT_GE(id, 0);
}

TEST(Subdivide, TwoLevelsAndTheLinearLimit) {
    Mesh m = cube();
    SubdivideParams p;
    p.levels = 2;
    ASSERT_TRUE(subdivideMesh(m, p));
    EXPECT_EQ(m.points.size(), 98u);
    EXPECT_EQ(m.faceCount(), 96u);
    // Continuity 0 is the linear subdivision: the cube keeps its shape.
    Mesh flat = cube();
    p.continuity = 0.0;
    ASSERT_TRUE(subdivideMesh(flat, p));
    EXPECT_NEAR(flat.signedVolume(), 1.0, 1e-5);
}

TEST(Subdivide, HardEdgesKeptAsCreasesKeepACubeACube) {
    Mesh m = cube();
    for (MeshEdge& e : m.edges) e.smooth = false;
    SubdivideParams p;
    p.keepHardEdges = true;
    ASSERT_TRUE(subdivideMesh(m, p));
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-5);
    size_t hard = 0;
    for (const MeshEdge& e : m.edges) hard += !e.smooth;
    EXPECT_EQ(hard, 24u);  // each of the 12 creased edges in two halves
}

TEST(Subdivide, KeepBorderHoldsAPlanesCorners) {
    Mesh kept = plane(2, 2), free = plane(2, 2);
    ASSERT_TRUE(subdivideMesh(kept, {}));
    EXPECT_NEAR(kept.bounds().hi.x, 0.5, 1e-6);
    EXPECT_NEAR(kept.bounds().hi.z, 0.5, 1e-6);
    SubdivideParams p;
    p.keepBorder = false;
    ASSERT_TRUE(subdivideMesh(free, p));
    // The corners round off: no point is left at a corner.
    bool corner = false;
    for (const glm::vec3& q : free.points) corner |= std::abs(q.x) > 0.4999f && std::abs(q.z) > 0.4999f;
    EXPECT_FALSE(corner);
}

TEST(Subdivide, RefusesHolesAndRunawayLevelsAndLeavesTheMesh) {
    Mesh m = plane(1, 1);
    m.points.push_back({0.1f, 0, 0.1f});
    m.points.push_back({-0.1f, 0, 0.1f});
    m.points.push_back({0, 0, -0.1f});
    const uint32_t hole[3] = {4, 5, 6};
    // Make face 0 hold a hole.
    Mesh holed;
    holed.points = m.points;
    holed.addFace(m.faceOuterLoop(0));
    holed.addHole(hole);
    std::string error;
    EXPECT_FALSE(subdivideMesh(holed, {}, nullptr, &error));
    EXPECT_NE(error.find("holes"), std::string::npos) << error;
    EXPECT_EQ(holed.faceCount(), 1u);

    Mesh big = cube();
    SubdivideParams p;
    p.levels = 40;
    EXPECT_FALSE(subdivideMesh(big, p, nullptr, &error));
    EXPECT_NE(error.find("more than"), std::string::npos) << error;
    EXPECT_EQ(big.faceCount(), 6u);
    // Level 0 changes nothing.
    p.levels = 0;
    ASSERT_TRUE(subdivideMesh(big, p));
    EXPECT_EQ(big.faceCount(), 6u);
}

// A 4×4 grid with its centre point raised by 1: Catmull-Clark's closed forms for a regular
// (valence 4) point. One level: the point moves to (Q + 2R + V)/4 = (0.25 + 2·0.5 + 1)/4, an edge
// point beside it to (v + w + f1 + f2)/4 = (1 + 0 + 0.25 + 0.25)/4; the limit is
// (n²·V + 4·Σedges + Σcorners)/(n(n + 5)) = 16/36.
double heightAt(const Mesh& m, float x, float z) {
    for (const glm::vec3& p : m.points)
        if (std::abs(p.x - x) < 1e-5f && std::abs(p.z - z) < 1e-5f) return p.y;
    return std::nan("");
}

TEST(Subdivide, MatchesCatmullClarksClosedForms) {
    Mesh base = plane(4, 4);
    ASSERT_EQ(base.points.size(), 25u);
    base.points[12].y = 1.0f;
    ASSERT_NEAR(base.points[12].x, 0.0, 1e-6);
    Mesh one = base;
    ASSERT_TRUE(subdivideMesh(one, {}));
    EXPECT_NEAR(heightAt(one, 0.0f, 0.0f), 0.5625, 1e-6);
    EXPECT_NEAR(heightAt(one, 0.125f, 0.0f), 0.375, 1e-6);
    EXPECT_NEAR(heightAt(one, 0.125f, 0.125f), 0.25, 1e-6);  // a face point: the average of its corners
    Mesh deep = base;
    SubdivideParams p;
    p.levels = 6;
    ASSERT_TRUE(subdivideMesh(deep, p));
    EXPECT_NEAR(heightAt(deep, 0.0f, 0.0f), 16.0 / 36.0, 2e-3);
}

}  // namespace
}  // namespace pushpin::geom
