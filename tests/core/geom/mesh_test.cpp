// Tests for core/geom/mesh.h.
#include "core/geom/mesh.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <random>
#include <unordered_map>
#include <limits>

namespace pushpin::geom {
namespace {

// Unit cube in Maya's polyCube layout (reference/ma-format.md).
Mesh unitCube() {
    Mesh m;
    m.points = {{-0.5f, -0.5f, 0.5f}, {0.5f, -0.5f, 0.5f},  {-0.5f, 0.5f, 0.5f},  {0.5f, 0.5f, 0.5f},
                {-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f},  {-0.5f, -0.5f, -0.5f}, {0.5f, -0.5f, -0.5f}};
    m.addFace({0, 1, 3, 2});
    m.addFace({2, 3, 5, 4});
    m.addFace({4, 5, 7, 6});
    m.addFace({6, 7, 1, 0});
    m.addFace({1, 7, 5, 3});
    m.addFace({6, 0, 2, 4});
    return m;
}

// A 2×2 square in the XY plane with a 1×1 square hole, facing +Z.
Mesh squareWithHole() {
    Mesh m;
    m.points = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0},
                {-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
    m.addFace({0, 1, 2, 3});
    const uint32_t hole[] = {4, 7, 6, 5};  // clockwise seen from +Z
    m.addHole(hole);
    return m;
}

// The flat edge table answers as a map does: the first index stored for a key stays, through
// every growth, for keys spread anywhere in the 64-bit range.
TEST(EdgeIndex, KeepsTheFirstIndexOfEveryKeyThroughGrowth) {
    std::mt19937_64 rng(5);
    std::unordered_map<uint64_t, uint32_t> want;
    EdgeIndex index;  // starts small: grows many times
    for (uint32_t i = 0; i < 200000; ++i) {
        const uint32_t a = uint32_t(rng() % 5000), b = uint32_t(rng() % (i % 7 == 0 ? 0xffffffffu : 5000));
        if (a == b) continue;
        const uint64_t key = edgeKey(a, b);
        bool inserted = false;
        const uint32_t got = index.emplace(key, i, &inserted);
        const auto [it, fresh] = want.emplace(key, i);
        ASSERT_EQ(inserted, fresh);
        ASSERT_EQ(got, it->second);
    }
    for (const auto& [key, value] : want) ASSERT_EQ(index.find(key, ~0u), value);
    EXPECT_EQ(index.find(edgeKey(6000, 7000), 99u), 99u);
    EXPECT_GT(want.size(), 100000u);
}

TEST(EdgeSmoothness, FindsListedEdgesEitherWayRoundAndTheLastEntryDecides) {
    Mesh m;
    m.points.resize(6);
    m.edges = {{0, 1, true}, {2, 1, false}, {3, 4, true}, {4, 3, false}, {5, 9, false}, {2, 2, false}};
    const EdgeSmoothness s(m);
    using Kind = EdgeSmoothness::Kind;
    EXPECT_EQ(s.find(0, 1), Kind::Smooth);
    EXPECT_EQ(s.find(1, 0), Kind::Smooth);
    EXPECT_EQ(s.find(1, 2), Kind::Hard);
    EXPECT_EQ(s.find(3, 4), Kind::Hard);  // listed twice: the last entry
    EXPECT_EQ(s.find(0, 2), Kind::Unlisted);
    EXPECT_EQ(s.find(5, 9), Kind::Unlisted);  // a point out of range is left out
    EXPECT_EQ(s.find(2, 2), Kind::Unlisted);
    EXPECT_EQ(s.find(70, 80), Kind::Unlisted);
}

TEST(Mesh, EmptyMeshIsValidAndHasEmptyBounds) {
    Mesh m;
    EXPECT_TRUE(m.empty());
    EXPECT_EQ(m.faceCount(), 0u);
    EXPECT_EQ(m.loopCount(), 0u);
    EXPECT_TRUE(m.bounds().empty());
    EXPECT_TRUE(m.validate().ok());
    EXPECT_DOUBLE_EQ(m.signedVolume(), 0.0);
    EXPECT_TRUE(m.shadingNormals().empty());
}

TEST(Mesh, CubeNormalsPointOutwardAndVolumeIsOne) {
    const Mesh m = unitCube();
    ASSERT_TRUE(m.validate().ok());
    EXPECT_TRUE(m.validate().degenerateFaces.empty());
    const glm::dvec3 expected[] = {{0, 0, 1}, {0, 1, 0}, {0, 0, -1}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}};
    for (size_t f = 0; f < 6; ++f) {
        const glm::dvec3 n = m.faceNormal(f);
        EXPECT_NEAR(glm::length(n - expected[f]), 0.0, 1e-12) << "face " << f;
        EXPECT_NEAR(glm::length(m.faceAreaVector(f)), 1.0, 1e-12);
    }
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-12);
    const Bounds3 b = m.bounds();
    EXPECT_EQ(b.lo, glm::dvec3(-0.5));
    EXPECT_EQ(b.hi, glm::dvec3(0.5));
}

