// Tests of core/geom/nurbs.h: knots, basis functions, exact evaluation, derivatives, validation.
#include "core/geom/nurbs.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace pushpin::geom {
namespace {

// The single-span bicubic patch of reference/ma-format.md ("NURBS data"), CVs as written (U-major).
NurbsSurface workedPatch() {
    const double xs[4] = {-1.5, -0.5, 0.5, 1.5};
    const double zs[4] = {1.5, 0.5, -0.5, -1.5};
    std::vector<glm::dvec4> cvs;
    for (double x : xs)
        for (double z : zs) cvs.emplace_back(x, 0.0, z, 1.0);
    const std::vector<double> maya = {0, 0, 0, 1, 1, 1};
    auto s = NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open,
                                  textbookKnotsFromMaya(maya, 3, NurbsForm::Open),
                                  textbookKnotsFromMaya(maya, 3, NurbsForm::Open), 4, 4, cvs, false, nullptr);
    EXPECT_TRUE(s.has_value());
    return *s;
}

// A rational, non-uniform bicubic × biquadratic surface with wavy CVs and weights.
NurbsSurface wavySurface() {
    const int nu = 6, nv = 5;
    std::vector<double> ku = {0, 0, 0, 0, 0.5, 1.25, 3, 3, 3, 3};
    std::vector<double> kv = {-1, -1, -1, 0.2, 0.7, 2, 2, 2};
    std::vector<glm::dvec4> cvs;
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            const double w = 0.6 + 0.35 * std::sin(1.3 * i + 0.7 * j) + 0.4;
            glm::dvec3 p(i * 0.8, std::cos(i * 0.9) * std::sin(j * 1.1), j * 0.6 + 0.1 * i * j);
            cvs.emplace_back(p * w, w);
        }
    }
    std::string err;
    auto s = NurbsSurface::create(3, 2, NurbsForm::Open, NurbsForm::Open, ku, kv, nu, nv, cvs, true, &err);
    EXPECT_TRUE(s.has_value()) << err;
    return *s;
}

TEST(NurbsBasis, PartitionOfUnityNonNegativeAndDerivativesSumToZero) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int degree = 1; degree <= 7; ++degree) {
        for (int trial = 0; trial < 20; ++trial) {
            const int cvCount = degree + 1 + int(uni(rng) * 6);
            std::vector<double> knots;
            double k = -1.0 + uni(rng);
            for (int i = 0; i < cvCount + degree + 1; ++i) {
                knots.push_back(k);
                if (uni(rng) < 0.7) k += 0.1 + uni(rng);  // repeated knots happen
            }
            if (!validateKnots(knots, degree, cvCount, "test").empty()) continue;
            const double lo = knots[size_t(degree)], hi = knots[size_t(cvCount)];
            for (int s = 0; s <= 50; ++s) {
                const double t = lo + (hi - lo) * s / 50.0;
                const int span = findKnotSpan(degree, knots, cvCount, t);
                ASSERT_GE(span, degree);
                ASSERT_LE(span, cvCount - 1);
                ASSERT_LT(knots[size_t(span)], knots[size_t(span) + 1]);
                double N[kMaxNurbsDegree + 1], dN[kMaxNurbsDegree + 1];
                basisFunctions(span, t, degree, knots, N, dN);
                double sum = 0.0, dsum = 0.0;
                for (int r = 0; r <= degree; ++r) {
                    EXPECT_GE(N[r], -1e-15);
                    sum += N[r];
                    dsum += dN[r];
                }
                EXPECT_NEAR(sum, 1.0, 1e-12) << "degree " << degree << " t " << t;
                EXPECT_NEAR(dsum, 0.0, 1e-9) << "degree " << degree << " t " << t;
            }
        }
    }
}

TEST(NurbsBasis, DerivativesMatchFiniteDifferences) {
    const std::vector<double> knots = {0, 0, 0, 0, 0.3, 0.3, 1.1, 2, 2.5, 2.5, 2.5, 2.5};
    const int degree = 3, cvCount = 8;
    ASSERT_EQ(validateKnots(knots, degree, cvCount, "U"), "");
    for (double t : {0.1, 0.2, 0.5, 0.9, 1.5, 2.2, 2.45}) {
        const int span = findKnotSpan(degree, knots, cvCount, t);
        double N[4], dN[4], Np[4], Nm[4];
        basisFunctions(span, t, degree, knots, N, dN);
        const double h = 1e-6;
        basisFunctions(span, t + h, degree, knots, Np);
        basisFunctions(span, t - h, degree, knots, Nm);
        for (int r = 0; r <= degree; ++r) EXPECT_NEAR(dN[r], (Np[r] - Nm[r]) / (2 * h), 1e-6) << t;
    }
}

TEST(NurbsKnots, MayaOpenVectorGetsRepeatedEndKnots) {
    const std::vector<double> maya = {0, 0, 0, 1, 2, 3, 4, 4, 4};
    const std::vector<double> expected = {0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4};
    EXPECT_EQ(textbookKnotsFromMaya(maya, 3, NurbsForm::Open), expected);
    EXPECT_EQ(textbookKnotsFromMaya(maya, 3, NurbsForm::Closed), expected);
    EXPECT_EQ(mayaKnotsFromTextbook(expected), maya);
    EXPECT_TRUE(textbookKnotsFromMaya({}, 3, NurbsForm::Open).empty());
}

