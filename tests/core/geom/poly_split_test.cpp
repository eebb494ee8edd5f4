// Tests for core/geom/poly_split.h, worked by hand on a unit quad and a strip of two quads.
#include "core/geom/poly_split.h"

#include "core/geom/detail/face_edit.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace pushpin::geom {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The quad 0(0,0) 1(1,0) 2(1,1) 3(0,1) in the XY plane, UVs equal to XY; edges e0 0→1, e1 1→2,
// e2 2→3, e3 3→0.
Mesh unitQuad() {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.addFace({0, 1, 2, 3});
    m.uvSets.push_back({"map1", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {0, 1, 2, 3}});
    completeEdges(m, true);
    return m;
}

SplitPoint onEdge(int64_t e, double t) { return {SplitPoint::Kind::Edge, e, t, {}}; }
SplitPoint inFace(int64_t f, glm::dvec3 p) { return {SplitPoint::Kind::Face, f, 0.0, p}; }

std::vector<uint32_t> loopOf(const Mesh& m, size_t f) {
    const auto l = m.faceOuterLoop(f);
    return {l.begin(), l.end()};
}

glm::vec2 uvAt(const Mesh& m, size_t f, size_t corner) {
    const UvSet& s = m.uvSets[0];
    return s.uvs[size_t(s.faceVertexUvs[m.faceVertexBegin(f) + corner])];
}

void expectEdge(const Mesh& m, size_t e, uint32_t v0, uint32_t v1) {
    ASSERT_LT(e, m.edges.size());
    EXPECT_EQ(m.edges[e].v0, v0) << "e" << e;
    EXPECT_EQ(m.edges[e].v1, v1) << "e" << e;
}

double totalArea(const Mesh& m) {
    double a = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) a += glm::length(m.faceAreaVector(f));
    return a;
}

TEST(Split, AcrossAQuadFromEdgeToOppositeEdge) {
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.5), onEdge(2, 0.25)};
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 2u);
    EXPECT_EQ(r.newFaces, 1u);
    EXPECT_EQ(r.newEdges, 3u);
    EXPECT_EQ(r.skippedCuts, 0u);
    ASSERT_TRUE(m.validate().ok());
    // p4 halfway along e0; p5 a quarter along e2 (2→3), at (0.75, 1).
    ASSERT_EQ(m.points.size(), 6u);
    EXPECT_EQ(m.points[4], glm::vec3(0.5f, 0.0f, 0.0f));
    EXPECT_EQ(m.points[5], glm::vec3(0.75f, 1.0f, 0.0f));
    // The face keeps the part B→A round from its first point; A forward to B is appended.
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{0, 4, 5, 3}));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{4, 1, 2, 5}));
    // Split edges keep their index up to the new point; the rest, then the cut, are appended.
    ASSERT_EQ(m.edges.size(), 7u);
    expectEdge(m, 0, 0, 4);
    expectEdge(m, 4, 4, 1);
    expectEdge(m, 2, 2, 5);
    expectEdge(m, 5, 5, 3);
    expectEdge(m, 6, 4, 5);
    // UVs follow the edges.
    EXPECT_EQ(uvAt(m, 0, 1), glm::vec2(0.5f, 0.0f));
    EXPECT_EQ(uvAt(m, 0, 2), glm::vec2(0.75f, 1.0f));
    EXPECT_EQ(uvAt(m, 1, 0), glm::vec2(0.5f, 0.0f));
    EXPECT_NEAR(totalArea(m), 1.0, 1e-6);
    EXPECT_NEAR(glm::length(m.faceAreaVector(1)), 0.375, 1e-6);
}

TEST(Split, NewEdgesAreSoftOnlyBelowTheSmoothingAngle) {
    // The two parts of a flat quad meet at 0°: hard at Maya's default angle 0, soft at 180°.
    Mesh hard = unitQuad(), soft = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.5), onEdge(2, 0.5)};
    ASSERT_TRUE(splitFaces(hard, p));
    p.smoothingAngle = kPi;
    ASSERT_TRUE(splitFaces(soft, p));
    EXPECT_FALSE(hard.edges.back().smooth);
    EXPECT_TRUE(soft.edges.back().smooth);
}

TEST(Split, EndsOfEdgesAreTheirPoints) {
    // e0 at 0 is point 0, e1 at 1 is point 2: the diagonal 0–2, no new point.
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.0), onEdge(1, 1.0)};
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 0u);
    EXPECT_EQ(r.newFaces, 1u);
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{0, 2, 3}));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{0, 1, 2}));
    ASSERT_EQ(m.edges.size(), 5u);
    expectEdge(m, 4, 0, 2);
}

TEST(Split, AlongAnExistingEdgeChangesNothing) {
    Mesh m = unitQuad();
    const Mesh before = m;
    SplitParams p;
    p.points = {onEdge(0, 0.0), onEdge(0, 1.0)};
    ASSERT_TRUE(splitFaces(m, p));
    EXPECT_EQ(m.faceVertices, before.faceVertices);
    EXPECT_EQ(m.edges.size(), before.edges.size());
}

