// Tests for core/geom/tessellation.h and core/geom/geometry_handle.h: mesh triangulation (area,
// winding, normals, uvs, adjacency), shared vertices, the counts known before tessellating, NURBS
// grids, and handles that tessellate once for every instance.
#include "core/geom/geometry_handle.h"
#include "core/geom/nurbs_primitives.h"
#include "core/geom/poly_primitives.h"
#include "core/geom/tessellation.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

namespace pushpin::geom {
namespace {

double triangleArea(const Tessellation& g, size_t t) {
    const glm::dvec3 a(g.position(3 * t)), b(g.position(3 * t + 1)), c(g.position(3 * t + 2));
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

glm::dvec3 triangleNormal(const Tessellation& g, size_t t) {
    const glm::dvec3 a(g.position(3 * t)), b(g.position(3 * t + 1)), c(g.position(3 * t + 2));
    return glm::cross(b - a, c - a);
}

// Two unit quads side by side in the z = 0 plane sharing the edge 1–4.
Mesh twoQuads() {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
    m.addFace({0, 1, 4, 3});
    m.addFace({1, 2, 5, 4});
    completeEdges(m, true);
    return m;
}

// The neighbour entry of triangle t across the edge joining points a and b (by position), or
// nullopt when t has no such edge.
std::optional<uint32_t> neighborAcross(const Tessellation& g, size_t t, glm::vec3 a, glm::vec3 b) {
    for (size_t k = 0; k < 3; ++k) {
        const glm::vec3 p = g.position(3 * t + k), q = g.position(3 * t + (k + 1) % 3);
        if ((p == a && q == b) || (p == b && q == a)) return g.neighbors[3 * t + k];
    }
    return std::nullopt;
}

// ------------------------------------------------------------------ triangulateMesh

TEST(TriangulateMesh, SquareFaceGivesTwoTrianglesWithFaceNormals) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.addFace({0, 1, 2, 3});
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 2u);
    // The four corners are shared: 4 vertices, 6 corners.
    ASSERT_EQ(g.vertexCount(), 4u);
    ASSERT_EQ(g.normals.size(), 4u);
    ASSERT_EQ(g.corners.size(), 6u);
    EXPECT_TRUE(g.uvs.empty());
    double area = 0.0;
    for (size_t t = 0; t < 2; ++t) {
        area += triangleArea(g, t);
        EXPECT_GT(triangleNormal(g, t).z, 0.0) << "triangles wind like the face";
        EXPECT_EQ(g.face[t], 0u);
        EXPECT_EQ(g.material[t], 0u);
    }
    EXPECT_NEAR(area, 1.0, 1e-9);
    for (const glm::vec3& n : g.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    EXPECT_EQ(g.bounds.lo, glm::dvec3(0, 0, 0));
    EXPECT_EQ(g.bounds.hi, glm::dvec3(1, 1, 0));
    // The diagonal is a soft edge between the two triangles; the outline is boundary.
    int inner = 0, boundary = 0;
    for (uint32_t n : g.neighbors) {
        if (n == kNoNeighbor) ++boundary;
        else {
            EXPECT_EQ(n & kHardNeighborBit, 0u);
            ++inner;
        }
    }
    EXPECT_EQ(inner, 2);
    EXPECT_EQ(boundary, 4);
}

TEST(TriangulateMesh, ConcaveLShapeConservesArea) {
    Mesh m;
    m.points = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    m.addFace({0, 1, 2, 3, 4, 5});
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 4u);
    double area = 0.0;
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        area += triangleArea(g, t);
        EXPECT_GT(triangleNormal(g, t).z, 0.0);
    }
    EXPECT_NEAR(area, glm::length(m.faceAreaVector(0)), 1e-9);
}

TEST(TriangulateMesh, FaceWithHoleConservesArea) {
    Mesh m;
    m.points = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}};
    m.addFace({0, 1, 2, 3});
    const uint32_t hole[] = {4, 5, 6, 7};
    m.addHole(hole);
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 8u);
    double area = 0.0;
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        area += triangleArea(g, t);
        EXPECT_GT(triangleNormal(g, t).z, 0.0);
    }
    EXPECT_NEAR(area, 12.0, 1e-9);
    EXPECT_NEAR(area, glm::length(m.faceAreaVector(0)), 1e-9);
}

