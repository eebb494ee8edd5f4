// Tests for core/scene/anim_curve.h: values at and between keys for each tangent type, smoothness,
// weighted tangents and every infinity mode. Expected numbers are derived by hand in the comments.
#include "core/scene/anim_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <utility>

namespace pushpin::scene {
namespace {

AnimCurveData keys(std::initializer_list<std::pair<double, double>> tv, TangentType type) {
    AnimCurveData d;
    for (auto [t, v] : tv) {
        AnimKey k;
        k.time = t;
        k.value = v;
        k.inType = type;
        k.outType = type;
        d.keys.push_back(k);
    }
    return d;
}

AnimCurve curve(std::initializer_list<std::pair<double, double>> tv, TangentType type,
                InfinityType pre = InfinityType::Constant, InfinityType post = InfinityType::Constant) {
    AnimCurveData d = keys(tv, type);
    d.preInfinity = pre;
    d.postInfinity = post;
    return AnimCurve(std::move(d));
}

// One-sided numeric derivatives.
double slopeLeft(const AnimCurve& c, double t, double h = 1e-6) { return (c.evaluate(t) - c.evaluate(t - h)) / h; }
double slopeRight(const AnimCurve& c, double t, double h = 1e-6) { return (c.evaluate(t + h) - c.evaluate(t)) / h; }

TEST(AnimCurve, EmptyCurveIsZeroAndSingleKeyIsConstant) {
    EXPECT_EQ(AnimCurve(AnimCurveData{}).evaluate(3.0), 0.0);
    const AnimCurve one = curve({{5, 2.5}}, TangentType::Spline, InfinityType::Linear, InfinityType::Cycle);
    for (double t : {-100.0, 0.0, 5.0, 6.0, 1e9}) EXPECT_EQ(one.evaluate(t), 2.5) << t;
}

TEST(AnimCurve, PassesThroughEveryKeyForEveryTangentType) {
    for (TangentType type : {TangentType::Fixed, TangentType::Linear, TangentType::Flat, TangentType::Step,
                             TangentType::Spline, TangentType::Clamped, TangentType::Plateau, TangentType::StepNext,
                             TangentType::Auto}) {
        const AnimCurve c = curve({{0, 1}, {4, 3}, {10, -2}, {11, 7}}, type);
        EXPECT_EQ(c.evaluate(0), 1) << int(type);
        EXPECT_EQ(c.evaluate(4), 3) << int(type);
        EXPECT_EQ(c.evaluate(10), -2) << int(type);
        EXPECT_EQ(c.evaluate(11), 7) << int(type);
    }
}

TEST(AnimCurve, LinearInterpolatesExactly) {
    const AnimCurve c = curve({{0, 0}, {10, 10}, {20, 0}}, TangentType::Linear);
    EXPECT_DOUBLE_EQ(c.evaluate(2.5), 2.5);
    EXPECT_DOUBLE_EQ(c.evaluate(5), 5);
    EXPECT_DOUBLE_EQ(c.evaluate(15), 5);
    EXPECT_DOUBLE_EQ(c.evaluate(19), 1);
}

TEST(AnimCurve, FlatHasZeroSlopeAtKeys) {
    const AnimCurve c = curve({{0, 0}, {10, 10}, {20, 4}}, TangentType::Flat);
    for (double t : {0.0, 10.0}) EXPECT_NEAR(slopeRight(c, t), 0.0, 1e-4) << t;
    for (double t : {10.0, 20.0}) EXPECT_NEAR(slopeLeft(c, t), 0.0, 1e-4) << t;
    // A zero-slope Hermite span is symmetric about its midpoint: h01(½) = ½.
    EXPECT_NEAR(c.evaluate(5), 5.0, 1e-12);
    // h01(¼) = 3/16 − 2/64 = 0.15625.
    EXPECT_NEAR(c.evaluate(2.5), 1.5625, 1e-12);
}

TEST(AnimCurve, StepHoldsUntilNextKey) {
    const AnimCurve c = curve({{0, 1}, {10, 5}, {20, 3}}, TangentType::Step);
    EXPECT_EQ(c.evaluate(0.5), 1);
    EXPECT_EQ(c.evaluate(9.999), 1);
    EXPECT_EQ(c.evaluate(10), 5);
    EXPECT_EQ(c.evaluate(19.5), 5);
    EXPECT_EQ(c.evaluate(25), 3);
}

TEST(AnimCurve, StepNextTakesTheNextValue) {
    const AnimCurve c = curve({{0, 1}, {10, 5}, {20, 3}}, TangentType::StepNext);
    EXPECT_EQ(c.evaluate(0), 1);
    EXPECT_EQ(c.evaluate(0.1), 5);
    EXPECT_EQ(c.evaluate(10.5), 3);
}

TEST(AnimCurve, SplineIsC1AtInteriorKeysWithCatmullRomSlope) {
    const AnimCurve c = curve({{0, 0}, {3, 2}, {10, -1}, {12, 4}}, TangentType::Spline);
    // Interior slopes: (v[i+1] − v[i−1]) / (t[i+1] − t[i−1]).
    const double s1 = (-1.0 - 0.0) / (10.0 - 0.0);
    const double s2 = (4.0 - 2.0) / (12.0 - 3.0);
    EXPECT_NEAR(c.outSlope(1), s1, 1e-15);
    EXPECT_NEAR(c.inSlope(2), s2, 1e-15);
    EXPECT_NEAR(slopeLeft(c, 3), s1, 1e-4);
    EXPECT_NEAR(slopeRight(c, 3), s1, 1e-4);
    EXPECT_NEAR(slopeLeft(c, 10), s2, 1e-4);
    EXPECT_NEAR(slopeRight(c, 10), s2, 1e-4);
}

TEST(AnimCurve, TwoKeySplineAndClampedAreStraightLines) {
    for (TangentType type : {TangentType::Spline, TangentType::Clamped}) {
        const AnimCurve c = curve({{0, 0}, {10, 10}}, type);
        EXPECT_NEAR(c.evaluate(2.5), 2.5, 1e-12) << int(type);
        EXPECT_NEAR(c.evaluate(7), 7, 1e-12) << int(type);
    }
}

TEST(AnimCurve, ClampedIsFlatNextToAHold) {
    const AnimCurve c = curve({{0, 0}, {10, 5}, {20, 5}, {30, 0}}, TangentType::Clamped);
    EXPECT_EQ(c.outSlope(1), 0.0);
    EXPECT_EQ(c.inSlope(2), 0.0);
    // Both ends of the hold are flat, so the hold does not overshoot.
    for (double t = 10; t <= 20; t += 0.5) EXPECT_NEAR(c.evaluate(t), 5.0, 1e-12) << t;
    // Plain spline would overshoot there: its slope at key 1 is (5 − 0)/(20 − 0) = 0.25.
    const AnimCurve s = curve({{0, 0}, {10, 5}, {20, 5}, {30, 0}}, TangentType::Spline);
    EXPECT_GT(s.evaluate(13), 5.0);
}

TEST(AnimCurve, PlateauIsFlatAtExtremaAndEnds) {
    const AnimCurve c = curve({{0, 0}, {10, 10}, {20, 0}}, TangentType::Plateau);
    EXPECT_NEAR(slopeRight(c, 0), 0.0, 1e-4);
    EXPECT_NEAR(slopeLeft(c, 10), 0.0, 1e-4);
    EXPECT_NEAR(slopeRight(c, 10), 0.0, 1e-4);
    EXPECT_NEAR(slopeLeft(c, 20), 0.0, 1e-4);
    for (double t = 0; t <= 20; t += 0.25) EXPECT_LE(c.evaluate(t), 10.0 + 1e-12);
}

TEST(AnimCurve, PlateauKeepsSplineSlopeWhenItCannotOvershoot) {
    // Key 1 of (0,0) (10,5) (20,10): spline slope 0.5, control points 5/3 away in value, well
    // inside the 5 units to either neighbour, so plateau keeps the spline slope.
    const AnimCurve c = curve({{0, 0}, {10, 5}, {20, 10}, {30, 10}}, TangentType::Plateau);
    EXPECT_NEAR(c.inSlope(1), 0.5, 1e-15);
    EXPECT_NEAR(c.outSlope(1), 0.5, 1e-15);
    // Key 1 of (0,0) (10,1) (11,10): spline slope 10/11 would put the in control point 3.03 below
    // the key, past the previous key (1 below), so that side is flat.
    const AnimCurve steep = curve({{0, 0}, {10, 1}, {11, 10}, {20, 10}}, TangentType::Plateau);
    EXPECT_EQ(steep.inSlope(1), 0.0);
    for (double t = 0; t <= 10; t += 0.25) EXPECT_GE(steep.evaluate(t), -1e-12) << t;
}

TEST(AnimCurve, AutoLimitsSlopeToAvoidOvershoot) {
    // Extremum: flat.
    const AnimCurve peak = curve({{0, 0}, {10, 10}, {20, 0}}, TangentType::Auto);
    EXPECT_EQ(peak.inSlope(1), 0.0);
    EXPECT_EQ(peak.outSlope(1), 0.0);
    // Monotone: spline slope (10 − 0)/20 = 0.5, limited by 3·(1 − 0)/10 = 0.3 on the left.
    const AnimCurve c = curve({{0, 0}, {10, 1}, {20, 10}}, TangentType::Auto);
    EXPECT_NEAR(c.inSlope(1), 0.3, 1e-15);
    EXPECT_NEAR(slopeLeft(c, 10), 0.3, 1e-4);
    EXPECT_NEAR(slopeRight(c, 10), 0.3, 1e-4);
    // End keys are flat: a two-key auto curve eases in and out (h01(¼)·10 = 1.5625).
    const AnimCurve ease = curve({{0, 0}, {10, 10}}, TangentType::Auto);
    EXPECT_NEAR(ease.evaluate(2.5), 1.5625, 1e-12);
}

TEST(AnimCurve, FixedTangentsUseStoredDirection) {
    AnimCurveData d = keys({{0, 0}, {10, 0}}, TangentType::Fixed);
    d.weightedTangents = false;
    d.keys[0].hasOutTangent = true;
    d.keys[0].outX = 0.5;  // direction only: slope 2
    d.keys[0].outY = 1.0;
    d.keys[1].hasInTangent = true;
    d.keys[1].inX = 3.0;  // slope −1
    d.keys[1].inY = -3.0;
    const AnimCurve c(std::move(d));
    EXPECT_NEAR(slopeRight(c, 0), 2.0, 1e-4);
    EXPECT_NEAR(slopeLeft(c, 10), -1.0, 1e-4);
    // Hermite: h10(½)·h·m0 + h11(½)·h·m1 = (⅛·10·2) + (−⅛·10·−1) = 2.5 + 1.25.
    EXPECT_NEAR(c.evaluate(5), 3.75, 1e-12);
}

TEST(AnimCurve, VerticalFixedTangentStaysFinite) {
    AnimCurveData d = keys({{0, 0}, {10, 1}}, TangentType::Fixed);
    d.weightedTangents = false;
    d.keys[0].hasOutTangent = true;
    d.keys[0].outX = 0.0;
    d.keys[0].outY = 1.0;
    const AnimCurve c(std::move(d));
    EXPECT_TRUE(std::isfinite(c.evaluate(0.001)));
    EXPECT_TRUE(std::isfinite(c.evaluate(5)));
}

TEST(AnimCurve, WeightedTangentsFollowTheBezier) {
    // Control points (0,0) (1,0) (2,3) (3,3): x(s) = 3s, y(s) = 9s² − 6s³.
    AnimCurveData d = keys({{0, 0}, {3, 3}}, TangentType::Fixed);
    d.weightedTangents = true;
    d.keys[0].hasOutTangent = true;
    d.keys[0].outX = 3.0;
    d.keys[0].outY = 0.0;
    d.keys[1].hasInTangent = true;
    d.keys[1].inX = 3.0;
    d.keys[1].inY = 0.0;
    const AnimCurve even(d);
    EXPECT_NEAR(even.evaluate(1.0), 1.0 - 6.0 / 27.0, 1e-10);
    EXPECT_NEAR(even.evaluate(1.5), 1.5, 1e-10);

    // Uneven weights: a long out tangent (control x at 2) and a short in tangent (x at 2.9) make x(s)
    // non-linear; each evaluated point must lie on the Bézier traced forward from its parameter.
    d.keys[0].outX = 6.0;
    d.keys[0].outY = 1.5;  // control point (2, 0.5)
    d.keys[1].inX = 0.3;
    d.keys[1].inY = 0.6;  // control point (2.9, 2.8)
    const AnimCurve uneven(d);
    const double px[4] = {0, 2, 2.9, 3}, py[4] = {0, 0.5, 2.8, 3};
    for (double s = 0.05; s < 1.0; s += 0.1) {
        const double u = 1 - s;
        const double x = u * u * u * px[0] + 3 * u * u * s * px[1] + 3 * u * s * s * px[2] + s * s * s * px[3];
        const double y = u * u * u * py[0] + 3 * u * u * s * py[1] + 3 * u * s * s * py[2] + s * s * s * py[3];
        EXPECT_NEAR(uneven.evaluate(x), y, 1e-9) << "s=" << s;
    }
    // The same tangents without weights give a different curve (only their directions count).
    d.weightedTangents = false;
    EXPECT_GT(std::abs(AnimCurve(d).evaluate(1.0) - uneven.evaluate(1.0)), 1e-3);
}

TEST(AnimCurve, WeightedComputedTangentsDefaultToSpanLength) {
    // Without stored x, a weighted spline span equals the non-weighted one (control points at thirds).
    AnimCurveData d = keys({{0, 0}, {4, 3}, {10, -2}}, TangentType::Spline);
    d.weightedTangents = true;
    const AnimCurve weighted(d);
    d.weightedTangents = false;
    const AnimCurve plain(d);
    for (double t = 0; t <= 10; t += 0.7) EXPECT_NEAR(weighted.evaluate(t), plain.evaluate(t), 1e-9) << t;
}

// Linear keys (0,0) → (10,10): each infinity mode before and after the range.
TEST(AnimCurve, ConstantInfinity) {
    const AnimCurve c = curve({{0, 0}, {10, 10}}, TangentType::Linear);
    EXPECT_EQ(c.evaluate(-5), 0);
    EXPECT_EQ(c.evaluate(15), 10);
}

TEST(AnimCurve, LinearInfinityFollowsEndTangents) {
    const AnimCurve c = curve({{0, 0}, {10, 10}}, TangentType::Linear, InfinityType::Linear, InfinityType::Linear);
    EXPECT_NEAR(c.evaluate(-5), -5, 1e-12);
    EXPECT_NEAR(c.evaluate(15), 15, 1e-12);
    // Flat end tangents make linear infinity flat.
    const AnimCurve f = curve({{0, 0}, {10, 10}}, TangentType::Flat, InfinityType::Linear, InfinityType::Linear);
    EXPECT_NEAR(f.evaluate(-5), 0, 1e-12);
    EXPECT_NEAR(f.evaluate(15), 10, 1e-12);
}

TEST(AnimCurve, CycleInfinityRepeats) {
    const AnimCurve c = curve({{0, 0}, {10, 10}}, TangentType::Linear, InfinityType::Cycle, InfinityType::Cycle);
    EXPECT_NEAR(c.evaluate(12), 2, 1e-12);
    EXPECT_NEAR(c.evaluate(27), 7, 1e-12);
    EXPECT_NEAR(c.evaluate(-2), 8, 1e-12);
    EXPECT_NEAR(c.evaluate(-13), 7, 1e-12);
}

TEST(AnimCurve, CycleWithOffsetAccumulates) {
    const AnimCurve c =
        curve({{0, 0}, {10, 10}}, TangentType::Linear, InfinityType::CycleRelative, InfinityType::CycleRelative);
    EXPECT_NEAR(c.evaluate(12), 12, 1e-12);
    EXPECT_NEAR(c.evaluate(27), 27, 1e-12);
    EXPECT_NEAR(c.evaluate(-2), -2, 1e-12);
    EXPECT_NEAR(c.evaluate(-13), -13, 1e-12);
    // With a curved span, the offset is the end-to-start value difference per cycle.
    const AnimCurve s =
        curve({{0, 1}, {4, 5}, {10, 3}}, TangentType::Spline, InfinityType::CycleRelative, InfinityType::CycleRelative);
    EXPECT_NEAR(s.evaluate(12), s.evaluate(2) + 2, 1e-12);
    EXPECT_NEAR(s.evaluate(-8), s.evaluate(2) - 2, 1e-12);
}

TEST(AnimCurve, OscillateInfinityMirrors) {
    const AnimCurve c =
        curve({{0, 0}, {10, 10}}, TangentType::Linear, InfinityType::Oscillate, InfinityType::Oscillate);
    EXPECT_NEAR(c.evaluate(12), 8, 1e-12);   // first cycle after the end runs backwards
    EXPECT_NEAR(c.evaluate(22), 2, 1e-12);   // second runs forwards again
    EXPECT_NEAR(c.evaluate(-2), 2, 1e-12);   // mirrored at the start
    EXPECT_NEAR(c.evaluate(-12), 8, 1e-12);  // then forwards shifted a cycle back
}

TEST(AnimCurve, PreAndPostInfinityAreIndependent) {
    const AnimCurve c = curve({{0, 0}, {10, 10}}, TangentType::Linear, InfinityType::Constant, InfinityType::Cycle);
    EXPECT_EQ(c.evaluate(-3), 0);
    EXPECT_NEAR(c.evaluate(13), 3, 1e-12);
}

TEST(AnimCurve, GlobalTypeUsesCurveDefault) {
    AnimCurveData d = keys({{0, 1}, {10, 5}}, TangentType::Global);
    d.tangentType = TangentType::Step;
    EXPECT_EQ(AnimCurve(d).evaluate(9), 1);
    d.tangentType = TangentType::Linear;
    EXPECT_DOUBLE_EQ(AnimCurve(d).evaluate(5), 3);
}

TEST(AnimCurve, KeysAreSortedAndNonFiniteInputIsSafe) {
    const AnimCurve c = curve({{10, 10}, {0, 0}}, TangentType::Linear);
    EXPECT_DOUBLE_EQ(c.evaluate(4), 4);
    EXPECT_EQ(c.evaluate(std::nan("")), 0);
    EXPECT_EQ(c.evaluate(INFINITY), 10);
    EXPECT_EQ(c.evaluate(-INFINITY), 0);
}

TEST(AnimCurve, EnumConversionRejectsUnknownValues) {
    EXPECT_EQ(tangentTypeFromInt(18), TangentType::Auto);
    EXPECT_EQ(tangentTypeFromInt(10), TangentType::Clamped);
    EXPECT_EQ(tangentTypeFromInt(4), TangentType::Global);
    EXPECT_EQ(tangentTypeFromInt(-1), TangentType::Global);
    EXPECT_EQ(infinityTypeFromInt(4), InfinityType::CycleRelative);
    EXPECT_EQ(infinityTypeFromInt(2), InfinityType::Constant);
}

}  // namespace
}  // namespace pushpin::scene
