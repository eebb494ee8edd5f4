// Tests for core/shade/light.h: each light type against the falloff formulas of
// reference/nodes.md §3, the flags, transformed(), defaultLight(), and degenerate samples.
#include "core/shade/light.h"

#include <glm/gtc/matrix_transform.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

namespace pushpin::shade {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A batch whose samples all sit at the origin facing +Z, unless set otherwise.
std::unique_ptr<ShadingBatch> makeBatch(int count) {
    auto b = std::make_unique<ShadingBatch>();
    *b = ShadingBatch{};
    b->count = count;
    for (int i = 0; i < kBatchSize; ++i) {
        b->px[i] = b->py[i] = b->pz[i] = 0.0f;
        b->nx[i] = b->ny[i] = 0.0f;
        b->nz[i] = 1.0f;
    }
    return b;
}

void setPoint(ShadingBatch& b, int i, glm::dvec3 p, glm::dvec3 n = {0, 0, 1}) {
    b.px[i] = float(p.x), b.py[i] = float(p.y), b.pz[i] = float(p.z);
    n = glm::normalize(n);
    b.nx[i] = float(n.x), b.ny[i] = float(n.y), b.nz[i] = float(n.z);
}

glm::dvec3 dirOf(const LightSamples& s, int i) { return {s.lx[i], s.ly[i], s.lz[i]}; }
glm::dvec3 intensityOf(const LightSamples& s, int i) { return {s.ir[i], s.ig[i], s.ib[i]}; }

void expectVec(glm::dvec3 got, glm::dvec3 want, double tol, const char* what) {
    EXPECT_NEAR(got.x, want.x, tol) << what << " x";
    EXPECT_NEAR(got.y, want.y, tol) << what << " y";
    EXPECT_NEAR(got.z, want.z, tol) << what << " z";
}

// A spot at the origin pointing down −Z, and a sample at `angleDeg` off its axis, distance 1.
double spotAt(const Light& spot, double angleDeg) {
    auto b = makeBatch(1);
    const double a = angleDeg * kDeg;
    setPoint(*b, 0, {std::sin(a), 0.0, -std::cos(a)}, {0, 0, 1});
    LightSamples s;
    illuminate(spot, *b, s);
    return s.ir[0];
}

Light spotLight(double coneDeg, double penumbraDeg, double dropoff = 0.0) {
    Light l;
    l.type = LightType::Spot;
    l.position = {0, 0, 0};
    l.direction = {0, 0, -1};
    l.coneAngle = float(coneDeg * kDeg);
    l.penumbraAngle = float(penumbraDeg * kDeg);
    l.dropoff = float(dropoff);
    return l;
}

TEST(Light, DirectionalShinesAlongItsDirectionWithoutFalloff) {
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(glm::dvec3(1, -2, -3));
    l.color = {0.5f, 1.0f, 2.0f};
    auto b = makeBatch(3);
    setPoint(*b, 1, {100, 0, 0});
    setPoint(*b, 2, {0, -1e4, 3});
    LightSamples s;
    illuminate(l, *b, s);
    for (int i = 0; i < 3; ++i) {
        expectVec(dirOf(s, i), -l.direction, 1e-6, "L");
        expectVec(intensityOf(s, i), {0.5, 1.0, 2.0}, 1e-6, "I");
    }
    EXPECT_FALSE(s.ambient);
    EXPECT_TRUE(s.diffuse);
    EXPECT_TRUE(s.specular);
}

TEST(Light, EmitFlagsFollowTheLight) {
    Light l;
    l.type = LightType::Point;
    l.emitDiffuse = false;
    auto b = makeBatch(1);
    LightSamples s;
    illuminate(l, *b, s);
    EXPECT_FALSE(s.diffuse);
    EXPECT_TRUE(s.specular);
    l.emitDiffuse = true;
    l.emitSpecular = false;
    illuminate(l, *b, s);
    EXPECT_TRUE(s.diffuse);
    EXPECT_FALSE(s.specular);
}

TEST(Light, PointDecayRatesMatchTheFormula) {
    Light l;
    l.type = LightType::Point;
    l.position = {0, 4, 3};  // distance 5 from the origin
    l.color = {2.0f, 2.0f, 2.0f};
    auto b = makeBatch(2);
    setPoint(*b, 1, {0, 4, 2.5});  // distance 0.5: inside the "no effect under 1 unit" zone
    for (int rate = 0; rate <= 3; ++rate) {
        l.decayRate = rate;
        LightSamples s;
        illuminate(l, *b, s);
        expectVec(dirOf(s, 0), glm::dvec3(0, 0.8, 0.6), 1e-6, "L");
        EXPECT_NEAR(s.ir[0], 2.0 / std::pow(5.0, rate), 1e-5) << "rate " << rate;
        EXPECT_NEAR(s.ir[1], 2.0, 1e-6) << "rate " << rate << " under 1 unit";
        expectVec(dirOf(s, 1), glm::dvec3(0, 0, 1), 1e-6, "L near");
    }
}

TEST(Light, SampleAtTheLightPositionIsFinite) {
    for (LightType type : {LightType::Point, LightType::Spot, LightType::Ambient}) {
        Light l;
        l.type = type;
        l.position = {1, 2, 3};
        l.decayRate = 3;
        auto b = makeBatch(1);
        setPoint(*b, 0, {1, 2, 3}, {0, 1, 0});
        LightSamples s;
        illuminate(l, *b, s);
        for (float v : {s.lx[0], s.ly[0], s.lz[0], s.ir[0], s.ig[0], s.ib[0]}) EXPECT_TRUE(std::isfinite(v));
        EXPECT_NEAR(glm::length(dirOf(s, 0)), 1.0, 1e-6);
        EXPECT_NEAR(s.ir[0], 1.0, 1e-6) << "full intensity on the light itself";
    }
}

TEST(Light, DegenerateNormalAtTheLightPositionStillGivesAUnitDirection) {
    Light l;
    l.type = LightType::Point;
    auto b = makeBatch(1);
    b->nx[0] = b->ny[0] = b->nz[0] = 0.0f;
    LightSamples s;
    illuminate(l, *b, s);
    EXPECT_NEAR(glm::length(dirOf(s, 0)), 1.0, 1e-6);
}

TEST(Light, SpotConeWithoutPenumbraIsAStep) {
    const Light l = spotLight(40, 0);
    EXPECT_NEAR(spotAt(l, 0), 1.0, 1e-6);
    EXPECT_NEAR(spotAt(l, 19.5), 1.0, 1e-6);
    EXPECT_NEAR(spotAt(l, 20.5), 0.0, 1e-6);
    EXPECT_NEAR(spotAt(l, 120), 0.0, 1e-6);
}

TEST(Light, SpotPositivePenumbraFadesOutsideTheCone) {
    // nodes.md: cone 50, penumbra +10 → fading between half-angles 25 and 35.
    const Light l = spotLight(50, 10);
    EXPECT_NEAR(spotAt(l, 24), 1.0, 1e-3);
    EXPECT_NEAR(spotAt(l, 27.5), 0.75, 1e-3);
    EXPECT_NEAR(spotAt(l, 30), 0.5, 1e-3);
    EXPECT_NEAR(spotAt(l, 34), 0.1, 1e-3);
    EXPECT_NEAR(spotAt(l, 36), 0.0, 1e-6);
}

TEST(Light, SpotNegativePenumbraFadesInsideTheCone) {
    // nodes.md: cone 50, penumbra −10 → fading between half-angles 15 and 25.
    const Light l = spotLight(50, -10);
    EXPECT_NEAR(spotAt(l, 14), 1.0, 1e-3);
    EXPECT_NEAR(spotAt(l, 17.5), 0.75, 1e-3);
    EXPECT_NEAR(spotAt(l, 20), 0.5, 1e-3);
    EXPECT_NEAR(spotAt(l, 26), 0.0, 1e-6);
}

TEST(Light, SpotDropoffIsCosinePower) {
    const Light l = spotLight(80, 0, 4.0);
    EXPECT_NEAR(spotAt(l, 0), 1.0, 1e-5);
    EXPECT_NEAR(spotAt(l, 30), std::pow(std::cos(30 * kDeg), 4.0), 1e-4);
    // Dropoff combines with the penumbra ramp.
    const Light m = spotLight(50, 10, 2.0);
    EXPECT_NEAR(spotAt(m, 30), 0.5 * std::pow(std::cos(30 * kDeg), 2.0), 1e-3);
}

TEST(Light, SpotDecaysWithDistance) {
    Light l = spotLight(40, 0);
    l.decayRate = 2;
    l.color = {3.0f, 3.0f, 3.0f};
    auto b = makeBatch(1);
    setPoint(*b, 0, {0, 0, -4});
    LightSamples s;
    illuminate(l, *b, s);
    EXPECT_NEAR(s.ir[0], 3.0 / 16.0, 1e-5);
    expectVec(dirOf(s, 0), {0, 0, 1}, 1e-6, "L");
}

TEST(Light, AmbientShadeMixesConstantAndLambertianParts) {
    Light l;
    l.type = LightType::Ambient;
    l.position = {0, 0, 10};
    l.color = {1.0f, 0.5f, 0.25f};
    l.ambientShade = 0.45f;
    auto b = makeBatch(3);
    setPoint(*b, 0, {0, 0, 0}, {0, 0, 1});   // facing the light: N·L = 1
    setPoint(*b, 1, {0, 0, 0}, {1, 0, 1});   // N·L = cos 45°
    setPoint(*b, 2, {0, 0, 0}, {0, 0, -1});  // facing away: N·L < 0 → only (1 − as)
    LightSamples s;
    illuminate(l, *b, s);
    const double k[3] = {1.0, 0.55 + 0.45 * std::sqrt(0.5), 0.55};
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(s.ir[i], 1.0 * k[i], 1e-5) << i;
        EXPECT_NEAR(s.ig[i], 0.5 * k[i], 1e-5) << i;
        EXPECT_NEAR(s.ib[i], 0.25 * k[i], 1e-5) << i;
        expectVec(dirOf(s, i), {0, 0, 1}, 1e-6, "L");
    }
    EXPECT_TRUE(s.ambient);
    EXPECT_FALSE(s.diffuse);
    EXPECT_FALSE(s.specular);
    l.ambientShade = 0.0f;  // fully flat
    illuminate(l, *b, s);
    EXPECT_NEAR(s.ir[2], 1.0, 1e-6);
}

