// Tests for core/geom/poly_primitives.h.
#include "core/geom/poly_primitives.h"
#include "core/geom/tessellation.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>

namespace pushpin::geom {
namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 faceCentroid(const Mesh& m, size_t f) {
    glm::dvec3 c(0.0);
    const auto loop = m.faceOuterLoop(f);
    for (uint32_t v : loop) c += glm::dvec3(m.points[v]);
    return c / double(loop.size());
}

// Every property a closed, convex, well-formed primitive must have.
void expectClosedConvexPrimitive(const Mesh& m, const std::string& what) {
    SCOPED_TRACE(what);
    const MeshValidation v = m.validate();
    ASSERT_TRUE(v.ok()) << v.errors.front();
    EXPECT_TRUE(v.degenerateFaces.empty()) << v.degenerateFaces.size() << " degenerate faces";
    // Closed 2-manifold: every edge used by exactly two loops, once in each direction.
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t l = 0; l < m.loopCount(); ++l) {
        const auto loop = m.loop(l);
        for (size_t i = 0; i < loop.size(); ++i) ++directed[{loop[i], loop[(i + 1) % loop.size()]}];
    }
    for (const auto& [e, count] : directed) {
        EXPECT_EQ(count, 1) << "edge " << e.first << "-" << e.second;
        EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "open edge " << e.first << "-" << e.second;
    }
    const glm::dvec3 centre = m.bounds().center();
    for (size_t f = 0; f < m.faceCount(); ++f)
        EXPECT_GT(glm::dot(m.faceNormal(f), faceCentroid(m, f) - centre), 0.0) << "face " << f << " points inward";
    EXPECT_GT(m.signedVolume(), 0.0);
    EXPECT_EQ(m.edges.size(), directed.size() / 2);
}

void expectUvsInUnitSquare(const Mesh& m) {
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].name, "map1");
    ASSERT_EQ(m.uvSets[0].faceVertexUvs.size(), m.faceVertexCount());
    for (int32_t id : m.uvSets[0].faceVertexUvs) EXPECT_GE(id, 0);
    for (const glm::vec2& uv : m.uvSets[0].uvs) {
        EXPECT_GE(uv.x, 0.0f);
        EXPECT_LE(uv.x, 1.0f);
        EXPECT_GE(uv.y, 0.0f);
        EXPECT_LE(uv.y, 1.0f);
    }
}

// Signed area of every face in UV space: a layout that is not mirrored gives positive areas.
void expectUvFacesNotMirrored(const Mesh& m) {
    const UvSet& set = m.uvSets.at(0);
    for (size_t f = 0; f < m.faceCount(); ++f) {
        double area2 = 0.0;
        const uint32_t b = m.faceVertexBegin(f), e = m.faceVertexEnd(f);
        for (uint32_t i = b; i < e; ++i) {
            const glm::vec2 p = set.uvs[set.faceVertexUvs[i]];
            const glm::vec2 q = set.uvs[set.faceVertexUvs[i + 1 < e ? i + 1 : b]];
            area2 += double(p.x) * q.y - double(q.x) * p.y;
        }
        EXPECT_GT(area2, 0.0) << "uv face " << f;
    }
}