TEST(TriangulateMesh, DropsDegenerateFaces) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {3, 0, 0}};
    m.addFace({0, 1, 2});
    m.addFace({1, 3, 4});  // collinear
    m.addFace({0, 0, 1});  // repeated point
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 1u);
    EXPECT_EQ(g.face[0], 0u);
}

TEST(TriangulateMesh, NonFinitePointsGiveNoGeometry) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, std::numeric_limits<float>::quiet_NaN(), 0}};
    m.addFace({0, 1, 2});
    EXPECT_EQ(triangulateMesh(m, {}, true).triangleCount(), 0u);
    m.points[2] = {1, std::numeric_limits<float>::infinity(), 0};
    EXPECT_EQ(triangulateMesh(m, {}, true).triangleCount(), 0u);
    EXPECT_EQ(triangulateMesh(Mesh{}, {}, true).triangleCount(), 0u);
}

TEST(TriangulateMesh, SoftEdgeJoinsFacesWithoutTheHardBit) {
    const Mesh m = twoQuads();
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 4u);
    int across = 0;
    for (size_t t = 0; t < 4; ++t)
        if (auto n = neighborAcross(g, t, m.points[1], m.points[4])) {
            ASSERT_NE(*n, kNoNeighbor);
            EXPECT_EQ(*n & kHardNeighborBit, 0u);
            EXPECT_NE(g.face[*n & ~kHardNeighborBit], g.face[t]);
            ++across;
        }
    EXPECT_EQ(across, 2);
    // Smooth normals: the shared points average to +z as well (a flat sheet).
    for (const glm::vec3& n : g.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

TEST(TriangulateMesh, HardEdgeSetsTheHardBit) {
    Mesh m = twoQuads();
    m.edges[size_t(findEdge(m, 1, 4))].smooth = false;
    const Tessellation g = triangulateMesh(m, {}, true);
    int across = 0;
    for (size_t t = 0; t < g.triangleCount(); ++t)
        if (auto n = neighborAcross(g, t, m.points[1], m.points[4])) {
            ASSERT_NE(*n, kNoNeighbor);
            EXPECT_NE(*n & kHardNeighborBit, 0u);
            ++across;
        }
    EXPECT_EQ(across, 2);
}

TEST(TriangulateMesh, MaterialBorderIsHard) {
    const Mesh m = twoQuads();
    const Tessellation g = triangulateMesh(m, {0, 1}, true);
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        EXPECT_EQ(g.material[t], g.face[t]);
        if (auto n = neighborAcross(g, t, m.points[1], m.points[4])) {
            EXPECT_NE(*n & kHardNeighborBit, 0u);
        }
    }
}

TEST(TriangulateMesh, FlatShadingUsesFaceNormalsAndHardEdges) {
    Mesh m = twoQuads();
    m.points[2].z = 1.0f;  // fold the second quad up
    m.points[5].z = 1.0f;
    const Tessellation smooth = triangulateMesh(m, {}, true);
    const Tessellation flat = triangulateMesh(m, {}, false);
    ASSERT_EQ(flat.triangleCount(), 4u);
    for (size_t t = 0; t < flat.triangleCount(); ++t) {
        const glm::vec3 fn(glm::normalize(triangleNormal(flat, t)));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(glm::dot(flat.normal(3 * t + k), fn), 1.0f, 1e-5f);
        if (auto n = neighborAcross(flat, t, m.points[1], m.points[4])) {
            EXPECT_NE(*n & kHardNeighborBit, 0u);
        }
    }
    // Smooth shading averages the two faces at the fold.
    bool averaged = false;
    for (size_t c = 0; c < smooth.positions.size(); ++c)
        if (smooth.positions[c] == m.points[1]) averaged |= smooth.normals[c].z < 0.99f && smooth.normals[c].z > 0.5f;
    EXPECT_TRUE(averaged);
}

