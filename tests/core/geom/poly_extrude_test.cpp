// Tests for core/geom/poly_extrude.h.
#include "core/geom/poly_extrude.h"

#include "tests/support/primitive_meshes.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <map>

namespace pushpin::geom {
namespace {

Mesh cube() { return test::unitCube(); }
Mesh plane(int sw, int sh) { return test::unitPlane(sw, sh); }

std::vector<bool> select(const Mesh& m, std::initializer_list<uint32_t> faces) {
    std::vector<bool> mask(m.faceCount(), false);
    for (uint32_t f : faces) mask[f] = true;
    return mask;
}

// Every loop edge of a closed mesh is used twice, once in each direction.
void expectClosed(const Mesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t l = 0; l < m.loopCount(); ++l) {
        const auto lp = m.loop(l);
        for (size_t k = 0; k < lp.size(); ++k) ++directed[{lp[k], lp[(k + 1) % lp.size()]}];
    }
    for (const auto& [e, n] : directed) {
        EXPECT_EQ(n, 1) << e.first << "-" << e.second;
        EXPECT_EQ(directed.count({e.second, e.first}), 1u) << e.first << "-" << e.second << " has no twin";
    }
}

TEST(ExtrudeFaces, OneCubeFaceGrowsACubeOnTop) {
    Mesh m = cube();
    const std::vector<uint32_t> top(m.faceOuterLoop(1).begin(), m.faceOuterLoop(1).end());
    ExtrudeFacesParams p;
    p.faces = select(m, {1});
    p.localTranslate = {0, 0, 1};
    ExtrudeFacesResult r;
    ASSERT_TRUE(extrudeFaces(m, p, &r));
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(r.sideFaces, 4u);
    EXPECT_EQ(r.removedPoints, 0u);
    ASSERT_EQ(m.points.size(), 12u);
    ASSERT_EQ(m.faceCount(), 10u);
    EXPECT_EQ(m.edges.size(), 20u);
    // The new points copy the face's points in its loop order, one unit up; the face keeps its index.
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(m.faceOuterLoop(1)[i], uint32_t(8 + i));
        const glm::vec3 expected = m.points[top[i]] + glm::vec3(0, 1, 0);
        EXPECT_NEAR(glm::length(m.points[8 + i] - expected), 0.0, 1e-6);
    }
    // Walls (a, b, b', a') along each edge of the old face.
    EXPECT_EQ(m.faceOuterLoop(6)[0], top[0]);
    EXPECT_EQ(m.faceOuterLoop(6)[1], top[1]);
    EXPECT_EQ(m.faceOuterLoop(6)[2], 9u);
    EXPECT_EQ(m.faceOuterLoop(6)[3], 8u);
    ASSERT_TRUE(m.validate().ok());
    expectClosed(m);
    EXPECT_NEAR(m.signedVolume(), 2.0, 1e-6);
    // New edges in Maya's order: per boundary edge, the edges up from its points not made yet,
    // then the edge along it (2→8, 3→9, 8–9, 5→10, 9–10, 4→11, 10–11, 11–8).
    const uint32_t order[8][2] = {{top[0], 8}, {top[1], 9}, {8, 9}, {top[2], 10}, {9, 10}, {top[3], 11}, {10, 11}, {11, 8}};
    for (size_t k = 0; k < 8; ++k) {
        EXPECT_EQ(std::min(m.edges[12 + k].v0, m.edges[12 + k].v1), std::min(order[k][0], order[k][1])) << k;
        EXPECT_EQ(std::max(m.edges[12 + k].v0, m.edges[12 + k].v1), std::max(order[k][0], order[k][1])) << k;
    }
    // The walls meet the cap and each other at right angles: hard under the 30 degree default.
    for (size_t e = 12; e < m.edges.size(); ++e) EXPECT_FALSE(m.edges[e].smooth) << e;
    // Every wall has UVs.
    for (size_t fv = m.faceVertexBegin(6); fv < m.faceVertexEnd(9); ++fv) EXPECT_GE(m.uvSets[0].faceVertexUvs[fv], 0);
}

TEST(ExtrudeFaces, ARegionsInteriorPointsAreRemovedAndTheCapComesLast) {
    Mesh m = plane(2, 2);  // 9 points, the centre one shared by all four faces
    const glm::vec3 centre = m.points[4];
    ExtrudeFacesParams p;
    p.faces = select(m, {0, 1, 2, 3});
    p.localTranslate = {0, 0, 0.5};
    ExtrudeFacesResult r;
    ASSERT_TRUE(extrudeFaces(m, p, &r));
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(r.sideFaces, 8u);
    EXPECT_EQ(r.removedPoints, 1u);
    ASSERT_EQ(m.points.size(), 9u - 1u + 9u);
    EXPECT_EQ(m.faceCount(), 12u);
    // The cap is the last nine points, all half a unit up; the old centre is gone.
    for (size_t i = 8; i < 17; ++i) EXPECT_NEAR(m.points[i].y, 0.5, 1e-6) << i;
    for (size_t i = 0; i < 8; ++i) EXPECT_NEAR(m.points[i].y, 0.0, 1e-6) << i;
    bool centreOnCap = false;
    for (size_t i = 8; i < 17; ++i) centreOnCap |= glm::length(m.points[i] - (centre + glm::vec3(0, 0.5f, 0))) < 1e-6;
    EXPECT_TRUE(centreOnCap);
    for (size_t f = 0; f < 4; ++f)
        for (uint32_t v : m.faceOuterLoop(f)) EXPECT_GE(v, 8u);
    ASSERT_TRUE(m.validate().ok());
    for (const MeshEdge& e : m.edges) {
        EXPECT_LT(e.v0, m.points.size());
        EXPECT_LT(e.v1, m.points.size());
    }
}