TEST(PolyCube, UnitCubeMatchesMayaLayout) {
    const std::optional<Mesh> m = makePolyCube({});
    ASSERT_TRUE(m);
    ASSERT_EQ(m->points.size(), 8u);
    ASSERT_EQ(m->faceCount(), 6u);
    const glm::vec3 expectedPoints[] = {{-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f},  {-0.5f, 0.5f, 0.5f},
                                        {0.5f, 0.5f, 0.5f},   {-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f},
                                        {-0.5f, -0.5f, -0.5f}, {0.5f, -0.5f, -0.5f}};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(m->points[i], expectedPoints[i]) << "point " << i;
    const std::vector<uint32_t> loops = {0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4};
    EXPECT_EQ(m->faceVertices, loops);
    const std::vector<int32_t> uvIds = {0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 9, 8, 1, 10, 11, 3, 12, 0, 2, 13};
    EXPECT_EQ(m->uvSets[0].faceVertexUvs, uvIds);
    const std::vector<glm::vec2> uvs = {{0.375f, 0},    {0.625f, 0},    {0.375f, 0.25f}, {0.625f, 0.25f},
                                        {0.375f, 0.5f}, {0.625f, 0.5f}, {0.375f, 0.75f}, {0.625f, 0.75f},
                                        {0.375f, 1},    {0.625f, 1},    {0.875f, 0},     {0.875f, 0.25f},
                                        {0.125f, 0},    {0.125f, 0.25f}};
    EXPECT_EQ(m->uvSets[0].uvs, uvs);
    expectClosedConvexPrimitive(*m, "unit cube");
    EXPECT_NEAR(m->signedVolume(), 1.0, 1e-9);
    for (const MeshEdge& e : m->edges) EXPECT_FALSE(e.smooth);
}

TEST(PolyCube, SubdividedCountsBoundsAndVolume) {
    struct Case { int sw, sh, sd; };
    for (const Case c : {Case{2, 2, 2}, Case{3, 1, 1}, Case{1, 2, 3}, Case{4, 5, 6}}) {
        PolyCubeParams p;
        p.width = 2;
        p.height = 3;
        p.depth = 4;
        p.subdivisionsWidth = c.sw;
        p.subdivisionsHeight = c.sh;
        p.subdivisionsDepth = c.sd;
        const std::optional<Mesh> m = makePolyCube(p);
        ASSERT_TRUE(m);
        const std::string what = std::to_string(c.sw) + "x" + std::to_string(c.sh) + "x" + std::to_string(c.sd);
        const size_t verts = size_t((c.sw + 1) * (c.sh + 1) * (c.sd + 1) - (c.sw - 1) * (c.sh - 1) * (c.sd - 1));
        EXPECT_EQ(m->points.size(), verts) << what;
        EXPECT_EQ(m->faceCount(), size_t(2 * (c.sw * c.sh + c.sw * c.sd + c.sh * c.sd))) << what;
        expectClosedConvexPrimitive(*m, what);
        expectUvsInUnitSquare(*m);
        expectUvFacesNotMirrored(*m);
        EXPECT_NEAR(m->signedVolume(), 24.0, 1e-4) << what;
        const Bounds3 b = m->bounds();
        EXPECT_NEAR(b.lo.x, -1.0, 1e-6);
        EXPECT_NEAR(b.hi.y, 1.5, 1e-6);
        EXPECT_NEAR(b.lo.z, -2.0, 1e-6);
    }
}

TEST(PolyCube, ThePlusXSideIsNumberedFromTheBack) {
    // After the belt (front, top, back, bottom), the +X side's faces run row by row from the
    // bottom, each row from the back (-Z) to the front, and so do its inner points. Maya's
    // recorded extrusion bounds on a real scene's 4×4×8 cube agree only so (see
    // Corpus.ExtrudedFacesHaveTheBoundsMayaRecorded, Hyena.ma polyExtrudeFace1).
    PolyCubeParams p;
    p.subdivisionsHeight = 2;
    p.subdivisionsDepth = 3;
    const Mesh m = *makePolyCube(p);
    const size_t belt = size_t(2 * (2 + 3));  // sw = 1
    ASSERT_EQ(m.faceCount(), belt + 2 * 6);
    auto centre = [&](size_t f) {
        glm::dvec3 c(0.0);
        for (uint32_t v : m.faceOuterLoop(f)) c += glm::dvec3(m.points[v]);
        return c / double(m.faceOuterLoop(f).size());
    };
    for (size_t k = 0; k < 6; ++k) {
        const glm::dvec3 c = centre(belt + k);
        EXPECT_NEAR(c.x, 0.5, 1e-6) << k;
        EXPECT_NEAR(c.y, k < 3 ? -0.25 : 0.25, 1e-6) << k;
        EXPECT_NEAR(c.z, -1.0 / 3.0 + double(k % 3) / 3.0, 1e-6) << k;
        EXPECT_GT(glm::dot(m.faceNormal(belt + k), glm::dvec3(1, 0, 0)), 0.99) << k;
    }
    // The belt's (K · (sw + 1) = 20) points come first; then the +X side's inner points.
    EXPECT_NEAR(m.points[20].x, 0.5, 1e-6);
    EXPECT_NEAR(m.points[20].z, -1.0 / 6.0, 1e-6);
    EXPECT_NEAR(m.points[21].z, 1.0 / 6.0, 1e-6);
}