TEST(TriangulateMesh, NonManifoldEdgeHasNoNeighbour) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.addFace({0, 1, 2});
    m.addFace({1, 0, 3});
    m.addFace({0, 1, 4});
    const Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.triangleCount(), 3u);
    for (size_t t = 0; t < 3; ++t) {
        auto n = neighborAcross(g, t, m.points[0], m.points[1]);
        ASSERT_TRUE(n.has_value());
        EXPECT_EQ(*n, kNoNeighbor);
    }
}

TEST(TriangulateMesh, UvsComeFromTheCurrentSetAndDefaultToZero) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    m.addFace({0, 1, 2});
    m.uvSets.push_back({"map1", {{0.1f, 0.2f}}, {0, -1, 0}});
    m.uvSets.push_back({"other", {{0.5f, 0.5f}, {0.7f, 0.7f}}, {1, 1, 1}});
    m.currentUvSet = 1;
    Tessellation g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.uvs.size(), 3u);
    for (const glm::vec2& uv : g.uvs) EXPECT_EQ(uv, glm::vec2(0.7f, 0.7f));
    m.currentUvSet = 0;
    g = triangulateMesh(m, {}, true);
    ASSERT_EQ(g.uvs.size(), 3u);
    for (size_t c = 0; c < 3; ++c) {
        const glm::vec2 expected = g.positions[c] == m.points[1] ? glm::vec2(0.0f) : glm::vec2(0.1f, 0.2f);
        EXPECT_EQ(g.uvs[c], expected);
    }
}

TEST(TriangulateMesh, FacesWithoutMaterialAreDropped) {
    const Mesh m = twoQuads();
    const Tessellation g = triangulateMesh(m, {kNoFaceMaterial, 3}, true);
    ASSERT_EQ(g.triangleCount(), 2u);
    for (size_t t = 0; t < 2; ++t) {
        EXPECT_EQ(g.face[t], 1u);
        EXPECT_EQ(g.material[t], 3u);
    }
    // The shared edge is now a boundary.
    for (size_t t = 0; t < 2; ++t)
        if (auto n = neighborAcross(g, t, m.points[1], m.points[4])) {
            EXPECT_EQ(*n, kNoNeighbor);
        }
}

// ------------------------------------------------------------------ shared vertices and counts

// Every corner names a vertex; positions, normals and uvs per corner are those of its vertex.
void expectWellFormed(const Tessellation& g) {
    ASSERT_EQ(g.corners.size(), 3 * g.triangleCount());
    ASSERT_EQ(g.neighbors.size(), 3 * g.triangleCount());
    ASSERT_EQ(g.material.size(), g.triangleCount());
    ASSERT_EQ(g.normals.size(), g.vertexCount());
    if (!g.uvs.empty()) {
        ASSERT_EQ(g.uvs.size(), g.vertexCount());
    }
    for (uint32_t v : g.corners) ASSERT_LT(v, g.vertexCount());
    for (const glm::vec3& p : g.positions) {
        EXPECT_GE(double(p.x), g.bounds.lo.x);
        EXPECT_LE(double(p.x), g.bounds.hi.x);
    }
}

TEST(Tessellation, SmoothSphereSharesVerticesExceptAtUvSeamsAndPoles) {
    PolySphereParams p;
    p.subdivisionsAxis = 24;
    p.subdivisionsHeight = 12;
    const std::optional<Mesh> m = makePolySphere(p);
    ASSERT_TRUE(m);
    const Tessellation g = triangulateMesh(*m, {}, true);
    expectWellFormed(g);
    EXPECT_EQ(g.triangleCount(), size_t(2 * 24 * 12 - 2 * 24));
    // One vertex per point, one more per ring where the uv seam splits it, and one per pole
    // triangle (each has its own pole uv): far fewer than the 3 per triangle of a corner list.
    const size_t points = m->points.size();
    EXPECT_EQ(g.vertexCount(), points + (12 - 1) + 2 * 24 - 2);
    EXPECT_LT(double(g.vertexCount()) / double(g.triangleCount()), 0.65);
    // The corner values are exactly the mesh's: each corner sits on a mesh point.
    for (size_t c = 0; c < g.corners.size(); ++c) {
        bool onPoint = false;
        for (const glm::vec3& q : m->points) onPoint |= q == g.position(c);
        ASSERT_TRUE(onPoint) << "corner " << c;
    }
}