TEST(ExtrudeFaces, SeparateFacesEachGetTheirOwnWalls) {
    Mesh m = plane(2, 2);
    ExtrudeFacesParams p;
    p.faces = select(m, {0, 1, 2, 3});
    p.keepFacesTogether = false;
    p.localTranslate = {0, 0, 0.5};
    ExtrudeFacesResult r;
    ASSERT_TRUE(extrudeFaces(m, p, &r));
    EXPECT_EQ(r.regions, 4u);
    EXPECT_EQ(r.sideFaces, 16u);
    EXPECT_EQ(r.removedPoints, 0u);
    EXPECT_EQ(m.points.size(), 9u + 16u);
    EXPECT_EQ(m.faceCount(), 20u);
    ASSERT_TRUE(m.validate().ok());
}

TEST(ExtrudeFaces, DivisionsMakeEvenRings) {
    Mesh m = cube();
    ExtrudeFacesParams p;
    p.faces = select(m, {1});
    p.divisions = 3;
    p.localTranslate = {0, 0, 3};
    ASSERT_TRUE(extrudeFaces(m, p));
    ASSERT_EQ(m.points.size(), 8u + 12u);
    EXPECT_EQ(m.faceCount(), 6u + 12u);
    // Rings at 1, 2 and 3 units above the old top (y = 0.5), intermediate rings first.
    for (size_t i = 0; i < 12; ++i) EXPECT_NEAR(m.points[8 + i].y, 0.5 + double(1 + i / 4), 1e-5) << i;
    ASSERT_TRUE(m.validate().ok());
    expectClosed(m);
    EXPECT_NEAR(m.signedVolume(), 4.0, 1e-5);
}

TEST(ExtrudeFaces, ACornerBetweenTwoSidesMovesHalfwayAlongEach) {
    // The four sides of a cube extruded together (a ring with no plane of its own): a corner
    // point moves by the average of its two faces' normals.
    Mesh m = cube();
    std::vector<bool> sides(m.faceCount(), false);
    for (size_t f = 0; f < m.faceCount(); ++f) {
        const glm::dvec3 n = m.faceNormal(f);
        sides[f] = std::abs(n.y) < 0.5;
    }
    ExtrudeFacesParams p;
    p.faces = sides;
    p.localTranslate = {0, 0, 1};
    p.localScale = {1, 1, 3};  // along each side's own normal: no effect on flat faces
    ASSERT_TRUE(extrudeFaces(m, p));
    const Bounds3 b = m.bounds();
    EXPECT_NEAR(b.hi.x, 1.0, 1e-6);
    EXPECT_NEAR(b.lo.z, -1.0, 1e-6);
    EXPECT_NEAR(b.hi.y, 0.5, 1e-6);
    ASSERT_TRUE(m.validate().ok());
}

TEST(ExtrudeFaces, LocalScaleIsAboutTheFaceCentreAndTheTransformInItsSpace) {
    Mesh m = cube();
    ExtrudeFacesParams p;
    p.faces = select(m, {1});
    p.localScale = {0.5, 0.5, 1};
    // Moved 2 up in a space where object units are doubled: 1 up in object space.
    p.space = glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
    p.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 2, 0));
    ASSERT_TRUE(extrudeFaces(m, p));
    for (size_t i = 8; i < 12; ++i) {
        EXPECT_NEAR(std::abs(m.points[i].x), 0.25, 1e-6);
        EXPECT_NEAR(std::abs(m.points[i].z), 0.25, 1e-6);
        EXPECT_NEAR(m.points[i].y, 1.5, 1e-6);
    }
}

TEST(ExtrudeFaces, NothingSelectedLeavesTheMeshAlone) {
    Mesh m = cube();
    const Mesh before = m;
    ExtrudeFacesParams p;
    ASSERT_TRUE(extrudeFaces(m, p));
    EXPECT_EQ(m.points.size(), before.points.size());
    EXPECT_EQ(m.faceVertices, before.faceVertices);
    p.faces = std::vector<bool>(2, false);
    ASSERT_TRUE(extrudeFaces(m, p));
    EXPECT_EQ(m.faceCount(), before.faceCount());
}

TEST(ExtrudeFaces, NonFiniteOrRunawayRequestsAreRefusedAndChangeNothing) {
    Mesh m = cube();
    const Mesh before = m;
    ExtrudeFacesParams p;
    p.faces = select(m, {1});
    p.localTranslate = {0, 0, std::numeric_limits<double>::infinity()};
    std::string error;
    EXPECT_FALSE(extrudeFaces(m, p, nullptr, &error));
    EXPECT_NE(error.find("not finite"), std::string::npos) << error;
    EXPECT_EQ(m.points.size(), before.points.size());
    EXPECT_EQ(m.faceCount(), before.faceCount());

    p.localTranslate = {0, 0, 1};
    p.divisions = 1 << 30;
    error.clear();
    EXPECT_FALSE(extrudeFaces(m, p, nullptr, &error));
    EXPECT_NE(error.find("more than"), std::string::npos) << error;
    EXPECT_EQ(m.points.size(), before.points.size());

    p.divisions = 1;
    p.space = glm::dmat4(0.0);
    EXPECT_FALSE(extrudeFaces(m, p, nullptr, &error));
    EXPECT_EQ(m.points.size(), before.points.size());
}

}  // namespace
}  // namespace pushpin::geom