TEST(PolyCube, AxisRotatesTheUpDirection) {
    PolyCubeParams p;
    p.height = 2;
    p.depth = 3;
    p.axis = {1, 0, 0};  // as in cgkit's objects.ma
    const std::optional<Mesh> m = makePolyCube(p);
    ASSERT_TRUE(m);
    const Bounds3 b = m->bounds();
    EXPECT_NEAR(b.hi.x, 1.0, 1e-6);   // height now along X
    EXPECT_NEAR(b.hi.y, 0.5, 1e-6);
    EXPECT_NEAR(b.hi.z, 1.5, 1e-6);
    expectClosedConvexPrimitive(*m, "x axis");
    EXPECT_NEAR(m->signedVolume(), 6.0, 1e-5);

    p.axis = {0, -1, 0};
    const std::optional<Mesh> down = makePolyCube(p);
    ASSERT_TRUE(down);
    expectClosedConvexPrimitive(*down, "-y axis");
    p.axis = {0, 0, 0};  // degenerate axis keeps +Y
    const std::optional<Mesh> keep = makePolyCube(p);
    ASSERT_TRUE(keep);
    EXPECT_NEAR(keep->bounds().hi.y, 1.0, 1e-6);
}

TEST(PolyCube, ClampsSubdivisionsAndRejectsNaN) {
    PolyCubeParams p;
    p.subdivisionsWidth = 0;
    p.subdivisionsHeight = -5;
    const std::optional<Mesh> m = makePolyCube(p);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->points.size(), 8u);
    p.width = std::numeric_limits<double>::quiet_NaN();
    std::string error;
    EXPECT_FALSE(makePolyCube(p, &error));
    EXPECT_NE(error.find("width"), std::string::npos) << error;
    p.width = 1;
    p.subdivisionsWidth = p.subdivisionsHeight = p.subdivisionsDepth = 100000;
    EXPECT_FALSE(makePolyCube(p, &error));
    EXPECT_NE(error.find("limit"), std::string::npos) << error;
}

TEST(PolyCube, ZeroSizeGivesDegenerateFacesNotACrash) {
    PolyCubeParams p;
    p.width = 0;
    p.height = -1;  // treated as 0
    const std::optional<Mesh> m = makePolyCube(p);
    ASSERT_TRUE(m);
    const MeshValidation v = m->validate();
    EXPECT_TRUE(v.ok());
    EXPECT_EQ(v.degenerateFaces.size(), 6u);
}

TEST(PolyCube, NoUvsWhenNotRequested) {
    PolyCubeParams p;
    p.createUVs = false;
    const std::optional<Mesh> m = makePolyCube(p);
    ASSERT_TRUE(m);
    EXPECT_TRUE(m->uvSets.empty());
    EXPECT_TRUE(m->validate().ok());
}