TEST(NurbsKnots, MayaPeriodicVectorIsExtendedByTheKnotSpacing) {
    std::vector<double> maya;
    for (int k = -2; k <= 10; ++k) maya.push_back(k);
    std::vector<double> expected;
    for (int k = -3; k <= 11; ++k) expected.push_back(k);
    EXPECT_EQ(textbookKnotsFromMaya(maya, 3, NurbsForm::Periodic), expected);

    // Non-uniform periodic cubic, 4 spans with spacings 1, 2, 1, 3 repeating: the spacing one period
    // away is used, not the neighbouring one.
    const std::vector<double> mayaNu = {-4, -3, 0, 1, 3, 4, 7, 8, 10};
    const std::vector<double> full = textbookKnotsFromMaya(mayaNu, 3, NurbsForm::Periodic);
    ASSERT_EQ(full.size(), 11u);
    EXPECT_DOUBLE_EQ(full.front(), -6.0);
    EXPECT_DOUBLE_EQ(full.back(), 11.0);
}

TEST(NurbsSurface, WorkedBicubicPatchIsThePlaneThroughItsCorners) {
    const NurbsSurface s = workedPatch();
    EXPECT_EQ(s.cvCountU(), 4);
    EXPECT_DOUBLE_EQ(s.uMin(), 0.0);
    EXPECT_DOUBLE_EQ(s.uMax(), 1.0);
    const glm::dvec3 c00 = s.point(0, 0), c11 = s.point(1, 1), c01 = s.point(0, 1), c10 = s.point(1, 0);
    EXPECT_NEAR(glm::length(c00 - glm::dvec3(-1.5, 0, 1.5)), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(c01 - glm::dvec3(-1.5, 0, -1.5)), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(c10 - glm::dvec3(1.5, 0, 1.5)), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(c11 - glm::dvec3(1.5, 0, -1.5)), 0.0, 1e-15);
    for (int i = 0; i <= 10; ++i) {
        for (int j = 0; j <= 10; ++j) {
            const double u = i / 10.0, v = j / 10.0;
            const NurbsSurfacePoint p = s.evaluate(u, v);
            // CVs at the Greville points: the parametrisation is linear.
            EXPECT_NEAR(p.position.x, -1.5 + 3 * u, 1e-14);
            EXPECT_NEAR(p.position.y, 0.0, 1e-15);
            EXPECT_NEAR(p.position.z, 1.5 - 3 * v, 1e-14);
            EXPECT_NEAR(glm::length(p.normal() - glm::dvec3(0, 1, 0)), 0.0, 1e-14);
        }
    }
    const Bounds3 b = s.bounds();
    EXPECT_EQ(b.lo, glm::dvec3(-1.5, 0, -1.5));
    EXPECT_EQ(b.hi, glm::dvec3(1.5, 0, 1.5));
}

TEST(NurbsSurface, PartialDerivativesMatchFiniteDifferences) {
    const NurbsSurface s = wavySurface();
    const double h = 1e-6;
    for (double u : {0.05, 0.4, 0.5, 1.0, 2.2, 2.9}) {
        for (double v : {-0.8, 0.1, 0.2, 1.0, 1.9}) {
            const NurbsSurfacePoint p = s.evaluate(u, v);
            const glm::dvec3 fu = (s.point(u + h, v) - s.point(u - h, v)) / (2 * h);
            const glm::dvec3 fv = (s.point(u, v + h) - s.point(u, v - h)) / (2 * h);
            EXPECT_NEAR(glm::length(p.dPdu - fu), 0.0, 1e-6 * (1 + glm::length(fu))) << u << "," << v;
            EXPECT_NEAR(glm::length(p.dPdv - fv), 0.0, 1e-6 * (1 + glm::length(fv))) << u << "," << v;
        }
    }
}

TEST(NurbsSurface, PointsLieInsideTheControlHullBounds) {
    const NurbsSurface s = wavySurface();
    const Bounds3 b = s.bounds();
    for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j <= 40; ++j) {
            const glm::dvec3 p = s.point(s.uMin() + (s.uMax() - s.uMin()) * i / 40, s.vMin() + (s.vMax() - s.vMin()) * j / 40);
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, b.lo - 1e-12)) && glm::all(glm::lessThanEqual(p, b.hi + 1e-12)));
        }
    }
}