TEST(Split, FreePointsMakeAPocketOffOneEdge) {
    // From e0 at 0.25 up to a free point at (0.5, 0.5) and back down to e0 at 0.75: a triangle
    // cut out of the quad along one edge. The edge points come first (A 4, B 5); the free points
    // of a cut are made after them, from B's end back (here just 6).
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.25), inFace(0, {0.5, 0.5, 0.0}), onEdge(0, 0.75)};
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 3u);
    EXPECT_EQ(r.newFaces, 1u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_EQ(m.points[5], glm::vec3(0.75f, 0.0f, 0.0f));
    EXPECT_EQ(m.points[6], glm::vec3(0.5f, 0.5f, 0.0f));
    // The pocket holds none of the quad's corners: it is the part appended.
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{0, 4, 6, 5, 1, 2, 3}));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{4, 5, 6}));
    // e0 0→4, then the piece 4→1 (e4) split again at 5: e4 4→5, e5 5→1; then the cut 4→6, 6→5.
    ASSERT_EQ(m.edges.size(), 8u);
    expectEdge(m, 4, 4, 5);
    expectEdge(m, 5, 5, 1);
    expectEdge(m, 6, 4, 6);
    expectEdge(m, 7, 6, 5);
    // The free point's UV is its place in the face.
    const glm::vec2 uv = uvAt(m, 0, 2);
    EXPECT_NEAR(uv.x, 0.5, 1e-6);
    EXPECT_NEAR(uv.y, 0.5, 1e-6);
    EXPECT_NEAR(glm::length(m.faceAreaVector(1)), 0.125, 1e-6);
    EXPECT_NEAR(totalArea(m), 1.0, 1e-6);
}

TEST(Split, ThePartWithMoreOfTheFacesCornersKeepsIt) {
    // A cut across a quad from e3 (3→0) at 0.5 to e0 (0→1) at 0.5 cuts the corner 0 off: the
    // part with corners 1, 2, 3 keeps the face.
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(3, 0.5), onEdge(0, 0.5)};
    ASSERT_TRUE(splitFaces(m, p));
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{5, 1, 2, 3, 4}));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{4, 0, 5}));
    // The other way round, from e0 to e3, A forward to B is the big part; it still keeps the face.
    Mesh back = unitQuad();
    p.points = {onEdge(0, 0.5), onEdge(3, 0.5)};
    ASSERT_TRUE(splitFaces(back, p));
    EXPECT_EQ(back.faceOuterLoop(1).size(), 3u);
    EXPECT_NEAR(glm::length(back.faceAreaVector(1)), 0.125, 1e-6);
}

TEST(Split, CleanTwoVerticesDropsTheFreePoints) {
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.5), inFace(0, {0.4, 0.5, 0.0}), onEdge(2, 0.5)};
    p.dropFreePoints = true;
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 2u);
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{4, 1, 2, 5}));
}

TEST(Split, APathAcrossTwoFacesCutsBoth) {
    // Two quads side by side: 0(0,0) 1(1,0) 2(2,0) 3(0,1) 4(1,1) 5(2,1); faces {0,1,4,3}, {1,2,5,4}.
    // Edges: e0 0→1, e1 1→4, e2 4→3, e3 3→0, e4 1→2, e5 2→5, e6 5→4. The path runs from the left
    // border e3, over the shared edge e1, to the right border e5, all at their middles.
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
    m.addFace({0, 1, 4, 3});
    m.addFace({1, 2, 5, 4});
    completeEdges(m, true);
    ASSERT_EQ(m.edges.size(), 7u);
    SplitParams p;
    p.points = {onEdge(3, 0.5), onEdge(1, 0.5), onEdge(5, 0.5)};
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 3u);
    EXPECT_EQ(r.newFaces, 2u);
    EXPECT_EQ(r.newEdges, 5u);
    ASSERT_TRUE(m.validate().ok());
    EXPECT_EQ(m.faceCount(), 4u);
    for (size_t f = 0; f < 4; ++f) {
        EXPECT_EQ(m.faceOuterLoop(f).size(), 4u) << f;
        EXPECT_NEAR(glm::length(m.faceAreaVector(f)), 0.5, 1e-6) << f;
    }
    // New points 6 (0, 0.5), 7 (1, 0.5), 8 (2, 0.5). Each face keeps its part from B round to A
    // (here the upper one) and the lower part is appended; the shared edge's point is in both
    // halves of both faces.
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{7, 4, 3, 6}));
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{8, 5, 4, 7}));
    EXPECT_EQ(loopOf(m, 2), (std::vector<uint32_t>{6, 0, 1, 7}));
    EXPECT_EQ(loopOf(m, 3), (std::vector<uint32_t>{7, 1, 2, 8}));
    expectEdge(m, 9, 6, 7);
    expectEdge(m, 11, 7, 8);
}