TEST(PolySphere, CountsMatchMaya) {
    struct Case { int sa, sh; };
    for (const Case c : {Case{20, 20}, Case{3, 2}, Case{8, 5}, Case{64, 32}}) {
        PolySphereParams p;
        p.radius = 2.0;
        p.subdivisionsAxis = c.sa;
        p.subdivisionsHeight = c.sh;
        const std::optional<Mesh> m = makePolySphere(p);
        ASSERT_TRUE(m);
        const std::string what = std::to_string(c.sa) + "x" + std::to_string(c.sh);
        EXPECT_EQ(m->points.size(), size_t(c.sa * (c.sh - 1) + 2)) << what;
        EXPECT_EQ(m->faceCount(), size_t(c.sa * c.sh)) << what;
        EXPECT_EQ(m->uvSets[0].uvs.size(), size_t((c.sa + 1) * (c.sh - 1) + 2 * c.sa)) << what;
        // Triangle fans at the poles, quads in between.
        size_t triangles = 0;
        for (size_t f = 0; f < m->faceCount(); ++f) triangles += m->faceOuterLoop(f).size() == 3;
        EXPECT_EQ(triangles, size_t(2 * c.sa)) << what;
        expectClosedConvexPrimitive(*m, what);
        expectUvsInUnitSquare(*m);
        expectUvFacesNotMirrored(*m);
        for (const glm::vec3& q : m->points) EXPECT_NEAR(glm::length(glm::dvec3(q)), 2.0, 1e-5);
        EXPECT_NEAR(m->bounds().hi.y, 2.0, 1e-6);
        EXPECT_NEAR(m->bounds().lo.y, -2.0, 1e-6);
        EXPECT_LT(m->signedVolume(), 4.0 / 3.0 * kPi * 8.0);
    }
    PolySphereParams fine;
    fine.subdivisionsAxis = 64;
    fine.subdivisionsHeight = 64;
    const std::optional<Mesh> m = makePolySphere(fine);
    ASSERT_TRUE(m);
    EXPECT_NEAR(m->signedVolume(), 4.0 / 3.0 * kPi, 0.01 * 4.0 / 3.0 * kPi);
    // Smooth shading: every edge soft, corner normals radial.
    for (const MeshEdge& e : m->edges) EXPECT_TRUE(e.smooth);
    const std::vector<glm::vec3> n = m->shadingNormals();
    for (size_t c = 0; c < n.size(); ++c)
        EXPECT_GT(glm::dot(glm::dvec3(n[c]), glm::normalize(glm::dvec3(m->points[m->faceVertices[c]]))), 0.999);
}

TEST(PolySphere, ClampsToMinimumsAndRejectsNaNRadius) {
    PolySphereParams p;
    p.subdivisionsAxis = 0;
    p.subdivisionsHeight = 0;
    const std::optional<Mesh> m = makePolySphere(p);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->points.size(), 5u);  // 3 around, 2 high
    EXPECT_EQ(m->faceCount(), 6u);
    p.radius = std::numeric_limits<double>::quiet_NaN();
    std::string error;
    EXPECT_FALSE(makePolySphere(p, &error));
    EXPECT_EQ(error, "polySphere: radius is not a finite number");
    p.radius = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(makePolySphere(p, &error));
}