TEST(Tessellation, HardEdgesSplitVerticesAndFlatShadingGivesOnePerFaceCorner) {
    PolyCubeParams p;
    const std::optional<Mesh> cube = makePolyCube(p);
    ASSERT_TRUE(cube);
    Mesh noUv = *cube;
    noUv.uvSets.clear();
    const Tessellation flat = triangulateMesh(noUv, {}, false);
    expectWellFormed(flat);
    EXPECT_EQ(flat.triangleCount(), 12u);
    EXPECT_EQ(flat.vertexCount(), 24u) << "each of 8 points has 3 face normals";
}

TEST(Tessellation, MeshTriangleCountMatchesTheTriangulation) {
    Mesh m;
    m.points = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0},
                {5, 0, 0}, {6, 0, 0}, {6, 1, 0}, {5, 1, 0}, {5.5f, 2, 0}};
    m.addFace({0, 1, 2, 3});
    const uint32_t hole[] = {4, 5, 6, 7};
    m.addHole(hole);
    m.addFace({8, 9, 10, 12, 11});
    m.addFace({8, 9, 10});
    const std::vector<uint16_t> materials = {0, 1, kNoFaceMaterial};
    const Tessellation g = triangulateMesh(m, materials, true);
    EXPECT_EQ(meshTriangleCount(m, materials, {}), g.triangleCount());
    EXPECT_EQ(meshTriangleCount(m, materials, {}), 8u + 3u);
    EXPECT_EQ(meshTriangleCount(m, {}, {}), 8u + 3u + 1u);
    EXPECT_EQ(meshTriangleCount(m, {}, {false, true, false}), 8u + 1u);
}

TEST(Tessellation, ClusterBoundsHoldTheirTriangles) {
    PolySphereParams p;
    p.subdivisionsAxis = 30;
    p.subdivisionsHeight = 7;  // 360 triangles: five full clusters and a short one
    const Tessellation g = triangulateMesh(*makePolySphere(p), {}, true);
    ASSERT_EQ(g.triangleCount(), 360u);
    ASSERT_EQ(g.clusterBounds.size(), 6u);
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        const Bounds3& b = g.clusterBounds[t / Tessellation::kClusterTriangles];
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 q(g.position(3 * t + size_t(k)));
            ASSERT_TRUE(q.x >= b.lo.x && q.y >= b.lo.y && q.z >= b.lo.z && q.x <= b.hi.x && q.y <= b.hi.y && q.z <= b.hi.z)
                << "triangle " << t;
        }
    }
    // Tight: a cluster's box is the box of its corners, so it is much smaller than the sphere's.
    EXPECT_LT(g.clusterBounds[2].size().y, 0.5 * g.bounds.size().y);
    EXPECT_TRUE(triangulateMesh(Mesh{}, {}, true).clusterBounds.empty());
}

TEST(Tessellation, BytesCountEveryArray) {
    const Tessellation g = triangulateMesh(*makePolySphere(PolySphereParams{}), {}, true);
    const uint64_t atLeast = g.positions.size() * 12 + g.normals.size() * 12 + g.uvs.size() * 8 +
                             g.corners.size() * 4 + g.face.size() * 4 + g.material.size() * 2 + g.neighbors.size() * 4;
    EXPECT_GE(g.bytes(), atLeast);
    EXPECT_LT(g.bytes(), 2 * atLeast);
    EXPECT_EQ(Tessellation{}.bytes(), 0u);
}