TEST(Mesh, HoleSubtractsAreaAndKeepsNormal) {
    const Mesh m = squareWithHole();
    ASSERT_TRUE(m.validate().ok());
    EXPECT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.loopCount(), 2u);
    EXPECT_EQ(m.holeCount(0), 1u);
    EXPECT_EQ(m.faceVertexBegin(0), 0u);
    EXPECT_EQ(m.faceVertexEnd(0), 8u);
    EXPECT_NEAR(m.faceAreaVector(0).z, 3.0, 1e-9);
    EXPECT_NEAR(glm::length(m.faceNormal(0) - glm::dvec3(0, 0, 1)), 0.0, 1e-12);
}

TEST(Mesh, AddFaceExtendsPerFaceVertexArrays) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    m.addFace({0, 1, 2});
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.uvSets.push_back({"map1", {{0, 0}, {1, 0}, {0, 1}}, {0, 1, 2}});
    m.addFace({1, 3, 2});
    EXPECT_EQ(m.normals.size(), 6u);
    EXPECT_EQ(m.normals[4], glm::vec3(0.0f));
    ASSERT_EQ(m.uvSets[0].faceVertexUvs.size(), 6u);
    EXPECT_EQ(m.uvSets[0].faceVertexUvs[5], -1);
    EXPECT_TRUE(m.validate().ok());
}

TEST(Mesh, ValidationReportsBadIndicesWithoutThrowing) {
    Mesh m = unitCube();
    m.faceVertices[5] = 99;
    MeshValidation v = m.validate();
    ASSERT_FALSE(v.ok());
    EXPECT_NE(v.errors[0].find("point 99"), std::string::npos) << v.errors[0];

    Mesh offsets = unitCube();
    offsets.loopStarts.back() = 3;
    EXPECT_FALSE(offsets.validate().ok());

    Mesh uv = unitCube();
    uv.uvSets.push_back({"map1", {{0, 0}}, std::vector<int32_t>(24, 0)});
    uv.uvSets[0].faceVertexUvs[7] = 4;
    v = uv.validate();
    ASSERT_FALSE(v.ok());
    EXPECT_NE(v.errors[0].find("uv 4"), std::string::npos) << v.errors[0];

    Mesh shortNormals = unitCube();
    shortNormals.normals.resize(5);
    EXPECT_FALSE(shortNormals.validate().ok());

    Mesh nan = unitCube();
    nan.points[3].x = std::numeric_limits<float>::quiet_NaN();
    v = nan.validate();
    ASSERT_FALSE(v.ok());
    EXPECT_NE(v.errors[0].find("not finite"), std::string::npos);

    Mesh emptyFace = unitCube();
    emptyFace.faceLoopStarts.push_back(emptyFace.faceLoopStarts.back());
    EXPECT_FALSE(emptyFace.validate().ok());
}

TEST(Mesh, DegenerateFacesAreListedNotFatal) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
    m.addFace({0, 1, 2});     // collinear
    m.addFace({0, 1, 1});     // repeated point
    m.addFace({0, 1});        // two points
    m.addFace({0, 1, 3});     // fine
    const MeshValidation v = m.validate();
    EXPECT_TRUE(v.ok());
    EXPECT_EQ(v.degenerateFaces, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(m.faceNormal(0), glm::dvec3(0.0));
    EXPECT_EQ(m.faceNormal(2), glm::dvec3(0.0));
    // Shading normals of degenerate faces stay finite.
    for (const glm::vec3& n : m.shadingNormals()) EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y));
}