TEST(PolyPlane, CountsBoundsAndUvs) {
    PolyPlaneParams p;
    p.width = 4;
    p.height = 2;
    p.subdivisionsWidth = 3;
    p.subdivisionsHeight = 2;
    const std::optional<Mesh> m = makePolyPlane(p);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->points.size(), 12u);
    EXPECT_EQ(m->faceCount(), 6u);
    EXPECT_EQ(m->points[0], glm::vec3(-2, 0, 1));
    EXPECT_EQ(m->points[11], glm::vec3(2, 0, -1));
    EXPECT_EQ(m->uvSets[0].uvs[0], glm::vec2(0, 0));
    EXPECT_EQ(m->uvSets[0].uvs[11], glm::vec2(1, 1));
    for (size_t f = 0; f < m->faceCount(); ++f)
        EXPECT_NEAR(glm::length(m->faceNormal(f) - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
    expectUvsInUnitSquare(*m);
    expectUvFacesNotMirrored(*m);
    EXPECT_TRUE(m->validate().degenerateFaces.empty());

    const std::optional<Mesh> defaults = makePolyPlane({});
    ASSERT_TRUE(defaults);
    EXPECT_EQ(defaults->points.size(), 121u);
    EXPECT_EQ(defaults->faceCount(), 100u);

    p.axis = {0, 0, 1};
    const std::optional<Mesh> front = makePolyPlane(p);
    ASSERT_TRUE(front);
    EXPECT_NEAR(glm::length(front->faceNormal(0) - glm::dvec3(0, 0, 1)), 0.0, 1e-9);
}

TEST(PolyCylinder, CountsForCapSettings) {
    struct Case { int sa, sh, sc; size_t verts, faces; };
    for (const Case c : {Case{20, 1, 1, 42, 60}, Case{20, 1, 0, 40, 22}, Case{8, 3, 2, 8 * 4 + 2 * 8 + 2, 8 * 3 + 2 * 8 * 2},
                         Case{3, 1, 3, 3 * 2 + 2 * 3 * 2 + 2, 3 + 2 * 3 * 3}}) {
        PolyCylinderParams p;
        p.radius = 0.5;
        p.height = 3;
        p.subdivisionsAxis = c.sa;
        p.subdivisionsHeight = c.sh;
        p.subdivisionsCaps = c.sc;
        const std::optional<Mesh> m = makePolyCylinder(p);
        ASSERT_TRUE(m);
        const std::string what = std::to_string(c.sa) + "/" + std::to_string(c.sh) + "/" + std::to_string(c.sc);
        EXPECT_EQ(m->points.size(), c.verts) << what;
        EXPECT_EQ(m->faceCount(), c.faces) << what;
        expectClosedConvexPrimitive(*m, what);
        expectUvsInUnitSquare(*m);
        expectUvFacesNotMirrored(*m);
        const double polygonArea = 0.5 * c.sa * 0.25 * std::sin(2 * kPi / c.sa);
        EXPECT_NEAR(m->signedVolume(), polygonArea * 3.0, 1e-5) << what;
        EXPECT_NEAR(m->bounds().hi.y, 1.5, 1e-6);
        EXPECT_NEAR(m->bounds().hi.x, 0.5, 1e-6);
        size_t hard = 0;
        for (const MeshEdge& e : m->edges) hard += !e.smooth;
        EXPECT_EQ(hard, size_t(2 * c.sa)) << what;  // the two cap borders
    }
}

TEST(PolyCone, CountsForCapSettings) {
    struct Case { int sa, sh, sc; size_t verts, faces; };
    for (const Case c : {Case{20, 1, 0, 21, 21}, Case{20, 1, 1, 22, 40}, Case{6, 3, 2, 6 * 3 + 1 + 6 + 1, 6 * 3 + 6 * 2}}) {
        PolyConeParams p;
        p.radius = 1;
        p.height = 2;
        p.subdivisionsAxis = c.sa;
        p.subdivisionsHeight = c.sh;
        p.subdivisionsCap = c.sc;
        const std::optional<Mesh> m = makePolyCone(p);
        ASSERT_TRUE(m);
        const std::string what = std::to_string(c.sa) + "/" + std::to_string(c.sh) + "/" + std::to_string(c.sc);
        EXPECT_EQ(m->points.size(), c.verts) << what;
        EXPECT_EQ(m->faceCount(), c.faces) << what;
        expectClosedConvexPrimitive(*m, what);
        expectUvsInUnitSquare(*m);
        expectUvFacesNotMirrored(*m);
        const double baseArea = 0.5 * c.sa * std::sin(2 * kPi / c.sa);
        EXPECT_NEAR(m->signedVolume(), baseArea * 2.0 / 3.0, 1e-5) << what;
        EXPECT_NEAR(m->bounds().hi.y, 1.0, 1e-6);
    }
}

TEST(PolyTorus, CountsVolumeAndOutwardNormals) {
    PolyTorusParams p;
    p.radius = 2;
    p.sectionRadius = 0.5;
    p.subdivisionsAxis = 48;
    p.subdivisionsHeight = 24;
    p.twistRadians = 0.3;
    const std::optional<Mesh> m = makePolyTorus(p);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->points.size(), 48u * 24u);
    EXPECT_EQ(m->faceCount(), 48u * 24u);
    EXPECT_EQ(m->uvSets[0].uvs.size(), 49u * 25u);
    expectUvsInUnitSquare(*m);
    expectUvFacesNotMirrored(*m);
    ASSERT_TRUE(m->validate().ok());
    EXPECT_TRUE(m->validate().degenerateFaces.empty());
    // Outward: away from the nearest point of the core circle.
    for (size_t f = 0; f < m->faceCount(); ++f) {
        const glm::dvec3 c = faceCentroid(*m, f);
        const glm::dvec3 core = glm::normalize(glm::dvec3(c.x, 0, c.z)) * 2.0;
        EXPECT_GT(glm::dot(m->faceNormal(f), c - core), 0.0) << "face " << f;
    }
    EXPECT_NEAR(m->signedVolume(), 2 * kPi * kPi * 2.0 * 0.25, 0.02 * 2 * kPi * kPi * 2.0 * 0.25);
    EXPECT_NEAR(m->bounds().hi.x, 2.5, 1e-3);
    EXPECT_NEAR(m->bounds().hi.y, 0.5, 1e-2);

    PolyTorusParams small;
    small.subdivisionsAxis = 1;
    small.subdivisionsHeight = 1;
    const std::optional<Mesh> clamped = makePolyTorus(small);
    ASSERT_TRUE(clamped);
    EXPECT_EQ(clamped->faceCount(), 9u);
    small.twistRadians = std::numeric_limits<double>::quiet_NaN();
    std::string error;
    EXPECT_FALSE(makePolyTorus(small, &error));
    EXPECT_NE(error.find("twist"), std::string::npos);
}