TEST(Tessellation, NurbsSphereGridIsIndexedWithinItsCountAndAdjacentAcrossTheSeam) {
    NurbsSphereParams p;
    p.sections = 8;
    p.spans = 4;
    std::string error;
    const std::optional<NurbsSurface> s = makeNurbSphere(p, &error);
    ASSERT_TRUE(s) << error;
    std::string problem;
    const std::optional<Tessellation> g = tessellateNurbs(*s, 3, 2, problem);
    ASSERT_TRUE(g) << problem;
    expectWellFormed(*g);
    const uint64_t bound = nurbsTriangleCount(*s, 3, 2);
    EXPECT_EQ(bound, uint64_t(2 * (8 * 3) * (4 * 2)));
    EXPECT_EQ(g->triangleCount(), bound) << "two triangle ids a cell, the poles' included";
    // A closed sphere: every edge of a triangle of nonzero area has a neighbour once seams and
    // poles are welded.
    for (size_t t = 0; t < g->triangleCount(); ++t)
        if (g->corners[3 * t] != g->corners[3 * t + 1] || g->corners[3 * t] != g->corners[3 * t + 2]) {
            for (int k = 0; k < 3; ++k) EXPECT_NE(g->neighbors[3 * t + size_t(k)], kNoNeighbor);
        }
    // One vertex per grid point used: (8·3 + 1) × (4·2 + 1) at most.
    EXPECT_LE(g->vertexCount(), size_t(25 * 9));
    for (const glm::vec3& n : g->normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

// ------------------------------------------------------------------ GeometryHandle

std::shared_ptr<const Mesh> sharedSphere(int axis, int height) {
    PolySphereParams p;
    p.subdivisionsAxis = axis;
    p.subdivisionsHeight = height;
    return std::make_shared<const Mesh>(*makePolySphere(p));
}

TEST(GeometryHandle, KnowsBoundsAndTrianglesBeforeTessellating) {
    const auto mesh = sharedSphere(16, 8);
    const auto h = GeometryHandle::fromMesh(mesh, {}, nullptr, true);
    EXPECT_EQ(h->triangleCount(), uint64_t(2 * 16 * 8 - 2 * 16));
    EXPECT_NEAR(h->bounds().lo.x, -1.0, 1e-6);
    EXPECT_NEAR(h->bounds().hi.y, 1.0, 1e-6);
    EXPECT_EQ(h->materialCount(), 1u);
    EXPECT_GT(h->sourceBytes(), mesh->points.size() * sizeof(glm::vec3));
    const Tessellation t = h->tessellate();
    EXPECT_EQ(t.triangleCount(), h->triangleCount());
    EXPECT_GE(t.bounds.lo.x, h->bounds().lo.x);
    EXPECT_LE(t.bounds.hi.x, h->bounds().hi.x);
    // The estimate is within a factor of two of what the tessellation holds.
    EXPECT_GT(h->tessellationBytesEstimate(), t.bytes() / 2);
    EXPECT_LT(h->tessellationBytesEstimate(), t.bytes() * 2);
}

TEST(GeometryHandle, UnassignedFacesLeaveTheBoundsAndTheCount) {
    Mesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {10, 10, 10}, {11, 10, 10}, {11, 11, 10}};
    m.addFace({0, 1, 2});
    m.addFace({3, 4, 5});
    const auto h = GeometryHandle::fromMesh(std::make_shared<const Mesh>(m), {2, kNoFaceMaterial}, nullptr, true);
    EXPECT_EQ(h->triangleCount(), 1u);
    EXPECT_EQ(h->materialCount(), 3u);
    EXPECT_EQ(h->bounds().hi, glm::dvec3(1, 1, 0));
}

TEST(GeometryHandle, TessellatesTheSameWhateverTheThread) {
    const auto h = GeometryHandle::fromMesh(sharedSphere(64, 32), {}, nullptr, true);
    std::vector<Tessellation> got(3);
    std::vector<std::thread> threads;
    for (size_t i = 0; i < got.size(); ++i) threads.emplace_back([&, i] { got[i] = h->tessellate(); });
    for (std::thread& t : threads) t.join();
    for (const Tessellation& g : got) {
        EXPECT_EQ(g.corners, got[0].corners);
        EXPECT_EQ(g.positions, got[0].positions);
        EXPECT_EQ(g.neighbors, got[0].neighbors);
    }
}

TEST(GeometryHandle, NurbsHandleCountsItsGridAndBoundsByTheHull) {
    NurbsSphereParams p;
    std::string error;
    auto s = makeNurbSphere(p, &error);
    ASSERT_TRUE(s) << error;
    const auto surface = std::make_shared<const NurbsSurface>(std::move(*s));
    const auto h = GeometryHandle::fromNurbs(surface, 4, 0);
    EXPECT_FALSE(h->isMesh());
    EXPECT_EQ(h->triangleCount(), nurbsTriangleCount(*surface, 4, 1)) << "divisions below 1 are 1";
    const Tessellation t = h->tessellate();
    EXPECT_LE(t.triangleCount(), h->triangleCount());
    EXPECT_GT(t.triangleCount(), 0u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(t.bounds.lo[k], h->bounds().lo[k] - 1e-6);
        EXPECT_LE(t.bounds.hi[k], h->bounds().hi[k] + 1e-6);
    }
}

TEST(GeometryHandle, TrianglesPerScanlineFollowsScreenSize) {
    const auto h = GeometryHandle::fromMesh(sharedSphere(100, 50), {}, nullptr, true);
    const double T = double(h->triangleCount());
    // Tiny on screen: every triangle on the one row.
    EXPECT_DOUBLE_EQ(h->trianglesPerScanline(0.5), T);
    EXPECT_DOUBLE_EQ(h->trianglesPerScanline(std::numeric_limits<double>::quiet_NaN()), T);
    // Huge on screen: about one grid row of triangles, sqrt(2T).
    EXPECT_NEAR(h->trianglesPerScanline(1e7), std::sqrt(2.0 * T), 0.01 * std::sqrt(2.0 * T));
    // Sub-pixel triangles: T spread over the rows, T / height.
    EXPECT_NEAR(h->trianglesPerScanline(20.0), T * (20.0 / std::sqrt(T / 2) + 1.0) / 20.0, 1e-9);
    double previous = T;
    for (double height : {2.0, 8.0, 32.0, 128.0, 512.0, 2048.0}) {
        const double c = h->trianglesPerScanline(height);
        EXPECT_LE(c, previous) << height;
        previous = c;
    }
    Mesh empty;
    EXPECT_EQ(GeometryHandle::fromMesh(std::make_shared<const Mesh>(empty), {}, nullptr, true)->trianglesPerScanline(10.0), 0.0);
}

TEST(CopyTriangles, KeepsWhatEachTriangleHasWithSharedVertices) {
    PolySphereParams p;
    p.subdivisionsAxis = 12;
    p.subdivisionsHeight = 8;
    const std::optional<Mesh> sphere = makePolySphere(p);
    ASSERT_TRUE(sphere);
    std::vector<uint16_t> material(sphere->faceCount(), 0);
    for (size_t f = 0; f < material.size(); f += 3) material[f] = 1;
    const Tessellation t = triangulateMesh(*sphere, material, true);
    ASSERT_GT(t.triangleCount(), 100u);
    ASSERT_FALSE(t.uvs.empty());
    const std::vector<uint32_t> kept = {0, 1, 2, 13, 14, 40, uint32_t(t.triangleCount() - 1)};
    const std::vector<uint32_t> vertices = triangleVertices(t, kept);
    EXPECT_TRUE(std::is_sorted(vertices.begin(), vertices.end()));
    EXPECT_EQ(std::adjacent_find(vertices.begin(), vertices.end()), vertices.end());
    EXPECT_LT(vertices.size(), 3 * kept.size());  // neighbouring triangles share theirs
    const Tessellation c = copyTriangles(t, kept, vertices);
    ASSERT_EQ(c.triangleCount(), kept.size());
    EXPECT_EQ(c.vertexCount(), vertices.size());
    EXPECT_EQ(c.bytes(), copiedTrianglesBytes(t, kept.size(), vertices.size()));
    for (size_t i = 0; i < kept.size(); ++i) {
        const size_t from = kept[i];
        EXPECT_EQ(c.face[i], t.face[from]);
        EXPECT_EQ(c.material[i], t.material[from]);
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(c.neighbors[3 * i + k], t.neighbors[3 * from + k]);
            EXPECT_EQ(c.position(3 * i + k), t.position(3 * from + k));
            EXPECT_EQ(c.normal(3 * i + k), t.normal(3 * from + k));
            EXPECT_EQ(c.uv(3 * i + k), t.uv(3 * from + k));
        }
    }
    const Tessellation none = copyTriangles(t, {}, triangleVertices(t, {}));
    EXPECT_EQ(none.triangleCount(), 0u);
    EXPECT_EQ(none.vertexCount(), 0u);
}

}  // namespace
}  // namespace pushpin::geom
