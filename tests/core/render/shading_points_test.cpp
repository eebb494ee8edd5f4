#include "core/render/shading_points.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <utility>

namespace pushpin::render {
namespace {

// The triangle (0,0,−5), (2,0,−5), (0,2,−5) facing the camera at the origin, normals tilted apart,
// uvs = (x, y) / 2.
ShadingTriangle facingTriangle() {
    ShadingTriangle t;
    t.p[0] = {0, 0, -5}, t.p[1] = {2, 0, -5}, t.p[2] = {0, 2, -5};
    t.n[0] = glm::normalize(glm::dvec3(-0.2, 0, 1));
    t.n[1] = glm::normalize(glm::dvec3(0.2, 0, 1));
    t.n[2] = glm::dvec3(0, 0, 1);
    t.uv[0] = {0, 0}, t.uv[1] = {1, 0}, t.uv[2] = {0, 1};
    t.hasUvs = true;
    return t;
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-12) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(ShadingPoints, TheRayMeetsThePlaneAtItsBarycentricPoint) {
    const ShadingTriangle t = facingTriangle();
    const glm::dvec3 target(0.5, 0.25, -5.0);
    const ShadingPoint s = shadingPointOn(t, glm::dvec3(0.0), glm::normalize(target));
    expectNear(s.position, target);
    EXPECT_NEAR(s.weight[0], 0.625, 1e-12);
    EXPECT_NEAR(s.weight[1], 0.25, 1e-12);
    EXPECT_NEAR(s.weight[2], 0.125, 1e-12);
    EXPECT_NEAR(s.uv.x, 0.25, 1e-12);
    EXPECT_NEAR(s.uv.y, 0.125, 1e-12);
    expectNear(s.geometricNormal, glm::dvec3(0, 0, 1));
    const glm::dvec3 ns = t.n[0] * 0.625 + t.n[1] * 0.25 + t.n[2] * 0.125;
    expectNear(s.shadingNormal, glm::normalize(ns));
    EXPECT_NEAR(glm::length(s.shadingNormal), 1.0, 1e-12);
    EXPECT_FALSE(s.flipped);
    // u grows along x, v along y, two units of position per unit of uv.
    expectNear(s.tangentU, glm::dvec3(2, 0, 0));
    expectNear(s.tangentV, glm::dvec3(0, 2, 0));
}

TEST(ShadingPoints, AHitJustOutsideIsPulledOntoTheTriangle) {
    const ShadingTriangle t = facingTriangle();
    const ShadingPoint s = shadingPointOn(t, glm::dvec3(0.0), glm::normalize(glm::dvec3(-0.01, 1.0, -5.0)));
    EXPECT_GE(s.weight[0], 0.0);
    EXPECT_EQ(s.weight[1], 0.0);
    EXPECT_GE(s.weight[2], 0.0);
    EXPECT_NEAR(s.weight[0] + s.weight[1] + s.weight[2], 1.0, 1e-12);
    EXPECT_EQ(s.position.x, 0.0);
    EXPECT_NEAR(s.position.z, -5.0, 1e-12);
}

TEST(ShadingPoints, ABackFaceTurnsItsNormalsToTheRay) {
    ShadingTriangle t = facingTriangle();
    std::swap(t.p[1], t.p[2]);  // now facing away, its vertex normals too
    std::swap(t.n[1], t.n[2]);
    for (glm::dvec3& n : t.n) n = -n;
    const ShadingPoint s = shadingPointOn(t, glm::dvec3(0.0), glm::normalize(glm::dvec3(0.5, 0.5, -5.0)));
    EXPECT_TRUE(s.flipped);
    expectNear(s.geometricNormal, glm::dvec3(0, 0, 1));
    EXPECT_GT(s.shadingNormal.z, 0.9);
    // The opposite flag turns them first: the same triangle then faces the ray.
    t.opposite = true;
    const ShadingPoint o = shadingPointOn(t, glm::dvec3(0.0), glm::normalize(glm::dvec3(0.5, 0.5, -5.0)));
    EXPECT_FALSE(o.flipped);
    expectNear(o.geometricNormal, glm::dvec3(0, 0, 1));
    EXPECT_GT(o.shadingNormal.z, 0.9);
}

TEST(ShadingPoints, ADegenerateTriangleIsShadedAtItsCentroidFacingTheRay) {
    ShadingTriangle t = facingTriangle();
    t.p[2] = t.p[1];
    t.n[0] = t.n[1] = t.n[2] = glm::dvec3(0.0);  // no direction anywhere
    t.hasUvs = false;
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.1, 0.2, -1.0));
    const ShadingPoint s = shadingPointOn(t, glm::dvec3(0.0), dir);
    expectNear(s.position, (t.p[0] + t.p[1] + t.p[2]) / 3.0);
    expectNear(s.geometricNormal, -dir);
    expectNear(s.shadingNormal, -dir);
    EXPECT_EQ(s.uv, glm::dvec2(0.0));
    EXPECT_EQ(s.tangentU, glm::dvec3(0.0));
    // A ray along the plane of a real triangle: the centroid too.
    const ShadingPoint along = shadingPointOn(facingTriangle(), glm::dvec3(0, 0, -5), glm::dvec3(1, 0, 0));
    expectNear(along.position, glm::dvec3(2.0 / 3.0, 2.0 / 3.0, -5.0));
    EXPECT_TRUE(std::isfinite(along.shadingNormal.x));
}

}  // namespace
}  // namespace pushpin::render
