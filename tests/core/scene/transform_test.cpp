// Tests for core/scene/transform.h. Expected values are worked out independently: points are moved
// step by step through the factors of Maya's formula with closed-form axis rotations, never by
// multiplying the matrices the code under test builds.
#include "core/scene/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace pushpin::scene {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

glm::dvec3 apply(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 q = m * glm::dvec4(p, 1.0);
    return {q.x, q.y, q.z};
}

// Right-handed rotation of a point about one coordinate axis (closed forms).
glm::dvec3 turn(char axis, double a, const glm::dvec3& p) {
    const double c = std::cos(a), s = std::sin(a);
    switch (axis) {
        case 'x': return {p.x, c * p.y - s * p.z, s * p.y + c * p.z};
        case 'y': return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
        default: return {c * p.x - s * p.y, s * p.x + c * p.y, p.z};
    }
}

glm::dvec3 turnInOrder(const std::string& order, const glm::dvec3& r, const glm::dvec3& p) {
    glm::dvec3 q = p;
    for (char axis : order) q = turn(axis, axis == 'x' ? r.x : axis == 'y' ? r.y : r.z, q);
    return q;
}

void expectNear(const glm::dvec3& got, const glm::dvec3& want, double tol = 1e-12) {
    EXPECT_NEAR(got.x, want.x, tol) << "x";
    EXPECT_NEAR(got.y, want.y, tol) << "y";
    EXPECT_NEAR(got.z, want.z, tol) << "z";
}

TEST(Transform, DefaultAttributesGiveIdentity) {
    const glm::dmat4 m = transformMatrix(TransformAttrs{});
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_DOUBLE_EQ(m[c][r], c == r ? 1.0 : 0.0);
}

TEST(Transform, ElementaryRotationsMoveAxesRightHanded) {
    // 90° about z takes +x to +y; about x takes +y to +z; about y takes +z to +x.
    expectNear(apply(rotationMatrix({0, 0, 90 * kDeg}, 0), {1, 0, 0}), {0, 1, 0});
    expectNear(apply(rotationMatrix({90 * kDeg, 0, 0}, 0), {0, 1, 0}), {0, 0, 1});
    expectNear(apply(rotationMatrix({0, 90 * kDeg, 0}, 0), {0, 0, 1}), {1, 0, 0});
}

TEST(Transform, RotateOrderXyzAppliesXFirst) {
    // x 90° leaves +x alone, then y 90° takes +x to −z.
    expectNear(apply(rotationMatrix({90 * kDeg, 90 * kDeg, 0}, 0), {1, 0, 0}), {0, 0, -1});
    // zyx: y 90° takes +x to −z first, then x 90° takes −z to +y.
    expectNear(apply(rotationMatrix({90 * kDeg, 90 * kDeg, 0}, 5), {1, 0, 0}), {0, 1, 0});
}

TEST(Transform, EveryRotateOrderMatchesSequentialAxisRotations) {
    const char* orders[] = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
    const glm::dvec3 r{30 * kDeg, -50 * kDeg, 110 * kDeg};
    const glm::dvec3 points[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3, -2.0, 1.7}};
    for (int order = 0; order < 6; ++order) {
        const glm::dmat4 m = rotationMatrix(r, order);
        for (const glm::dvec3& p : points) {
            SCOPED_TRACE(orders[order]);
            expectNear(apply(m, p), turnInOrder(orders[order], r, p));
        }
    }
    // The orders really differ from each other for these angles.
    const glm::dvec3 p{0.3, -2.0, 1.7};
    EXPECT_GT(glm::length(apply(rotationMatrix(r, 0), p) - apply(rotationMatrix(r, 5), p)), 0.1);
}

TEST(Transform, OutOfRangeRotateOrderIsXyz) {
    const glm::dvec3 r{0.1, 0.2, 0.3};
    expectNear(apply(rotationMatrix(r, 42), {1, 2, 3}), apply(rotationMatrix(r, 0), {1, 2, 3}));
}

TEST(Transform, RotatePivotKeepsPivotFixed) {
    TransformAttrs a;
    a.rotate = {0, 0, 90 * kDeg};
    a.rotatePivot = {1, 0, 0};
    const glm::dmat4 m = transformMatrix(a);
    expectNear(apply(m, {1, 0, 0}), {1, 0, 0});
    // (2,0,0) is one unit from the pivot along +x; the rotation swings it to one unit along +y.
    expectNear(apply(m, {2, 0, 0}), {1, 1, 0});
}

TEST(Transform, ScalePivotWithNonUniformScale) {
    TransformAttrs a;
    a.scale = {2, 3, 1};
    a.scalePivot = {1, 1, 0};
    const glm::dmat4 m = transformMatrix(a);
    expectNear(apply(m, {1, 1, 0}), {1, 1, 0});
    expectNear(apply(m, {2, 2, 0}), {3, 4, 0});
    expectNear(apply(m, {0, 0, 5}), {-1, -2, 5});
}

TEST(Transform, PivotTranslatesShiftTheResult) {
    TransformAttrs a;
    a.rotatePivotTranslate = {0, 0, 5};
    a.scalePivotTranslate = {1, 0, 0};
    expectNear(apply(transformMatrix(a), {0, 0, 0}), {1, 0, 5});
}