TEST(Light, FullBatchAndEmptyBatch) {
    Light l;
    l.type = LightType::Point;
    l.position = {0, 0, 2};
    l.decayRate = 1;
    auto b = makeBatch(kBatchSize);
    for (int i = 0; i < kBatchSize; ++i) setPoint(*b, i, {0, 0, -double(i)});
    LightSamples s;
    illuminate(l, *b, s);
    for (int i = 0; i < kBatchSize; ++i) EXPECT_NEAR(s.ir[i], 1.0 / (2.0 + i), 1e-6) << i;
    // count 0 writes nothing.
    s.ir[0] = -7.0f;
    b->count = 0;
    illuminate(l, *b, s);
    EXPECT_EQ(s.ir[0], -7.0f);
}

TEST(Light, TransformedMovesPositionAndTurnsDirection) {
    Light l;
    l.type = LightType::Spot;
    l.position = {1, 0, 0};
    l.direction = {0, 0, -1};
    const glm::dmat4 m = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 5, 0)), std::numbers::pi / 2,
                                     glm::dvec3(0, 1, 0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
    const Light t = transformed(l, m);
    expectVec(t.position, {0, 5, -2}, 1e-9, "position");
    expectVec(t.direction, {-1, 0, 0}, 1e-9, "direction (unit after scale)");
    EXPECT_EQ(t.coneAngle, l.coneAngle);
}

TEST(Light, DefaultLightShinesAlongTheViewDirection) {
    const Light l = defaultLight({0, 0, -2});
    EXPECT_EQ(l.type, LightType::Directional);
    expectVec(l.direction, {0, 0, -1}, 1e-12, "direction");
    auto b = makeBatch(1);
    LightSamples s;
    illuminate(l, *b, s);
    expectVec(dirOf(s, 0), {0, 0, 1}, 1e-6, "L toward the camera");
    expectVec(intensityOf(s, 0), {1, 1, 1}, 1e-6, "I");
    // A degenerate view direction gives a usable light.
    const Light d = defaultLight({0, 0, 0});
    EXPECT_NEAR(glm::length(d.direction), 1.0, 1e-12);
}

}  // namespace
}  // namespace pushpin::shade