TEST(PolyPlatonicSolid, FacesVolumesAndUvs) {
    struct Case { int type; size_t verts, faces, sides; double volume; };
    const double s5 = std::sqrt(5.0);
    const double icosaEdge = 4.0 / std::sqrt(10.0 + 2.0 * s5);
    const double dodecaEdge = 4.0 / (std::sqrt(3.0) * (1.0 + s5));
    const Case cases[] = {
        {0, 20, 12, 5, (15.0 + 7.0 * s5) / 4.0 * std::pow(dodecaEdge, 3)},
        {1, 12, 20, 3, 5.0 / 12.0 * (3.0 + s5) * std::pow(icosaEdge, 3)},
        {2, 6, 8, 3, 4.0 / 3.0},
        {3, 4, 4, 3, 8.0 / (9.0 * std::sqrt(3.0))},
    };
    for (const Case& c : cases) {
        PolyPlatonicParams p;
        p.solidType = c.type;
        const std::optional<Mesh> m = makePolyPlatonicSolid(p);
        ASSERT_TRUE(m);
        const std::string what = "solidType " + std::to_string(c.type);
        EXPECT_EQ(m->points.size(), c.verts) << what;
        EXPECT_EQ(m->faceCount(), c.faces) << what;
        for (size_t f = 0; f < m->faceCount(); ++f) EXPECT_EQ(m->faceOuterLoop(f).size(), c.sides) << what;
        expectClosedConvexPrimitive(*m, what);
        expectUvsInUnitSquare(*m);
        expectUvFacesNotMirrored(*m);
        EXPECT_NEAR(m->signedVolume(), c.volume, 1e-5) << what;
    }
    PolyPlatonicParams bad;
    bad.solidType = 7;
    std::string error;
    EXPECT_FALSE(makePolyPlatonicSolid(bad, &error));
    EXPECT_NE(error.find("solidType 7"), std::string::npos);
}

TEST(AxisRotation, MapsUpOntoAxis) {
    for (const glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(1, 2, 3), glm::dvec3(0, -1, 0),
                                  glm::dvec3(1e-9, -1, 0)}) {
        const glm::dmat3 r = axisRotation(axis);
        EXPECT_NEAR(glm::length(r * glm::dvec3(0, 1, 0) - glm::normalize(axis)), 0.0, 1e-9);
        EXPECT_NEAR(glm::determinant(r), 1.0, 1e-9);
    }
    EXPECT_EQ(axisRotation(glm::dvec3(std::numeric_limits<double>::quiet_NaN())), glm::dmat3(1.0));
}

