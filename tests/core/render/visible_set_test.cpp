// Tests for core/render/visible_set.h: where an object's bounds land before the default camera
// (at the origin looking down −Z, screen window [−1, 1] × [−0.75, 0.75] on z = −1, 640×480,
// near 0.1, far 10000). Expected screen boxes are worked by hand from the perspective divide.
#include "core/render/visible_set.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pushpin::render {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const PixelRect kScreen{0, 0, 640, 480};

geom::Bounds3 box(glm::dvec3 lo, glm::dvec3 hi) {
    geom::Bounds3 b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

TEST(PlaceObject, ABoxBeforeTheCameraProjectsToTheBoxOfItsCorners) {
    const RenderCamera camera;
    // A 2-unit cube centred 10 units away, placed there by its world matrix: its nearest face
    // (z = −9) spans x and y in ±1/9 of the window's half-widths 1 and 0.75.
    const glm::dmat4 world = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -10));
    const ObjectPlacement p = placeObject(box({-1, -1, -1}, {1, 1, 1}), world, camera, kScreen);
    ASSERT_TRUE(p.kept);
    EXPECT_FALSE(p.culledFar);
    EXPECT_NEAR(p.x0, (1.0 - 1.0 / 9.0) / 2.0 * 640.0, 1e-9);
    EXPECT_NEAR(p.x1, (1.0 + 1.0 / 9.0) / 2.0 * 640.0, 1e-9);
    EXPECT_NEAR(p.y0, (0.75 - 1.0 / 9.0) / 1.5 * 480.0, 1e-9);
    EXPECT_NEAR(p.y1, (0.75 + 1.0 / 9.0) / 1.5 * 480.0, 1e-9);
    EXPECT_NEAR(p.nearKey, -1.0 / 9.0, 1e-15);  // depth keys are −1/distance
    EXPECT_NEAR(p.farKey, -1.0 / 11.0, 1e-15);
    const glm::dvec4 c = p.cameraFromObject * glm::dvec4(0.5, -0.25, 1.0, 1.0);
    EXPECT_NEAR(c.z, -9.0, 1e-12);
    const glm::dvec4 back = p.objectFromCamera * c;
    EXPECT_NEAR(back.x, 0.5, 1e-12);
    EXPECT_NEAR(back.y, -0.25, 1e-12);
    EXPECT_NEAR(back.z, 1.0, 1e-12);
}

TEST(PlaceObject, NormalsGoToCameraSpaceByTheInverseTranspose) {
    const RenderCamera camera;
    // Stretched 4× along x: a normal (1, 1, 0)/√2 of the unstretched shape leans towards y.
    const glm::dmat4 world = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -10)), glm::dvec3(4, 1, 1));
    const ObjectPlacement p = placeObject(box({-1, -1, -1}, {1, 1, 1}), world, camera, kScreen);
    const glm::dvec3 n = p.normalToCamera * glm::dvec3(1, 1, 0);
    EXPECT_NEAR(n.x, 0.25, 1e-12);
    EXPECT_NEAR(n.y, 1.0, 1e-12);
    EXPECT_NEAR(n.z, 0.0, 1e-12);
}

TEST(PlaceObject, PastTheFarPlaneIsCulledFar) {
    const RenderCamera camera;
    const ObjectPlacement p = placeObject(box({-1, -1, -20002}, {1, 1, -20000}), glm::dmat4(1.0), camera, kScreen);
    EXPECT_FALSE(p.kept);
    EXPECT_TRUE(p.culledFar);
    // Reaching over the far plane by a little keeps it.
    EXPECT_TRUE(placeObject(box({-1, -1, -20000}, {1, 1, -9999}), glm::dmat4(1.0), camera, kScreen).kept);
}

TEST(PlaceObject, BehindTheEyeOrBeforeTheNearPlaneIsNotKept) {
    const RenderCamera camera;
    for (const geom::Bounds3& b : {box({-1, -1, 1}, {1, 1, 2}), box({-1, -1, -0.09}, {1, 1, -0.01})}) {
        const ObjectPlacement p = placeObject(b, glm::dmat4(1.0), camera, kScreen);
        EXPECT_FALSE(p.kept);
        EXPECT_FALSE(p.culledFar);
    }
}

