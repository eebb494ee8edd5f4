// Tests for core/geom/poly_extrude_edge.h, worked by hand on a unit quad.
#include "core/geom/poly_extrude_edge.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <limits>
#include <vector>

namespace pushpin::geom {
namespace {

// The quad 0(0,0) 1(1,0) 2(1,1) 3(0,1) in the XY plane, facing +Z; edges e0 0→1, e1 1→2,
// e2 2→3, e3 3→0.
Mesh unitQuad() {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.addFace({0, 1, 2, 3});
    completeEdges(m, true);
    return m;
}

std::vector<bool> pick(const Mesh& m, std::initializer_list<uint32_t> edges) {
    std::vector<bool> mask(m.edges.size(), false);
    for (uint32_t e : edges) mask[e] = true;
    return mask;
}

std::vector<uint32_t> loopOf(const Mesh& m, size_t f) {
    const auto l = m.faceOuterLoop(f);
    return {l.begin(), l.end()};
}

TEST(ExtrudeEdges, AWallStandsOnTheEdgeAndKeepsTheFacesWinding) {
    Mesh m = unitQuad();
    ExtrudeEdgesParams p;
    p.edges = pick(m, {0});
    p.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(0, -1, 0));
    ExtrudeEdgesResult r;
    ASSERT_TRUE(extrudeEdges(m, p, &r));
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(r.wallFaces, 1u);
    ASSERT_TRUE(m.validate().ok());
    ASSERT_EQ(m.points.size(), 6u);
    EXPECT_EQ(m.points[4], glm::vec3(0, -1, 0));
    EXPECT_EQ(m.points[5], glm::vec3(1, -1, 0));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{1, 0, 4, 5}));
    // The wall faces the way the quad does.
    EXPECT_GT(glm::dot(m.faceNormal(1), glm::dvec3(0, 0, 1)), 0.999);
    EXPECT_NEAR(glm::length(m.faceAreaVector(1)), 1.0, 1e-9);
    ASSERT_EQ(m.edges.size(), 7u);
    EXPECT_EQ(m.edges[4].v0, 0u);
    EXPECT_EQ(m.edges[4].v1, 4u);
    EXPECT_EQ(m.edges[5].v0, 1u);
    EXPECT_EQ(m.edges[5].v1, 5u);
    EXPECT_EQ(m.edges[6].v0, 4u);
    EXPECT_EQ(m.edges[6].v1, 5u);
}

TEST(ExtrudeEdges, LocalTranslateYPointsIntoTheFaceBesideTheEdge) {
    // Local frame: z the face normal (+Z), x along the edge (+X), y = z × x = +Y, into the quad.
    Mesh m = unitQuad();
    ExtrudeEdgesParams p;
    p.edges = pick(m, {0});
    p.localTranslate = {0.0, -0.5, 2.0};
    ASSERT_TRUE(extrudeEdges(m, p));
    EXPECT_EQ(m.points[4], glm::vec3(0, -0.5f, 2));
    EXPECT_EQ(m.points[5], glm::vec3(1, -0.5f, 2));
    // Local scale is about the region's centre, along the edge.
    Mesh s = unitQuad();
    p.localTranslate = glm::dvec3(0.0);
    p.localScale = {2.0, 1.0, 1.0};
    ASSERT_TRUE(extrudeEdges(s, p));
    EXPECT_EQ(s.points[4], glm::vec3(-0.5f, 0, 0));
    EXPECT_EQ(s.points[5], glm::vec3(1.5f, 0, 0));
}

TEST(ExtrudeEdges, EdgesSharingAPointShareItsCopyWhenKeptTogether) {
    Mesh together = unitQuad(), apart = unitQuad();
    ExtrudeEdgesParams p;
    p.edges = pick(together, {0, 1});
    p.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 1));
    ExtrudeEdgesResult r;
    ASSERT_TRUE(extrudeEdges(together, p, &r));
    EXPECT_EQ(r.regions, 1u);
    EXPECT_EQ(together.points.size(), 7u);  // copies of 0, 1, 2
    EXPECT_EQ(loopOf(together, 1), (std::vector<uint32_t>{1, 0, 4, 5}));
    EXPECT_EQ(loopOf(together, 2), (std::vector<uint32_t>{2, 1, 5, 6}));
    EXPECT_EQ(together.edges.size(), 4u + 5u);
    ASSERT_TRUE(together.validate().ok());

    p.keepFacesTogether = false;
    ASSERT_TRUE(extrudeEdges(apart, p, &r));
    EXPECT_EQ(r.regions, 2u);
    EXPECT_EQ(apart.points.size(), 8u);  // each edge its own two copies
    EXPECT_EQ(loopOf(apart, 2), (std::vector<uint32_t>{2, 1, 6, 7}));
    EXPECT_EQ(apart.edges.size(), 4u + 6u);
}

TEST(ExtrudeEdges, DivisionsSpaceTheRingsEvenly) {
    Mesh m = unitQuad();
    ExtrudeEdgesParams p;
    p.edges = pick(m, {2});  // 2→3, along the top
    p.divisions = 2;
    p.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 2, 0));
    ExtrudeEdgesResult r;
    ASSERT_TRUE(extrudeEdges(m, p, &r));
    EXPECT_EQ(r.wallFaces, 2u);
    ASSERT_EQ(m.points.size(), 8u);
    EXPECT_EQ(m.points[4], glm::vec3(1, 2, 0));
    EXPECT_EQ(m.points[6], glm::vec3(1, 3, 0));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{3, 2, 4, 5}));
    EXPECT_EQ(loopOf(m, 2), (std::vector<uint32_t>{5, 4, 6, 7}));
    double area = 0;
    for (size_t f = 1; f < 3; ++f) area += glm::length(m.faceAreaVector(f));
    EXPECT_NEAR(area, 2.0, 1e-6);
}

TEST(ExtrudeEdges, NothingSelectedOrBadValues) {
    Mesh m = unitQuad();
    const Mesh before = m;
    ExtrudeEdgesParams p;
    ASSERT_TRUE(extrudeEdges(m, p));
    EXPECT_EQ(m.faceVertices, before.faceVertices);
    p.edges = pick(m, {0});
    p.space = glm::dmat4(0.0);
    std::string error;
    EXPECT_FALSE(extrudeEdges(m, p, nullptr, &error));
    EXPECT_FALSE(error.empty());
    p.space = glm::dmat4(1.0);
    p.localTranslate = {std::numeric_limits<double>::infinity(), 0, 0};
    EXPECT_FALSE(extrudeEdges(m, p, nullptr, &error));
    EXPECT_EQ(m.points.size(), before.points.size());
    EXPECT_EQ(m.faceCount(), 1u);
}

}  // namespace
}  // namespace pushpin::geom