TEST(Mesh, DegenerateFacesOfALargeMeshAreListedInFaceOrder) {
    // 300 × 300 quads, checked in runs on all threads: every kind of degenerate face, spread over
    // the runs, comes back once, in face order.
    constexpr uint32_t kSide = 300;
    Mesh m;
    for (uint32_t j = 0; j <= kSide; ++j)
        for (uint32_t i = 0; i <= kSide; ++i) m.points.push_back(glm::vec3(float(i), float((i * j) % 7) * 0.1f, float(j)));
    std::mt19937 rng(11);
    std::vector<uint32_t> want;
    for (uint32_t j = 0; j < kSide; ++j)
        for (uint32_t i = 0; i < kSide; ++i) {
            const uint32_t a = j * (kSide + 1) + i, b = a + kSide + 1, c = b + 1, d = a + 1;
            const uint32_t f = uint32_t(m.faceCount());
            switch (rng() % 97) {
            case 0: m.addFace({a, b, b, a}); want.push_back(f); break;     // two distinct points
            case 1: m.addFace({a, d, a}); want.push_back(f); break;        // a triangle folded flat
            case 2: m.addFace({a, b, a, b, a}); want.push_back(f); break;  // n-gon of two distinct points
            default: m.addFace({a, b, c, d}); break;
            }
        }
    ASSERT_GT(m.faceCount(), 4u * 16384u);
    ASSERT_GT(want.size(), 1000u);
    const MeshValidation v = m.validate();
    EXPECT_TRUE(v.ok());
    EXPECT_EQ(v.degenerateFaces, want);
}

TEST(Mesh, DeriveEdgesFindsTwelveCubeEdges) {
    Mesh m = unitCube();
    const std::vector<MeshEdge> edges = deriveEdges(m, false);
    EXPECT_EQ(edges.size(), 12u);
    for (const MeshEdge& e : edges) EXPECT_FALSE(e.smooth);
    m.edges = {{0, 1, true}};
    completeEdges(m, false);
    EXPECT_EQ(m.edges.size(), 12u);
    EXPECT_TRUE(m.edges[0].smooth);
    EXPECT_EQ(findEdge(m, 1, 0), 0);
    EXPECT_EQ(findEdge(m, 0, 5), -1);
}

TEST(Mesh, ShadingNormalsFollowHardAndSoftEdges) {
    Mesh hard = unitCube();
    hard.edges = deriveEdges(hard, false);
    const std::vector<glm::vec3> flat = hard.shadingNormals();
    ASSERT_EQ(flat.size(), 24u);
    for (size_t f = 0; f < 6; ++f)
        for (uint32_t c = hard.faceVertexBegin(f); c < hard.faceVertexEnd(f); ++c)
            EXPECT_NEAR(glm::length(glm::dvec3(flat[c]) - hard.faceNormal(f)), 0.0, 1e-6);

    Mesh soft = unitCube();  // no edge list: every edge soft, normals point along the corners
    const std::vector<glm::vec3> smooth = soft.shadingNormals();
    for (size_t c = 0; c < smooth.size(); ++c) {
        const glm::dvec3 corner = glm::normalize(glm::dvec3(soft.points[soft.faceVertices[c]]));
        EXPECT_NEAR(glm::length(glm::dvec3(smooth[c]) - corner), 0.0, 1e-6);
    }

    soft.normals.assign(24, glm::vec3(0.0f));
    soft.normals[3] = glm::vec3(0, 0, 1);  // a stored normal wins
    EXPECT_EQ(soft.shadingNormals()[3], glm::vec3(0, 0, 1));
}

TEST(Mesh, TransformMovesPointsAndNormals) {
    Mesh m = unitCube();
    m.normals.assign(24, glm::vec3(0.0f));
    m.normals[0] = glm::vec3(0, 0, 1);
    const glm::dmat4 t = glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2, 1, 4));
    transformMesh(m, t);
    const Bounds3 b = m.bounds();
    EXPECT_NEAR(b.lo.x, 9.0, 1e-6);
    EXPECT_NEAR(b.hi.x, 11.0, 1e-6);
    EXPECT_NEAR(b.hi.z, 2.0, 1e-6);
    EXPECT_NEAR(m.signedVolume(), 8.0, 1e-5);
    EXPECT_NEAR(glm::length(glm::dvec3(m.normals[0]) - glm::dvec3(0, 0, 1)), 0.0, 1e-6);
    EXPECT_EQ(m.normals[1], glm::vec3(0.0f));
}