TEST(Split, SubdivisionPutsPointsAlongAStraightCut) {
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, 0.5), onEdge(2, 0.5)};
    p.subdivisions = 3;
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.newPoints, 4u);
    EXPECT_EQ(r.newEdges, 5u);  // two halves and three sections
    EXPECT_NEAR(m.points[6].y, 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(m.points[7].y, 2.0 / 3.0, 1e-6);
    EXPECT_EQ(loopOf(m, 0), (std::vector<uint32_t>{0, 4, 6, 7, 5, 3}));
    EXPECT_NEAR(totalArea(m), 1.0, 1e-6);
}

TEST(Split, CutsWithNoFaceForBothEndsAreCountedAndSkipped) {
    // Two separate quads: no face holds a point of each.
    Mesh m = unitQuad();
    m.points.insert(m.points.end(), {{3, 0, 0}, {4, 0, 0}, {4, 1, 0}, {3, 1, 0}});
    m.addFace({4, 5, 6, 7});
    completeEdges(m, true);
    SplitParams p;
    p.points = {onEdge(0, 0.5), onEdge(4, 0.5), inFace(-1, {0.5, 0.5, 0.0})};
    SplitResult r;
    ASSERT_TRUE(splitFaces(m, p, &r));
    EXPECT_EQ(r.skippedCuts, 2u);  // the cut, and the free point that leads nowhere
    EXPECT_EQ(m.faceCount(), 2u);
    ASSERT_TRUE(m.validate().ok());
    // The free point that went into no face is not left behind.
    EXPECT_EQ(m.points.size(), 10u);
}

TEST(Split, BadRequestsAreRefusedAndChangeNothing) {
    const Mesh before = unitQuad();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<SplitParams> bad = {
        {{onEdge(4, 0.5), onEdge(0, 0.5)}, 1, 0.0, false},
        {{onEdge(-1, 0.5), onEdge(0, 0.5)}, 1, 0.0, false},
        {{onEdge(0, nan), onEdge(2, 0.5)}, 1, 0.0, false},
        {{onEdge(0, 0.5), inFace(3, {0.5, 0.5, 0}), onEdge(2, 0.5)}, 1, 0.0, false},
        {{onEdge(0, 0.5), inFace(0, {nan, 0.5, 0}), onEdge(2, 0.5)}, 1, 0.0, false},
        {{onEdge(0, 0.5), onEdge(2, 0.5)}, 0, 0.0, false},
        {{onEdge(0, 0.5), onEdge(2, 0.5)}, kMaxSplitSubdivisions + 1, 0.0, false},
        {{onEdge(0, 0.5), onEdge(2, 0.5)}, 1, nan, false},
    };
    SplitParams crowded;  // more path points than any split tool makes, all on one edge
    for (size_t i = 0; i <= kMaxSplitPathPoints; ++i) crowded.points.push_back(onEdge(0, double(i) / double(kMaxSplitPathPoints + 1)));
    bad.push_back(crowded);
    for (size_t i = 0; i < bad.size(); ++i) {
        Mesh m = before;
        std::string error;
        EXPECT_FALSE(splitFaces(m, bad[i], nullptr, &error)) << i;
        EXPECT_FALSE(error.empty()) << i;
        EXPECT_EQ(m.faceVertices, before.faceVertices) << i;
        EXPECT_EQ(m.points.size(), before.points.size()) << i;
    }
}

TEST(Split, FractionsOutsideTheEdgeAreClamped) {
    Mesh m = unitQuad();
    SplitParams p;
    p.points = {onEdge(0, -3.0), onEdge(1, 7.0)};  // points 0 and 2
    ASSERT_TRUE(splitFaces(m, p));
    EXPECT_EQ(m.points.size(), 4u);
    EXPECT_EQ(loopOf(m, 1), (std::vector<uint32_t>{0, 1, 2}));
}

TEST(PolygonWeights, InterpolateCornersEdgesAndTheInside) {
    const std::vector<glm::dvec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const glm::dvec3 n(0, 0, 1);
    auto at = [&](glm::dvec3 p) {
        const std::vector<double> w = detail::polygonWeights(square, p, n);
        glm::dvec3 sum(0.0);
        double total = 0;
        for (size_t i = 0; i < 4; ++i) {
            sum += w[i] * square[i];
            total += w[i];
        }
        EXPECT_NEAR(total, 1.0, 1e-12);
        return sum;
    };
    // Mean value weights reproduce linear functions: the point itself comes back.
    for (const glm::dvec3 p : {glm::dvec3(0.5, 0.5, 0), glm::dvec3(0.1, 0.7, 0), glm::dvec3(1, 0, 0), glm::dvec3(0.5, 0, 0)}) {
        const glm::dvec3 q = at(p);
        EXPECT_NEAR(q.x, p.x, 1e-12);
        EXPECT_NEAR(q.y, p.y, 1e-12);
    }
    const std::vector<double> corner = detail::polygonWeights(square, {1, 1, 0}, n);
    EXPECT_EQ(corner[2], 1.0);
}

}  // namespace
}  // namespace pushpin::geom