TEST(NurbsSurface, OutOfDomainParametersAreClampedAndNonFiniteOnesSafe) {
    const NurbsSurface s = workedPatch();
    EXPECT_EQ(s.point(-5, 0.5), s.point(0, 0.5));
    EXPECT_EQ(s.point(7, 0.5), s.point(1, 0.5));
    const glm::dvec3 p = s.point(std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity());
    EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

TEST(NurbsCurve, RationalQuadraticCircleIsExactAndPeriodicWraps) {
    // Full circle from four 90° arcs: weights 1, √½, 1, …
    const double r = 2.5, w = std::sqrt(0.5);
    const glm::dvec3 pts[9] = {{r, 0, 0}, {r, r, 0}, {0, r, 0}, {-r, r, 0}, {-r, 0, 0},
                               {-r, -r, 0}, {0, -r, 0}, {r, -r, 0}, {r, 0, 0}};
    std::vector<glm::dvec4> cvs;
    for (int i = 0; i < 9; ++i) {
        const double wi = (i % 2) ? w : 1.0;
        cvs.emplace_back(pts[i] * wi, wi);
    }
    std::vector<double> knots = {0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4};
    std::string err;
    auto c = NurbsCurve::create(2, NurbsForm::Closed, knots, cvs, true, &err);
    ASSERT_TRUE(c.has_value()) << err;
    double worst = 0.0;
    for (int i = 0; i <= 1000; ++i) {
        const double t = 4.0 * i / 1000;
        glm::dvec3 p, d;
        c->evaluate(t, &p, &d);
        worst = std::max(worst, std::abs(glm::length(p) - r));
        EXPECT_NEAR(glm::dot(p, d), 0.0, 1e-9);  // tangent ⟂ radius
    }
    EXPECT_LT(worst, 1e-13);

    // A periodic uniform cubic wraps its parameter.
    std::vector<glm::dvec4> pc;
    for (int j = 0; j < 11; ++j) {
        const double a = 2 * std::numbers::pi * ((j - 1 + 8) % 8) / 8.0;
        pc.emplace_back(std::cos(a), std::sin(a), 0.0, 1.0);
    }
    std::vector<double> mk;
    for (int k = -2; k <= 10; ++k) mk.push_back(k);
    auto pcurve = NurbsCurve::create(3, NurbsForm::Periodic, textbookKnotsFromMaya(mk, 3, NurbsForm::Periodic), pc,
                                     false, &err);
    ASSERT_TRUE(pcurve.has_value()) << err;
    EXPECT_DOUBLE_EQ(pcurve->tMin(), 0.0);
    EXPECT_DOUBLE_EQ(pcurve->tMax(), 8.0);
    EXPECT_NEAR(glm::length(pcurve->point(9.25) - pcurve->point(1.25)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(pcurve->point(-0.5) - pcurve->point(7.5)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(pcurve->point(0.0) - pcurve->point(8.0)), 0.0, 1e-12);
}

TEST(NurbsValidation, BadDataGivesClearErrors) {
    std::string err;
    const std::vector<double> good = {0, 0, 0, 0, 1, 1, 1, 1};
    std::vector<glm::dvec4> cvs(16, glm::dvec4(0, 0, 0, 1));

    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, {0, 0, 0, 1, 1, 1, 1}, good, 4, 4, cvs,
                                      false, &err));
    EXPECT_NE(err.find("U: 7 knots, expected 8"), std::string::npos) << err;

    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, good, {0, 0, 0, 2, 1, 1, 1, 1}, 4, 4,
                                      cvs, false, &err));
    EXPECT_NE(err.find("V: knots decrease at index 4"), std::string::npos) << err;

    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, good, good, 4, 4,
                                      std::vector<glm::dvec4>(15, glm::dvec4(0, 0, 0, 1)), false, &err));
    EXPECT_NE(err.find("15 CVs, expected 4 × 4 = 16"), std::string::npos) << err;

    auto nanCvs = cvs;
    nanCvs[6].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, good, good, 4, 4, nanCvs, false, &err));
    EXPECT_NE(err.find("CV [1][2] is not finite"), std::string::npos) << err;

    auto zeroW = cvs;
    zeroW[3].w = 0.0;
    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, good, good, 4, 4, zeroW, true, &err));
    EXPECT_NE(err.find("weight 0"), std::string::npos) << err;

    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, {0, 0, 0, 0, 0, 0, 0, 0}, good, 4, 4,
                                      cvs, false, &err));
    EXPECT_NE(err.find("empty parameter domain"), std::string::npos) << err;

    EXPECT_FALSE(NurbsSurface::create(0, 3, NurbsForm::Open, NurbsForm::Open, good, good, 4, 4, cvs, false, &err));
    EXPECT_NE(err.find("U degree 0"), std::string::npos) << err;

    EXPECT_FALSE(NurbsSurface::create(3, 3, NurbsForm::Open, NurbsForm::Open, {0, 0, 0, 1, 1, 1}, good, 2, 8, cvs,
                                      false, &err));
    EXPECT_NE(err.find("too few for degree 3"), std::string::npos) << err;

    std::vector<double> infKnots = good;
    infKnots[4] = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(NurbsCurve::create(3, NurbsForm::Open, infKnots, std::vector<glm::dvec4>(4, glm::dvec4(0, 0, 0, 1)),
                                    false, &err));
    EXPECT_NE(err.find("curve: knot 4 is not finite"), std::string::npos) << err;
}

}  // namespace
}  // namespace pushpin::geom