// What the counts promise, checked against the generated mesh: every count exact (uvs at most),
// no degenerate face, every point inside the bounds; `tight` also asks the bounds to be the
// points' own box to within their padding.
void expectCountsMatch(const std::optional<PrimitiveCounts>& counts, const std::optional<Mesh>& mesh, bool tight,
                       const std::string& what) {
    SCOPED_TRACE(what);
    ASSERT_TRUE(counts.has_value());
    ASSERT_TRUE(mesh.has_value());
    const MeshValidation v = mesh->validate();
    ASSERT_TRUE(v.ok());
    EXPECT_TRUE(v.degenerateFaces.empty());
    EXPECT_EQ(counts->points, mesh->points.size());
    EXPECT_EQ(counts->faces, mesh->faceCount());
    EXPECT_EQ(counts->faceVertices, mesh->faceVertexCount());
    EXPECT_EQ(counts->edges, mesh->edges.size());
    EXPECT_EQ(counts->triangles, meshTriangleCount(*mesh, {}, {}));
    const uint64_t uvs = mesh->uvSets.empty() ? 0 : mesh->uvSets[0].uvs.size();
    EXPECT_GE(counts->uvs, uvs);
    const Bounds3 actual = mesh->bounds();
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(counts->bounds.lo[k], actual.lo[k]);
        EXPECT_GE(counts->bounds.hi[k], actual.hi[k]);
        if (tight) {
            const double slack = 1e-4 * std::max(1.0, glm::length(actual.size()));
            EXPECT_NEAR(counts->bounds.lo[k], actual.lo[k], slack);
            EXPECT_NEAR(counts->bounds.hi[k], actual.hi[k], slack);
        }
    }
}

TEST(PrimitiveCounts, SphereCountsAndBoundsMatchTheMesh) {
    for (auto [sa, sh] : {std::pair{20, 20}, std::pair{3, 2}, std::pair{1, 1}, std::pair{64, 7}, std::pair{5, 300}}) {
        for (const glm::dvec3& axis : {glm::dvec3(0, 1, 0), glm::dvec3(1, 2, 3), glm::dvec3(0, -1, 0)}) {
            for (bool uvs : {true, false}) {
                PolySphereParams p;
                p.radius = 2.5;
                p.subdivisionsAxis = sa;
                p.subdivisionsHeight = sh;
                p.axis = axis;
                p.createUVs = uvs;
                expectCountsMatch(polySphereCounts(p), makePolySphere(p), false,
                                  "sphere " + std::to_string(sa) + "x" + std::to_string(sh));
                if (uvs) {
                    EXPECT_EQ(polySphereCounts(p)->uvs, makePolySphere(p)->uvSets[0].uvs.size());
                }
            }
        }
    }
}

TEST(PrimitiveCounts, PlaneAndCubeCountsAndBoundsMatchTheMesh) {
    for (const glm::dvec3& axis : {glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1), glm::dvec3(1, 2, 3), glm::dvec3(0, -1, 0)}) {
        PolyPlaneParams plane;
        plane.width = 7.0;
        plane.height = 0.5;
        plane.subdivisionsWidth = 13;
        plane.subdivisionsHeight = 4;
        plane.axis = axis;
        expectCountsMatch(polyPlaneCounts(plane), makePolyPlane(plane), true, "plane");
        EXPECT_EQ(polyPlaneCounts(plane)->uvs, makePolyPlane(plane)->uvSets[0].uvs.size());
        for (auto [sw, sh, sd] : {std::tuple{1, 1, 1}, std::tuple{3, 2, 5}, std::tuple{0, 7, 1}}) {
            PolyCubeParams cube;
            cube.width = 1.5;
            cube.height = 4.0;
            cube.depth = 0.75;
            cube.subdivisionsWidth = sw;
            cube.subdivisionsHeight = sh;
            cube.subdivisionsDepth = sd;
            cube.axis = axis;
            expectCountsMatch(polyCubeCounts(cube), makePolyCube(cube), true,
                              "cube " + std::to_string(sw) + "x" + std::to_string(sh) + "x" + std::to_string(sd));
        }
    }
}

