// Object space to camera space and the near-plane clip (core/render/camera_space.h), against
// hand-worked cases.
#include "core/render/camera_space.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pushpin::render {
namespace {

void expectNear(const glm::dvec3& got, const glm::dvec3& want) {
    EXPECT_NEAR(got.x, want.x, 1e-12);
    EXPECT_NEAR(got.y, want.y, 1e-12);
    EXPECT_NEAR(got.z, want.z, 1e-12);
}

TEST(CameraSpace, PointTakesTheWholeMatrixInDoublePrecision) {
    const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(1.0, 2.0, -3.0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0, 2.0, 2.0));
    expectNear(cameraPoint(m, glm::vec3(0.5f, -1.0f, 0.25f)), glm::dvec3(2.0, 0.0, -2.5));
    // 0.1f is kept as the float it is, not rounded again.
    EXPECT_EQ(cameraPoint(glm::dmat4(1.0), glm::vec3(0.1f, 0.0f, 0.0f)).x, double(0.1f));
}

TEST(CameraSpace, NormalIsUnitOrZero) {
    const glm::dmat3 stretch(glm::dvec3(4.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(0.0, 0.0, 1.0));
    expectNear(cameraNormal(stretch, glm::vec3(1.0f, 1.0f, 0.0f)), glm::dvec3(4.0, 1.0, 0.0) / std::sqrt(17.0));
    expectNear(cameraNormal(stretch, glm::vec3(0.0f)), glm::dvec3(0.0));
    const float inf = std::numeric_limits<float>::infinity();
    expectNear(cameraNormal(stretch, glm::vec3(inf, 0.0f, 0.0f)), glm::dvec3(0.0));
    expectNear(cameraNormal(stretch, glm::vec3(std::nanf(""), 0.0f, 0.0f)), glm::dvec3(0.0));
}

TEST(CameraSpace, ClipNearKeepsATriangleInside) {
    const glm::dvec3 in[3] = {{0, 0, -2}, {1, 0, -2}, {0, 1, -3}};
    glm::dvec3 out[4];
    ASSERT_EQ(clipNear(in, -1.0, out), 3);
    for (int i = 0; i < 3; ++i) expectNear(out[i], in[i]);
}

TEST(CameraSpace, ClipNearDropsATriangleBeyondThePlane) {
    const glm::dvec3 in[3] = {{0, 0, -0.5}, {1, 0, 0.5}, {0, 1, -0.9}};
    glm::dvec3 out[4];
    EXPECT_EQ(clipNear(in, -1.0, out), 0);
}

TEST(CameraSpace, OneVertexPastThePlaneGivesAQuadrilateral) {
    // Vertex 1 at z = 0 is past the plane z = -1; the edges to it are cut halfway.
    const glm::dvec3 in[3] = {{0, 0, -2}, {2, 0, 0}, {0, 2, -2}};
    glm::dvec3 out[4];
    ASSERT_EQ(clipNear(in, -1.0, out), 4);
    expectNear(out[0], {0, 0, -2});
    expectNear(out[1], {1, 0, -1});
    expectNear(out[2], {1, 1, -1});
    expectNear(out[3], {0, 2, -2});
}

TEST(CameraSpace, TwoVerticesPastThePlaneGiveASmallerTriangle) {
    const glm::dvec3 in[3] = {{0, 0, -3}, {4, 0, 1}, {0, 4, 1}};
    glm::dvec3 out[4];
    ASSERT_EQ(clipNear(in, -1.0, out), 3);
    expectNear(out[0], {0, 0, -3});
    expectNear(out[1], {2, 0, -1});
    expectNear(out[2], {0, 2, -1});
}

TEST(CameraSpace, AVertexOnThePlaneIsInside) {
    const glm::dvec3 in[3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
    glm::dvec3 out[4];
    EXPECT_EQ(clipNear(in, -1.0, out), 3);
}

}  // namespace
}  // namespace pushpin::render