TEST(PlaceObject, ABoxCrossingTheNearPlaneReachesEverywhere) {
    const RenderCamera camera;
    const ObjectPlacement p = placeObject(box({-1, -1, -5}, {1, 1, 1}), glm::dmat4(1.0), camera, kScreen);
    ASSERT_TRUE(p.kept);
    EXPECT_EQ(p.x0, -kInf);
    EXPECT_EQ(p.y0, -kInf);
    EXPECT_EQ(p.x1, kInf);
    EXPECT_EQ(p.y1, kInf);
    EXPECT_EQ(p.nearKey, -kInf);
    EXPECT_EQ(p.farKey, kInf);
}

TEST(PlaceObject, OffTheScreenIsNotKeptUnlessTheReachTakesItIn) {
    const RenderCamera camera;
    // A flat card at z = −10 whose left edge lands on raster x = 641: x = (641 / 320 − 1) · 10.
    const double left = (641.0 / 320.0 - 1.0) * 10.0;
    const geom::Bounds3 card = box({left, -1, -10}, {left + 1, 1, -10});
    EXPECT_FALSE(placeObject(card, glm::dmat4(1.0), camera, kScreen).kept);
    const ObjectPlacement wide = placeObject(card, glm::dmat4(1.0), camera, {0, 0, 642, 480});
    ASSERT_TRUE(wide.kept);
    EXPECT_NEAR(wide.x0, 641.0, 1e-9);
    // Touching the reach along its edge keeps it.
    EXPECT_TRUE(placeObject(card, glm::dmat4(1.0), camera, {0, 0, 641, 480}).kept);
    // Far to the left, above and below.
    EXPECT_FALSE(placeObject(box({-40, -1, -10}, {-30, 1, -10}), glm::dmat4(1.0), camera, kScreen).kept);
    EXPECT_FALSE(placeObject(box({-1, 20, -10}, {1, 30, -10}), glm::dmat4(1.0), camera, kScreen).kept);
    EXPECT_FALSE(placeObject(box({-1, -30, -10}, {1, -20, -10}), glm::dmat4(1.0), camera, kScreen).kept);
}

TEST(PlaceObject, AFlattenedObjectShadesFromTheOrigin) {
    const RenderCamera camera;
    const glm::dmat4 world = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -10)), glm::dvec3(1, 1, 0));
    const ObjectPlacement p = placeObject(box({-1, -1, -1}, {1, 1, 1}), world, camera, kScreen);
    EXPECT_TRUE(p.kept);
    const glm::dvec4 o = p.objectFromCamera * glm::dvec4(3.0, -2.0, -10.0, 1.0);
    EXPECT_EQ(o, glm::dvec4(0.0, 0.0, 0.0, 1.0));
    // So does one scaled so small that the inverse leaves the scene range.
    const glm::dmat4 tiny = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -10)), glm::dvec3(1e-20));
    const ObjectPlacement q = placeObject(box({-1, -1, -1}, {1, 1, 1}), tiny, camera, kScreen);
    EXPECT_TRUE(q.kept);
    EXPECT_EQ(q.objectFromCamera * glm::dvec4(3.0, -2.0, -10.0, 1.0), glm::dvec4(0.0, 0.0, 0.0, 1.0));
}

TEST(PlaceObject, EmptyOrNonFiniteBoundsAreNotKept) {
    const RenderCamera camera;
    EXPECT_FALSE(placeObject(geom::Bounds3{}, glm::dmat4(1.0), camera, kScreen).kept);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    geom::Bounds3 b = box({-1, -1, -11}, {1, 1, -9});
    b.lo.x = nan;
    EXPECT_FALSE(placeObject(b, glm::dmat4(1.0), camera, kScreen).kept);
    b = box({-1, -1, -11}, {1, 1, -9});
    b.hi.x = kInf;
    EXPECT_FALSE(placeObject(b, glm::dmat4(1.0), camera, kScreen).kept);
}

}  // namespace
}  // namespace pushpin::render