TEST(Mesh, DeleteFacesCompactsPointsAndKeepsAttributes) {
    Mesh m = unitCube();
    m.edges = deriveEdges(m, false);
    m.edges[0].smooth = true;  // edge 0-1, used by faces 0 and 3
    m.uvSets.push_back({"map1", {{0, 0}}, std::vector<int32_t>(24, 0)});
    m.normals.assign(24, glm::vec3(0.0f));
    m.normals[4] = glm::vec3(0, 1, 0);  // first face-vertex of face 1
    std::vector<bool> remove(6, false);
    remove[0] = true;
    deleteFaces(m, remove);
    EXPECT_EQ(m.faceCount(), 5u);
    EXPECT_EQ(m.points.size(), 8u);
    EXPECT_EQ(m.normals.size(), 20u);
    EXPECT_EQ(m.normals[0], glm::vec3(0, 1, 0));
    EXPECT_EQ(m.uvSets[0].faceVertexUvs.size(), 20u);
    EXPECT_EQ(m.edges.size(), 12u);
    EXPECT_TRUE(m.validate().ok());

    // Removing every face touching point 0 leaves 7 points, renumbered.
    Mesh c = unitCube();
    std::vector<bool> touching(6, false);
    for (size_t f = 0; f < 6; ++f)
        for (uint32_t v : c.faceOuterLoop(f))
            if (v == 0) touching[f] = true;
    deleteFaces(c, touching);
    EXPECT_EQ(c.faceCount(), 3u);
    EXPECT_EQ(c.points.size(), 7u);
    EXPECT_TRUE(c.validate().ok());
    for (const glm::vec3& p : c.points) EXPECT_NE(p, glm::vec3(-0.5f, -0.5f, 0.5f));

    Mesh all = unitCube();
    deleteFaces(all, std::vector<bool>(6, true));
    EXPECT_TRUE(all.empty());
    EXPECT_TRUE(all.points.empty());
    EXPECT_TRUE(all.validate().ok());
}

TEST(Mesh, RemoveUnusedPointsRenumbers) {
    Mesh m;
    m.points = {{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.addFace({1, 2, 3});
    m.edges = {{0, 1, true}, {1, 2, false}};
    EXPECT_EQ(removeUnusedPoints(m), 1u);
    EXPECT_EQ(m.faceVertices, (std::vector<uint32_t>{0, 1, 2}));
    ASSERT_EQ(m.edges.size(), 1u);
    EXPECT_EQ(m.edges[0].v0, 0u);
    EXPECT_FALSE(m.edges[0].smooth);
}

Mesh uvQuad(const std::string& set) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.addFace({0, 1, 2, 3});
    m.uvSets.push_back({set, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {0, 1, 2, 3}});
    return m;
}

TEST(AppendMesh, JoinsUvSetsByNameAndTransformsPoints) {
    Mesh into = uvQuad("map1");
    Mesh same = uvQuad("map1"), other = uvQuad("extra");
    ASSERT_TRUE(appendMesh(into, same, glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 2))));
    ASSERT_TRUE(appendMesh(into, other, glm::dmat4(1.0)));
    EXPECT_EQ(into.points.size(), 12u);
    EXPECT_EQ(into.faceCount(), 3u);
    EXPECT_FLOAT_EQ(into.points[4].z, 2.0f);
    ASSERT_EQ(into.uvSets.size(), 2u);
    const UvSet& map1 = into.uvSets[0];
    ASSERT_EQ(map1.faceVertexUvs.size(), 12u);
    EXPECT_EQ(map1.uvs.size(), 8u);
    EXPECT_EQ(map1.faceVertexUvs[4], 4);   // the second quad's UVs follow the first's
    EXPECT_EQ(map1.faceVertexUvs[8], -1);  // the third quad has no map1 UVs
    ASSERT_EQ(into.uvSets[1].faceVertexUvs.size(), 12u);
    EXPECT_EQ(into.uvSets[1].faceVertexUvs[0], -1);
    EXPECT_EQ(into.uvSets[1].faceVertexUvs[8], 0);
    EXPECT_TRUE(into.validate().ok());
}

TEST(FaceShells, FacesJoinedThroughPointsShareAShell) {
    Mesh m = uvQuad("map1");
    appendMesh(m, uvQuad("map1"), glm::translate(glm::dmat4(1.0), glm::dvec3(5, 0, 0)));
    m.addFace({1, 4, 2});  // touches the first quad only (point 4 is the second quad's first)
    std::vector<uint32_t> shell;
    EXPECT_EQ(faceShells(m, shell), 1u);  // the triangle joins both quads into one shell
    Mesh apart = uvQuad("map1");
    appendMesh(apart, uvQuad("map1"), glm::translate(glm::dmat4(1.0), glm::dvec3(5, 0, 0)));
    EXPECT_EQ(faceShells(apart, shell), 2u);
    EXPECT_EQ(shell, (std::vector<uint32_t>{0, 1}));
}

}  // namespace
}  // namespace pushpin::geom