TEST(Transform, ShearLayout) {
    TransformAttrs a;
    a.shear = {0.5, 0, 0};  // shearXY: x += 0.5·y
    expectNear(apply(transformMatrix(a), {0, 2, 0}), {1, 2, 0});
    a.shear = {0, 0.25, 0};  // shearXZ: x += 0.25·z
    expectNear(apply(transformMatrix(a), {0, 0, 4}), {1, 0, 4});
    a.shear = {0, 0, 2};  // shearYZ: y += 2·z
    expectNear(apply(transformMatrix(a), {0, 0, 1}), {0, 2, 1});
}

TEST(Transform, RotateAxisAppliesBeforeRotate) {
    TransformAttrs a;
    a.rotateAxis = {0, 0, 90 * kDeg};
    a.rotate = {90 * kDeg, 0, 0};
    // rotateAxis first: +x → +y; then rotate x 90°: +y → +z.
    expectNear(apply(transformMatrix(a), {1, 0, 0}), {0, 0, 1});
}

TEST(Transform, FullStackMatchesStepByStepComposition) {
    TransformAttrs a;
    a.translate = {1.5, -2, 3};
    a.rotate = {20 * kDeg, 35 * kDeg, -70 * kDeg};
    a.scale = {1.5, 0.5, 2.0};
    a.shear = {0.3, -0.2, 0.4};
    a.rotateAxis = {10 * kDeg, -15 * kDeg, 5 * kDeg};
    a.rotatePivot = {0.5, 1, -1};
    a.rotatePivotTranslate = {0.1, 0.2, 0.3};
    a.scalePivot = {-1, 0.25, 2};
    a.scalePivotTranslate = {0.4, -0.5, 0.6};
    const char* orders[] = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
    for (int order = 0; order < 6; ++order) {
        a.rotateOrder = order;
        const glm::dmat4 m = transformMatrix(a);
        for (glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(1, 2, 3), glm::dvec3(-4, 0.5, 1)}) {
            // p · SP⁻¹ · S · SH · SP · ST · RP⁻¹ · RA · R · RP · RT · T, one factor at a time.
            glm::dvec3 q = p - a.scalePivot;
            q *= a.scale;
            q = {q.x + a.shear.x * q.y + a.shear.y * q.z, q.y + a.shear.z * q.z, q.z};
            q += a.scalePivot + a.scalePivotTranslate;
            q -= a.rotatePivot;
            q = turnInOrder("xyz", a.rotateAxis, q);
            q = turnInOrder(orders[order], a.rotate, q);
            q += a.rotatePivot + a.rotatePivotTranslate + a.translate;
            SCOPED_TRACE(orders[order]);
            expectNear(apply(m, p), q, 1e-12);
        }
    }
}

TEST(Joint, JointOrientAppliesAfterRotate) {
    JointAttrs j;
    j.rotate = {90 * kDeg, 0, 0};
    j.jointOrient = {0, 0, 90 * kDeg};
    // rotate x 90° leaves +x alone, then the orient's z 90° takes it to +y.
    expectNear(apply(jointMatrix(j), {1, 0, 0}), {0, 1, 0});
}

TEST(Joint, RotateAxisAppliesBeforeRotate) {
    JointAttrs j;
    j.rotateAxis = {0, 0, 90 * kDeg};
    j.rotate = {90 * kDeg, 0, 0};
    expectNear(apply(jointMatrix(j), {1, 0, 0}), {0, 0, 1});
}

TEST(Joint, SegmentScaleCompensateDividesByParentScale) {
    JointAttrs j;
    j.translate = {4, 0, 0};
    j.inverseScale = {2, 2, 2};
    expectNear(apply(jointMatrix(j), {1, 0, 0}), {4.5, 0, 0});
    j.segmentScaleCompensate = false;
    expectNear(apply(jointMatrix(j), {1, 0, 0}), {5, 0, 0});
}

TEST(Joint, FullStackMatchesStepByStepComposition) {
    JointAttrs j;
    j.translate = {1, 2, 3};
    j.rotate = {15 * kDeg, -25 * kDeg, 40 * kDeg};
    j.rotateOrder = 2;  // zxy
    j.scale = {2, 1, 0.5};
    j.rotateAxis = {5 * kDeg, 10 * kDeg, -20 * kDeg};
    j.jointOrient = {-30 * kDeg, 12 * kDeg, 60 * kDeg};
    j.inverseScale = {0.5, 4, 2};
    const glm::dvec3 p{0.7, -1.1, 2.3};
    // p · S · RA · R · JO · IS · T
    glm::dvec3 q = p * j.scale;
    q = turnInOrder("xyz", j.rotateAxis, q);
    q = turnInOrder("zxy", j.rotate, q);
    q = turnInOrder("xyz", j.jointOrient, q);
    q /= j.inverseScale;
    q += j.translate;
    expectNear(apply(jointMatrix(j), p), q);
}

TEST(Joint, ZeroInverseScaleStaysFinite) {
    JointAttrs j;
    j.inverseScale = {0, 1, 1};
    const glm::dvec3 q = apply(jointMatrix(j), {1, 1, 1});
    EXPECT_TRUE(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z));
    expectNear(q, {1, 1, 1});
}

}  // namespace
}  // namespace pushpin::scene