TEST(PrimitiveCounts, CylinderConeAndTorusCountsAndBoundsMatchTheMesh) {
    for (const glm::dvec3& axis : {glm::dvec3(0, 1, 0), glm::dvec3(1, 2, 3), glm::dvec3(0, -1, 0)}) {
        for (bool uvs : {true, false}) {
            for (auto [sa, sh, sc] : {std::tuple{20, 1, 1}, std::tuple{8, 3, 0}, std::tuple{5, 2, 3}, std::tuple{1, 0, -1}}) {
                const std::string what = std::to_string(sa) + "x" + std::to_string(sh) + "x" + std::to_string(sc) +
                                         (uvs ? " uvs" : "");
                PolyCylinderParams cylinder;
                cylinder.radius = 0.8;
                cylinder.height = 3.0;
                cylinder.subdivisionsAxis = sa;
                cylinder.subdivisionsHeight = sh;
                cylinder.subdivisionsCaps = sc;
                cylinder.axis = axis;
                cylinder.createUVs = uvs;
                expectCountsMatch(polyCylinderCounts(cylinder), makePolyCylinder(cylinder), false, "cylinder " + what);
                PolyConeParams cone;
                cone.radius = 1.3;
                cone.height = 2.0;
                cone.subdivisionsAxis = sa;
                cone.subdivisionsHeight = sh;
                cone.subdivisionsCap = sc;
                cone.axis = axis;
                cone.createUVs = uvs;
                expectCountsMatch(polyConeCounts(cone), makePolyCone(cone), false, "cone " + what);
                if (uvs) {
                    EXPECT_EQ(polyCylinderCounts(cylinder)->uvs, makePolyCylinder(cylinder)->uvSets[0].uvs.size());
                    EXPECT_EQ(polyConeCounts(cone)->uvs, makePolyCone(cone)->uvSets[0].uvs.size());
                }
            }
            PolyTorusParams torus;
            torus.radius = 2.0;
            torus.sectionRadius = 0.6;
            torus.twistRadians = 0.7;
            torus.subdivisionsAxis = 17;
            torus.subdivisionsHeight = 9;
            torus.axis = axis;
            torus.createUVs = uvs;
            expectCountsMatch(polyTorusCounts(torus), makePolyTorus(torus), false, "torus");
            if (uvs) {
                EXPECT_EQ(polyTorusCounts(torus)->uvs, makePolyTorus(torus)->uvSets[0].uvs.size());
            }
        }
    }
    // A section as wide as the ring meets itself at the axis: no promise.
    PolyTorusParams fat;
    fat.radius = 1.0;
    fat.sectionRadius = 1.0;
    EXPECT_FALSE(polyTorusCounts(fat).has_value());
    PolyCylinderParams flat;
    flat.height = 0.0;
    EXPECT_FALSE(polyCylinderCounts(flat).has_value());
}

// Where the generator fails or may make degenerate faces, the counts vouch for nothing.
TEST(PrimitiveCounts, NothingIsPromisedForZeroBadOrExtremeSizes) {
    PolySphereParams sphere;
    for (double r : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 1e13}) {
        sphere.radius = r;
        EXPECT_FALSE(polySphereCounts(sphere).has_value()) << r;
    }
    sphere.radius = 1.0;
    sphere.subdivisionsAxis = 1 << 20;
    sphere.subdivisionsHeight = 1 << 20;  // past kMaxPrimitiveFaces
    EXPECT_FALSE(polySphereCounts(sphere).has_value());
    PolyPlaneParams plane;
    plane.width = 1e6;
    plane.height = 1e-3;  // cells a billion times longer than wide
    EXPECT_FALSE(polyPlaneCounts(plane).has_value());
    plane.width = plane.height = 1.0;
    plane.subdivisionsWidth = 1 << 20;  // cells a millionth of the plane
    plane.subdivisionsHeight = 1;
    EXPECT_FALSE(polyPlaneCounts(plane).has_value());
    PolyCubeParams cube;
    cube.depth = 0.0;
    EXPECT_FALSE(polyCubeCounts(cube).has_value());
}

}  // namespace
}  // namespace pushpin::geom
