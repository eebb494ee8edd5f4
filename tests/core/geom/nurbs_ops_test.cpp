// Tests of core/geom/nurbs_ops.h: revolve, loft and tessellation against results worked out by hand
// (cylinders, planes, spheres), the curve edits they rely on, and unusable input.
#include "core/geom/nurbs_ops.h"

#include "core/geom/nurbs_primitives.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pushpin::geom {
namespace {

constexpr double kPi = std::numbers::pi;

NurbsCurve line(const glm::dvec3& a, const glm::dvec3& b, int degree = 1) {
    std::vector<glm::dvec4> cvs;
    for (int i = 0; i <= degree; ++i) cvs.emplace_back(a + (b - a) * (double(i) / degree), 1.0);
    std::vector<double> knots(size_t(degree) + 1, 0.0);
    knots.insert(knots.end(), size_t(degree) + 1, 1.0);
    std::string err;
    auto c = NurbsCurve::create(degree, NurbsForm::Open, knots, cvs, false, &err);
    EXPECT_TRUE(c.has_value()) << err;
    return *c;
}

// A clamped cubic through the given CVs with uniform knots over [0, 1].
NurbsCurve cubic(const std::vector<glm::dvec3>& pts) {
    const int spans = int(pts.size()) - 3;
    std::vector<double> knots(4, 0.0);
    for (int k = 1; k < spans; ++k) knots.push_back(double(k) / spans);
    knots.insert(knots.end(), 4, 1.0);
    std::vector<glm::dvec4> cvs;
    for (const glm::dvec3& p : pts) cvs.emplace_back(p, 1.0);
    std::string err;
    auto c = NurbsCurve::create(3, NurbsForm::Open, knots, cvs, false, &err);
    EXPECT_TRUE(c.has_value()) << err;
    return *c;
}

double radiusAboutY(const glm::dvec3& p) { return std::hypot(p.x, p.z); }

// ---- revolve

TEST(NurbsOpsRevolve, LineParallelToTheAxisGivesACylinder) {
    const NurbsCurve profile = line({2, 0, 0}, {2, 3, 0}, 3);
    RevolveParams p;
    p.axis = {0, 1, 0};
    std::string err;
    auto s = revolveCurve(profile, p, &err);
    ASSERT_TRUE(s.has_value()) << err;
    EXPECT_EQ(s->formV(), NurbsForm::Periodic);
    EXPECT_EQ(s->degreeV(), 3);
    EXPECT_EQ(s->cvCountV(), 11);  // 8 sections + 3 wrap-around CVs
    EXPECT_DOUBLE_EQ(s->vMin(), 0.0);
    EXPECT_DOUBLE_EQ(s->vMax(), 8.0);
    EXPECT_EQ(s->cvCountU(), profile.cvCount());
    double worst = 0.0;
    for (int i = 0; i <= 12; ++i) {
        const double u = i / 12.0;
        // Exactly on the circle at the V knots, the height kept.
        for (int k = 0; k <= 8; ++k) {
            const glm::dvec3 q = s->point(u, k);
            EXPECT_NEAR(radiusAboutY(q), 2.0, 1e-12);
            EXPECT_NEAR(q.y, 3.0 * u, 1e-12);
        }
        for (int j = 0; j <= 160; ++j) {
            const glm::dvec3 q = s->point(u, 8.0 * j / 160);
            worst = std::max(worst, std::abs(radiusAboutY(q) - 2.0));
            EXPECT_NEAR(q.y, 3.0 * u, 1e-12);
        }
        // Closed: the seam meets.
        EXPECT_NEAR(glm::length(s->point(u, 0.0) - s->point(u, 8.0)), 0.0, 1e-12);
    }
    // The non-rational cubic circle bulges between knots by a fraction of a percent.
    EXPECT_GT(worst, 1e-5);
    EXPECT_LT(worst, 0.003 * 2.0);
}

TEST(NurbsOpsRevolve, LinearSweepIsTheInscribedPolygon) {
    RevolveParams p;
    p.axis = {0, 1, 0};
    p.degree = 1;
    p.sections = 6;
    auto s = revolveCurve(line({1, 0, 0}, {1, 1, 0}), p, nullptr);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->degreeV(), 1);
    for (int j = 0; j <= 60; ++j) {
        const double r = radiusAboutY(s->point(0.5, 6.0 * j / 60));
        EXPECT_LE(r, 1.0 + 1e-12);
        EXPECT_GE(r, std::cos(kPi / 6) - 1e-12);
    }
    EXPECT_NEAR(radiusAboutY(s->point(0.5, 1.0)), 1.0, 1e-12);
}

TEST(NurbsOpsRevolve, ProfileIsReproducedAtSweepZeroAboutAnyAxis) {
    const NurbsCurve profile = cubic({{1, 0, 0}, {2, 1, 0.5}, {1.5, 2, -0.5}, {0.5, 3, 0}, {1, 4, 1}});
    for (const auto& [axis, pivot] : {std::pair{glm::dvec3(0, 1, 0), glm::dvec3(0.0)},
                                      std::pair{glm::dvec3(1, 1, 0), glm::dvec3(-1, 0, 2)},
                                      std::pair{glm::dvec3(0, 0, -3), glm::dvec3(0.5, 0.5, 0.5)}}) {
        RevolveParams p;
        p.axis = axis;
        p.pivot = pivot;
        auto s = revolveCurve(profile, p, nullptr);
        ASSERT_TRUE(s.has_value());
        const glm::dvec3 a = glm::normalize(axis);
        auto distanceToAxis = [&](const glm::dvec3& q) {
            const glm::dvec3 d = q - pivot;
            return glm::length(d - glm::dot(d, a) * a);
        };
        for (int i = 0; i <= 20; ++i) {
            const double u = i / 20.0;
            const glm::dvec3 c = profile.point(u);
            EXPECT_NEAR(glm::length(s->point(u, 0.0) - c), 0.0, 1e-12);
            // Every knot isoparm keeps the distance to the axis and the height along it.
            for (int k = 1; k <= 8; ++k) {
                const glm::dvec3 q = s->point(u, k);
                EXPECT_NEAR(distanceToAxis(q), distanceToAxis(c), 1e-12);
                EXPECT_NEAR(glm::dot(q - pivot, a), glm::dot(c - pivot, a), 1e-12);
            }
        }
    }
}

TEST(NurbsOpsRevolve, HalfSweepSpansHalfATurnTowardsRadialCrossAxis) {
    RevolveParams p;
    p.axis = {0, 1, 0};
    p.endSweep = kPi;
    p.sections = 4;
    auto s = revolveCurve(line({2, 0, 0}, {2, 1, 0}), p, nullptr);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->formV(), NurbsForm::Open);
    EXPECT_DOUBLE_EQ(s->vMax(), 4.0);
    EXPECT_NEAR(glm::length(s->point(0.5, 0.0) - glm::dvec3(2, 0.5, 0)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(s->point(0.5, 2.0) - glm::dvec3(0, 0.5, 2)), 0.0, 1e-12);  // +X turns to +Z
    EXPECT_NEAR(glm::length(s->point(0.5, 4.0) - glm::dvec3(-2, 0.5, 0)), 0.0, 1e-12);
    // A profile running along +axis gets normals pointing away from the axis.
    const glm::dvec3 n = s->normal(0.5, 1.3);
    const glm::dvec3 q = s->point(0.5, 1.3);
    EXPECT_GT(glm::dot(n, glm::normalize(glm::dvec3(q.x, 0, q.z))), 0.99);
}

TEST(NurbsOpsRevolve, AutoCorrectNormalReversesTheAxisForADownwardProfile) {
    RevolveParams p;
    p.axis = {0, 1, 0};
    p.autoCorrectNormal = true;
    auto s = revolveCurve(line({2, 1, 0}, {2, 0, 0}), p, nullptr);
    ASSERT_TRUE(s.has_value());
    const glm::dvec3 q = s->point(0.5, 1.0);
    EXPECT_GT(glm::dot(s->normal(0.5, 1.0), glm::normalize(glm::dvec3(q.x, 0, q.z))), 0.99);
    p.autoCorrectNormal = false;
    auto inward = revolveCurve(line({2, 1, 0}, {2, 0, 0}), p, nullptr);
    ASSERT_TRUE(inward.has_value());
    const glm::dvec3 qi = inward->point(0.5, 1.0);
    EXPECT_LT(glm::dot(inward->normal(0.5, 1.0), glm::normalize(glm::dvec3(qi.x, 0, qi.z))), -0.99);
    // The reversed axis sweeps the other way round.
    EXPECT_NEAR(q.x, qi.x, 1e-12);
    EXPECT_NEAR(q.z, -qi.z, 1e-12);
}

TEST(NurbsOpsRevolve, ToleranceChoosesTheFewestSectionsThatMeetIt) {
    RevolveParams p;
    p.axis = {0, 1, 0};
    p.useTolerance = true;
    p.tolerance = 1e-4;
    const NurbsCurve profile = line({5, 0, 0}, {5, 1, 0});
    auto s = revolveCurve(profile, p, nullptr);
    ASSERT_TRUE(s.has_value());
    const int sections = s->cvCountV() - 3;
    auto error = [&](const NurbsSurface& surf) {
        double worst = 0.0;
        for (int j = 0; j <= 4000; ++j)
            worst = std::max(worst, std::abs(radiusAboutY(surf.point(0.5, surf.vMax() * j / 4000)) - 5.0));
        return worst;
    };
    EXPECT_LE(error(*s), 1e-4 * 1.01);
    RevolveParams fewer = p;
    fewer.useTolerance = false;
    fewer.sections = sections - 1;
    auto coarser = revolveCurve(profile, fewer, nullptr);
    ASSERT_TRUE(coarser.has_value());
    EXPECT_GT(error(*coarser), 1e-4);
}

TEST(NurbsOpsRevolve, UnusableValuesGiveAReason) {
    const NurbsCurve profile = line({1, 0, 0}, {1, 1, 0});
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<RevolveParams> bad(8);
    bad[0].axis = {nan, 1, 0};
    bad[1].axis = {0, 0, 0};
    bad[2].endSweep = 0.0;
    bad[3].degree = 2;
    bad[4].startSweep = inf;
    bad[5].pivot = {0, nan, 0};
    bad[6].sections = 2;  // a full turn needs 3
    bad[7].useTolerance = true;
    bad[7].tolerance = nan;
    for (size_t k = 0; k < bad.size(); ++k) {
        std::string err;
        EXPECT_FALSE(revolveCurve(profile, bad[k], &err).has_value()) << k;
        EXPECT_FALSE(err.empty()) << k;
    }
    std::string err;
    RevolveParams onAxis;
    onAxis.axis = {0, 1, 0};
    EXPECT_FALSE(revolveCurve(line({0, 0, 0}, {0, 1, 0}), onAxis, &err).has_value());
    EXPECT_NE(err.find("axis"), std::string::npos) << err;
}

// ---- loft

TEST(NurbsOpsLoft, ThreeParallelLinesAreReproducedAtTheirSectionParameters) {
    const std::vector<NurbsCurve> lines = {line({0, 0, 0}, {4, 0, 0}, 3), line({0, 0, 1}, {4, 0, 1}, 3),
                                           line({0, 0, 3}, {4, 0, 3}, 3)};
    for (bool uniform : {true, false}) {
        LoftParams p;
        p.uniform = uniform;
        std::string err;
        auto s = loftCurves(lines, p, &err);
        ASSERT_TRUE(s.has_value()) << err;
        EXPECT_EQ(s->degreeU(), 3);
        EXPECT_EQ(s->cvCountU(), 5);  // 3 sections: 2 spans, natural ends
        const double params[3] = {0.0, uniform ? 1.0 : 1.0, uniform ? 2.0 : 3.0};
        EXPECT_DOUBLE_EQ(s->uMax(), params[2]);
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j <= 10; ++j) {
                const double v = j / 10.0;
                EXPECT_NEAR(glm::length(s->point(params[k], v) - lines[size_t(k)].point(v)), 0.0, 1e-12)
                    << "uniform " << uniform << " section " << k;
            }
        // Interpolating coplanar sections stays in their plane.
        for (int i = 0; i <= 20; ++i) EXPECT_NEAR(s->point(params[2] * i / 20, 0.3).y, 0.0, 1e-12);
    }
}

TEST(NurbsOpsLoft, LinearLoftIsRuledAndSwappingReversesTheNormal) {
    const std::vector<NurbsCurve> lines = {line({0, 0, 0}, {1, 0, 0}), line({0, 1, 0}, {1, 1, 0}),
                                           line({0, 2, 1}, {1, 2, 1})};
    LoftParams p;
    p.degree = 1;
    p.uniform = true;
    auto s = loftCurves(lines, p, nullptr);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->degreeU(), 1);
    EXPECT_NEAR(glm::length(s->point(1.5, 0.5) - glm::dvec3(0.5, 1.5, 0.5)), 0.0, 1e-12);
    p.reverseSurfaceNormals = true;
    auto r = loftCurves(lines, p, nullptr);
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->degreeV(), 1);
    for (double u : {0.2, 0.7})
        for (double v : {0.3, 1.6}) {
            EXPECT_NEAR(glm::length(r->point(u, v) - s->point(v, u)), 0.0, 1e-12);
            EXPECT_NEAR(glm::dot(r->normal(u, v), s->normal(v, u)), -1.0, 1e-9);
        }
}

TEST(NurbsOpsLoft, ClosedLoftIsPeriodicThroughEverySection) {
    auto circle = [](double radius, double z) {
        NurbsCircleParams c;
        c.radius = radius;
        c.center = {0, 0, z};
        return *makeNurbCircle(c, nullptr);
    };
    const std::vector<NurbsCurve> rings = {circle(1, 0), circle(2, 1), circle(1.5, 2), circle(0.5, 1)};
    LoftParams p;
    p.close = true;
    p.uniform = true;
    std::string err;
    auto s = loftCurves(rings, p, &err);
    ASSERT_TRUE(s.has_value()) << err;
    EXPECT_EQ(s->formU(), NurbsForm::Periodic);
    EXPECT_EQ(s->formV(), NurbsForm::Periodic);  // identical circle knots keep their periodic form
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j <= 16; ++j) {
            const double v = rings[0].tMin() + (rings[0].tMax() - rings[0].tMin()) * j / 16;
            EXPECT_NEAR(glm::length(s->point(k, v) - rings[size_t(k)].point(v)), 0.0, 1e-12) << k;
        }
    for (int j = 0; j <= 8; ++j) {
        EXPECT_NEAR(glm::length(s->point(s->uMin(), j) - s->point(s->uMax(), j)), 0.0, 1e-12);
        EXPECT_NEAR(glm::length(s->point(0.3, j) - s->point(4.3, j)), 0.0, 1e-12);
    }
    p.sectionSpans = 3;
    auto fine = loftCurves(rings, p, &err);
    ASSERT_TRUE(fine.has_value()) << err;
    EXPECT_EQ(fine->spansU(), 12);
    for (double u : {0.25, 1.7, 3.9}) EXPECT_NEAR(glm::length(fine->point(u, 2.5) - s->point(u, 2.5)), 0.0, 1e-9);
}

TEST(NurbsOpsLoft, CurvesOfDifferentDegreeAndKnotsAreMadeCompatible) {
    const NurbsCurve a = line({0, 0, 0}, {2, 0, 0}, 1);
    const NurbsCurve b = cubic({{0, 1, 0}, {0.5, 1.5, 0}, {1, 0.5, 0}, {1.5, 1.5, 0}, {2, 1, 0}});
    NurbsCurve c = cubic({{0, 2, 0}, {1, 3, 0}, {2, 2, 0}, {2.5, 2, 0}});
    // A rational quadratic arc (a quarter circle) as a third kind of curve.
    const double w = std::sqrt(0.5);
    auto arc = NurbsCurve::create(2, NurbsForm::Open, {0, 0, 0, 1, 1, 1},
                                  {{0, 3, 0, 1}, {w * 1, w * 4, 0, w}, {2, 4, 0, 1}}, true, nullptr);
    ASSERT_TRUE(arc.has_value());
    const std::vector<NurbsCurve> curves = {a, b, c, *arc};
    LoftParams p;
    p.uniform = true;
    std::string err;
    auto s = loftCurves(curves, p, &err);
    ASSERT_TRUE(s.has_value()) << err;
    EXPECT_EQ(s->degreeV(), 3);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j <= 20; ++j) {
            const double v = j / 20.0;
            EXPECT_NEAR(glm::length(s->point(k, v) - curves[size_t(k)].point(v)), 0.0, 1e-12) << k << " " << v;
        }
}

TEST(NurbsOpsLoft, AutoReverseTurnsAnOpposedCurve) {
    const NurbsCurve a = line({0, 0, 0}, {1, 0, 0}, 3);
    const NurbsCurve b = line({1, 1, 0}, {0, 1, 0}, 3);  // runs the other way
    LoftParams p;
    p.uniform = true;
    auto s = loftCurves({a, b}, p, nullptr);
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(glm::length(s->point(1.0, 0.0) - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
    p.autoReverse = false;
    auto twisted = loftCurves({a, b}, p, nullptr);
    ASSERT_TRUE(twisted.has_value());
    EXPECT_NEAR(glm::length(twisted->point(1.0, 0.0) - glm::dvec3(1, 1, 0)), 0.0, 1e-12);
    p.reverse = {false, true};
    auto explicitFlip = loftCurves({a, b}, p, nullptr);
    ASSERT_TRUE(explicitFlip.has_value());
    EXPECT_NEAR(glm::length(explicitFlip->point(1.0, 0.0) - glm::dvec3(0, 1, 0)), 0.0, 1e-12);
    // Two sections and a cubic loft direction: a straight ruled surface.
    EXPECT_NEAR(glm::length(s->point(0.25, 0.5) - glm::dvec3(0.5, 0.25, 0)), 0.0, 1e-12);
}

TEST(NurbsOpsLoft, UnusableInputGivesAReason) {
    const NurbsCurve a = line({0, 0, 0}, {1, 0, 0});
    std::string err;
    EXPECT_FALSE(loftCurves({a}, {}, &err).has_value());
    EXPECT_FALSE(err.empty());
    LoftParams p;
    p.degree = 2;
    err.clear();
    EXPECT_FALSE(loftCurves({a, a}, p, &err).has_value());
    EXPECT_FALSE(err.empty());
    p.degree = 3;
    p.sectionSpans = 0;
    err.clear();
    EXPECT_FALSE(loftCurves({a, line({0, 1, 0}, {1, 1, 0})}, p, &err).has_value());
    EXPECT_FALSE(err.empty());
    // Two identical sections with uniform spacing still loft (a flat, degenerate surface).
    EXPECT_TRUE(loftCurves({a, a}, LoftParams{.uniform = true}, nullptr).has_value());
}

// ---- curve edits

TEST(NurbsOpsEdits, InsertClampElevateAndReverseKeepTheCurve) {
    NurbsCircleParams cp;
    cp.radius = 2.0;
    const NurbsCurve circle = *makeNurbCircle(cp, nullptr);  // periodic cubic
    const NurbsCurve open = cubic({{0, 0, 0}, {1, 2, 0}, {3, -1, 1}, {4, 0, 2}, {5, 1, 0}});
    for (const NurbsCurve* c : {&circle, &open}) {
        auto inserted = insertKnot(*c, c->tMin() + 0.37 * (c->tMax() - c->tMin()));
        auto clamped = clampCurve(*c);
        auto elevated = elevateCurveDegree(*c, 5);
        auto reversed = reverseCurve(*c);
        ASSERT_TRUE(inserted && clamped && elevated && reversed);
        EXPECT_EQ(inserted->cvCount(), c->cvCount() + 1);
        EXPECT_EQ(elevated->degree(), 5);
        EXPECT_DOUBLE_EQ(clamped->knots().front(), clamped->knots()[3]);
        for (int i = 0; i <= 50; ++i) {
            const double t = c->tMin() + (c->tMax() - c->tMin()) * i / 50;
            const glm::dvec3 q = c->point(t);
            EXPECT_NEAR(glm::length(inserted->point(t) - q), 0.0, 1e-12);
            EXPECT_NEAR(glm::length(clamped->point(t) - q), 0.0, 1e-12);
            EXPECT_NEAR(glm::length(elevated->point(t) - q), 0.0, 1e-12);
            EXPECT_NEAR(glm::length(reversed->point(c->tMin() + c->tMax() - t) - q), 0.0, 1e-12);
        }
    }
    EXPECT_EQ(clampCurve(circle)->form(), NurbsForm::Closed);
    EXPECT_FALSE(insertKnot(open, 2.0).has_value());
    EXPECT_FALSE(elevateCurveDegree(open, 2).has_value());
}

// ---- tessellation

TessellateParams general(int un, int vn, bool quads) {
    TessellateParams p;
    p.format = int(TessellationFormat::General);
    p.polygonType = quads ? 1 : 0;
    p.uNumber = un;
    p.vNumber = vn;
    p.useChordHeightRatio = false;
    return p;
}

TEST(NurbsOpsTessellate, GeneralPerSpanCountsOrderAndUvs) {
    NurbsPlaneParams pp;
    pp.patchesU = 2;
    pp.patchesV = 3;
    pp.axis = {0, 1, 0};
    const NurbsSurface plane = *makeNurbPlane(pp, nullptr);
    for (int k : {1, 2, 5}) {
        const size_t m = size_t(2 * (k + 1) + 1), n = size_t(3 * (k + 1) + 1);
        std::string err;
        auto quads = tessellateSurface(plane, general(k, k, true), &err);
        ASSERT_TRUE(quads.has_value()) << err;
        EXPECT_TRUE(quads->validate().ok());
        EXPECT_EQ(quads->points.size(), m * n);
        EXPECT_EQ(quads->faceCount(), (m - 1) * (n - 1));
        // Vertex j·m + i sits at (u_i, v_j): u fastest, equal steps inside each span.
        const double du = (plane.uMax() - plane.uMin()) / double(m - 1);
        const double dv = (plane.vMax() - plane.vMin()) / double(n - 1);
        for (size_t j = 0; j < n; ++j)
            for (size_t i = 0; i < m; ++i) {
                const glm::dvec3 q = plane.point(plane.uMin() + du * double(i), plane.vMin() + dv * double(j));
                EXPECT_NEAR(glm::length(glm::dvec3(quads->points[j * m + i]) - q), 0.0, 1e-6);
            }
        const auto f0 = quads->faceOuterLoop(0);
        ASSERT_EQ(f0.size(), 4u);
        EXPECT_EQ(std::vector<uint32_t>(f0.begin(), f0.end()),
                  (std::vector<uint32_t>{0, 1, uint32_t(m) + 1, uint32_t(m)}));
        const auto f1 = quads->faceOuterLoop(1);
        EXPECT_EQ(f1[0], 1u);
        // Faces wind with the surface normal (the plane's axis, +Y).
        for (size_t f = 0; f < quads->faceCount(); ++f) EXPECT_GT(quads->faceNormal(f).y, 0.999);
        ASSERT_EQ(quads->uvSets.size(), 1u);
        const UvSet& uv = quads->uvSets[0];
        EXPECT_EQ(uv.name, "map1");
        for (const glm::vec2& t : uv.uvs) {
            EXPECT_GE(t.x, 0.0f);
            EXPECT_LE(t.x, 1.0f);
            EXPECT_GE(t.y, 0.0f);
            EXPECT_LE(t.y, 1.0f);
        }
        EXPECT_EQ(uv.uvs.front(), glm::vec2(0, 0));
        EXPECT_EQ(uv.uvs.back(), glm::vec2(1, 1));
        EXPECT_EQ(uv.faceVertexUvs.size(), quads->faceVertexCount());

        auto tris = tessellateSurface(plane, general(k, k, false), &err);
        ASSERT_TRUE(tris.has_value()) << err;
        EXPECT_EQ(tris->points.size(), m * n);
        EXPECT_EQ(tris->faceCount(), 2 * (m - 1) * (n - 1));
        const auto t0 = tris->faceOuterLoop(0), t1 = tris->faceOuterLoop(1);
        EXPECT_EQ(std::vector<uint32_t>(t0.begin(), t0.end()), (std::vector<uint32_t>{0, 1, uint32_t(m) + 1}));
        EXPECT_EQ(std::vector<uint32_t>(t1.begin(), t1.end()), (std::vector<uint32_t>{0, uint32_t(m) + 1, uint32_t(m)}));
    }
    // Per-surface: number + 1 equal segments over the whole domain, whatever the spans.
    TessellateParams p = general(4, 1, true);
    p.uType = p.vType = int(IsoparmType::SurfaceEquiSpaced);
    auto perSurface = tessellateSurface(plane, p, nullptr);
    ASSERT_TRUE(perSurface.has_value());
    EXPECT_EQ(perSurface->points.size(), size_t(6 * 3));
}

TEST(NurbsOpsTessellate, SphereIsClosedWithWeldedSeamAndPoles) {
    NurbsSphereParams sp;
    sp.axis = {0, 1, 0};
    const NurbsSurface sphere = *makeNurbSphere(sp, nullptr);  // 4 spans pole to pole, 8 sections
    std::string err;
    auto mesh = tessellateSurface(sphere, general(3, 3, true), &err);
    ASSERT_TRUE(mesh.has_value()) << err;
    EXPECT_TRUE(mesh->validate().ok());
    const size_t rings = 4 * 4 - 1, around = 8 * 4;
    EXPECT_EQ(mesh->points.size(), rings * around + 2);
    EXPECT_EQ(mesh->faceCount(), 16u * 32u);
    size_t triangles = 0;
    for (size_t f = 0; f < mesh->faceCount(); ++f) triangles += mesh->faceOuterLoop(f).size() == 3;
    EXPECT_EQ(triangles, 2 * around);
    // Every vertex within the cubic sphere's bulge of the radius; faces point outwards.
    for (const glm::vec3& q : mesh->points) EXPECT_NEAR(glm::length(glm::dvec3(q)), 1.0, 0.003);
    const Bounds3 b = mesh->bounds();
    EXPECT_NEAR(b.hi.y, 1.0, 1e-6);
    EXPECT_NEAR(b.lo.y, -1.0, 1e-6);
    EXPECT_GT(b.hi.x, 0.997);
    EXPECT_LT(b.hi.x, 1.003);
    const double volume = mesh->signedVolume();
    EXPECT_GT(volume, 0.95 * 4.0 / 3.0 * kPi);
    EXPECT_LT(volume, 4.0 / 3.0 * kPi * 1.01);
}

TEST(NurbsOpsTessellate, ChordHeightRefinementBoundsTheDeviation) {
    NurbsSphereParams sp;
    sp.degree = 2;  // the exact rational sphere: deviation is the chord sagitta alone
    sp.axis = {0, 1, 0};
    const NurbsSurface sphere = *makeNurbSphere(sp, nullptr);
    TessellateParams p = general(1, 1, true);
    p.useChordHeight = true;
    p.chordHeight = 0.002;
    std::vector<std::string> notes;
    auto mesh = tessellateSurface(sphere, p, nullptr, &notes);
    ASSERT_TRUE(mesh.has_value());
    EXPECT_FALSE(notes.empty());
    auto coarse = tessellateSurface(sphere, general(1, 1, true), nullptr);
    ASSERT_TRUE(coarse.has_value());
    EXPECT_GT(mesh->points.size(), coarse->points.size());
    // Every edge's midpoint lies within the chord height of the sphere.
    double worst = 0.0;
    for (size_t f = 0; f < mesh->faceCount(); ++f) {
        const auto loop = mesh->faceOuterLoop(f);
        for (size_t k = 0; k < loop.size(); ++k) {
            const glm::dvec3 a(mesh->points[loop[k]]), c(mesh->points[loop[(k + 1) % loop.size()]]);
            worst = std::max(worst, 1.0 - glm::length(0.5 * (a + c)));
        }
        for (uint32_t v : loop) EXPECT_NEAR(glm::length(glm::dvec3(mesh->points[v])), 1.0, 1e-6);
    }
    EXPECT_LE(worst, 0.002 + 1e-6);
}

TEST(NurbsOpsTessellate, ControlPointFormatUsesTheCvHull) {
    NurbsPlaneParams pp;
    pp.patchesU = 2;
    pp.patchesV = 3;
    const NurbsSurface plane = *makeNurbPlane(pp, nullptr);
    TessellateParams p;
    p.format = int(TessellationFormat::ControlPoints);
    p.polygonType = 1;
    auto mesh = tessellateSurface(plane, p, nullptr);
    ASSERT_TRUE(mesh.has_value());
    EXPECT_EQ(mesh->points.size(), size_t(5 * 6));
    EXPECT_EQ(mesh->faceCount(), size_t(4 * 5));
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 5; ++i)
            EXPECT_NEAR(glm::length(glm::dvec3(mesh->points[size_t(j * 5 + i)]) - plane.cvPoint(i, j)), 0.0, 1e-6);
    // A periodic sphere: 8 distinct CVs around (the 3 wrap-around ones joined), the pole rows collapsed.
    NurbsSphereParams sp;
    const NurbsSurface sphere = *makeNurbSphere(sp, nullptr);
    auto hull = tessellateSurface(sphere, p, nullptr);
    ASSERT_TRUE(hull.has_value());
    EXPECT_TRUE(hull->validate().ok());
    EXPECT_EQ(hull->points.size(), size_t(5 * 8 + 2));
}

TEST(NurbsOpsTessellate, OtherFormatsGiveMeshesAndNotes) {
    NurbsSphereParams sp;
    const NurbsSurface sphere = *makeNurbSphere(sp, nullptr);
    TessellateParams count;
    count.format = 0;
    count.polygonCount = 400;
    std::vector<std::string> notes;
    auto a = tessellateSurface(sphere, count, nullptr, &notes);
    ASSERT_TRUE(a.has_value());
    EXPECT_FALSE(notes.empty());
    EXPECT_GT(a->faceCount(), 300u);
    EXPECT_LT(a->faceCount(), 500u);
    notes.clear();
    auto b = tessellateSurface(sphere, TessellateParams{}, nullptr, &notes);  // standard fit
    ASSERT_TRUE(b.has_value());
    EXPECT_TRUE(b->validate().ok());
    EXPECT_FALSE(notes.empty());
}

TEST(NurbsOpsTessellate, UnusableSettingsGiveAReason) {
    const NurbsSurface plane = *makeNurbPlane({}, nullptr);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<TessellateParams> bad(7, general(3, 3, true));
    bad[0].uNumber = 0;
    bad[1].vNumber = -1;
    bad[2].format = 7;
    bad[3].polygonType = 2;
    bad[4].uType = 9;
    bad[5].useChordHeightRatio = true;
    bad[5].chordHeightRatio = nan;
    bad[6].useChordHeight = true;
    bad[6].chordHeight = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < bad.size(); ++k) {
        std::string err;
        EXPECT_FALSE(tessellateSurface(plane, bad[k], &err).has_value()) << k;
        EXPECT_FALSE(err.empty()) << k;
    }
    std::string err;
    EXPECT_FALSE(tessellateSurface(plane, general(100000, 100000, true), &err).has_value());
    EXPECT_NE(err.find("4M"), std::string::npos) << err;
}

}  // namespace
}  // namespace pushpin::geom

namespace pushpin::geom {
namespace {

// Every piece of a detach is the part of the surface over its range, point for point.
void expectPiecesMatch(const NurbsSurface& whole, const std::vector<NurbsSurface>& pieces, bool directionU,
                       const std::vector<double>& ends) {
    ASSERT_EQ(pieces.size() + 1, ends.size());
    for (size_t r = 0; r < pieces.size(); ++r) {
        const NurbsSurface& piece = pieces[r];
        EXPECT_NEAR(directionU ? piece.uMin() : piece.vMin(), ends[r], 1e-12) << r;
        EXPECT_NEAR(directionU ? piece.uMax() : piece.vMax(), ends[r + 1], 1e-12) << r;
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j) {
                const double u = piece.uMin() + (piece.uMax() - piece.uMin()) * i / 8.0;
                const double v = piece.vMin() + (piece.vMax() - piece.vMin()) * j / 8.0;
                const glm::dvec3 a = piece.point(u, v), b = whole.point(u, v);
                EXPECT_NEAR(glm::length(a - b), 0.0, 1e-9) << "piece " << r << " at " << u << ", " << v;
            }
    }
}

TEST(NurbsOpsDetach, ASphereCutAcrossUIsTwoCapsOfTheSameSurface) {
    const NurbsSurface sphere = *makeNurbSphere({}, nullptr);  // u over [0, 4] pole to pole, v periodic
    std::string error;
    const auto pieces = detachSurface(sphere, true, {2.1746218690000001}, &error);
    ASSERT_TRUE(pieces) << error;
    expectPiecesMatch(sphere, *pieces, true, {0.0, 2.1746218690000001, 4.0});
    // The cut is a full-multiplicity knot: the two pieces share their edge CVs.
    const NurbsSurface& low = (*pieces)[0];
    const NurbsSurface& high = (*pieces)[1];
    for (int j = 0; j < sphere.cvCountV(); ++j)
        EXPECT_NEAR(glm::length(low.cvPoint(low.cvCountU() - 1, j) - high.cvPoint(0, j)), 0.0, 1e-12) << j;
    EXPECT_EQ(high.formV(), sphere.formV());
    EXPECT_EQ(low.cvCountV(), sphere.cvCountV());
}

TEST(NurbsOpsDetach, SeveralCutsAcrossVTakeTheInsideOnesOnceInOrder) {
    NurbsPlaneParams p;
    p.patchesU = 2;
    p.patchesV = 3;  // v over [0, 3]
    const NurbsSurface plane = *makeNurbPlane(p, nullptr);
    std::string error;
    // Out of order, one twice, and two outside the domain or on its ends.
    const auto pieces = detachSurface(plane, false, {2.5, 0.75, 2.5, -1.0, 3.0, 0.0}, &error);
    ASSERT_TRUE(pieces) << error;
    expectPiecesMatch(plane, *pieces, false, {0.0, 0.75, 2.5, 3.0});
    // No cut inside: the whole surface.
    const auto whole = detachSurface(plane, false, {}, &error);
    ASSERT_TRUE(whole);
    expectPiecesMatch(plane, *whole, false, {0.0, 3.0});
}

TEST(NurbsOpsDetach, APeriodicDirectionOrABadParameterIsRefused) {
    const NurbsSurface sphere = *makeNurbSphere({}, nullptr);
    std::string error;
    EXPECT_FALSE(detachSurface(sphere, false, {2.0}, &error));  // around the sphere: periodic
    EXPECT_NE(error.find("periodic"), std::string::npos) << error;
    EXPECT_FALSE(detachSurface(sphere, true, {std::numeric_limits<double>::quiet_NaN()}, &error));
    EXPECT_NE(error.find("not finite"), std::string::npos) << error;
    // A flood of cuts is refused rather than worked through one CV pass each.
    std::vector<double> many;
    for (size_t i = 1; i <= kMaxSurfaceEdits + 1; ++i) many.push_back(4.0 * double(i) / double(kMaxSurfaceEdits + 2));
    EXPECT_FALSE(detachSurface(sphere, true, many, &error));
    EXPECT_NE(error.find("cuts"), std::string::npos) << error;
}

}  // namespace
}  // namespace pushpin::geom

namespace pushpin::geom {
namespace {

// The largest distance between a and b at the same fractions of their domains.
double largestGap(const NurbsSurface& a, const NurbsSurface& b) {
    double worst = 0.0;
    for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 10; ++j) {
            const double u = a.uMin() + (a.uMax() - a.uMin()) * i / 10.0, v = a.vMin() + (a.vMax() - a.vMin()) * j / 10.0;
            const double ub = b.uMin() + (b.uMax() - b.uMin()) * i / 10.0, vb = b.vMin() + (b.vMax() - b.vMin()) * j / 10.0;
            worst = std::max(worst, glm::length(a.point(u, v) - b.point(ub, vb)));
        }
    return worst;
}

TEST(NurbsOpsInsertKnots, TheShapeStaysAndTheCvsGrow) {
    NurbsPlaneParams p;
    p.patchesU = 2;
    p.patchesV = 2;
    const NurbsSurface plane = *makeNurbPlane(p, nullptr);
    std::string error;
    // u = 0.5 twice, u = 1 (a knot already) five times (capped at full multiplicity 3), u = 5 outside.
    const auto more = insertSurfaceKnots(plane, true, {{0.5, 2}, {1.0, 5}, {5.0, 1}}, &error);
    ASSERT_TRUE(more) << error;
    EXPECT_EQ(more->cvCountU(), plane.cvCountU() + 2 + 2);
    EXPECT_EQ(more->cvCountV(), plane.cvCountV());
    EXPECT_LT(largestGap(*more, plane), 1e-12);
    const NurbsSurface sphere = *makeNurbSphere({}, nullptr);
    EXPECT_FALSE(insertSurfaceKnots(sphere, false, {{1.0, 1}}, &error));  // around: periodic
}

TEST(NurbsOpsRebuild, AUniformCubicRebuiltToItsOwnSpansIsItself) {
    // Rebuilding interpolates in the same spline space, so a uniform bicubic comes back exactly.
    NurbsPlaneParams p;
    p.patchesU = 4;
    p.patchesV = 4;
    const NurbsSurface plane = *makeNurbPlane(p, nullptr);
    RebuildParams r;
    std::string error;
    const auto same = rebuildSurface(plane, r, &error);
    ASSERT_TRUE(same) << error;
    EXPECT_EQ(same->cvCountU(), 7);
    EXPECT_LT(largestGap(*same, plane), 1e-9);
    // The default sphere: 4 spans pole to pole (open), 8 sections round (periodic).
    const NurbsSurface sphere = *makeNurbSphere({}, nullptr);
    r.spansV = 8;
    r.range = RebuildRange::ZeroToOne;
    const auto round = rebuildSurface(sphere, r, &error);
    ASSERT_TRUE(round) << error;
    EXPECT_EQ(round->formV(), NurbsForm::Periodic);
    EXPECT_NEAR(round->uMax(), 1.0, 1e-12);
    EXPECT_NEAR(round->vMax(), 1.0, 1e-12);
    EXPECT_LT(largestGap(*round, sphere), 1e-9);  // same spans: the same surface over 0 to 1
}

TEST(NurbsOpsRebuild, FewerSpansApproximateAndKeepControlPointsOnlyRemaps) {
    const NurbsSurface sphere = *makeNurbSphere({}, nullptr);
    RebuildParams r;
    r.spansU = 2;
    r.spansV = 6;
    std::string error;
    const auto coarse = rebuildSurface(sphere, r, &error);
    ASSERT_TRUE(coarse) << error;
    EXPECT_EQ(coarse->cvCountU(), 5);
    EXPECT_EQ(coarse->cvCountV(), 9);
    const double gap = largestGap(*coarse, sphere);
    EXPECT_GT(gap, 1e-6);  // a different surface...
    EXPECT_LT(gap, 0.1);   // ...close to the unit sphere
    r.keepControlPoints = true;
    r.range = RebuildRange::ZeroToSpans;
    const auto remapped = rebuildSurface(sphere, r, &error);
    ASSERT_TRUE(remapped) << error;
    EXPECT_EQ(remapped->cvs(), sphere.cvs());
    EXPECT_NEAR(remapped->uMax(), 4.0, 1e-12);
    EXPECT_LT(largestGap(*remapped, sphere), 1e-12);
    r.spansU = 0;
    EXPECT_FALSE(rebuildSurface(sphere, r, &error));
    r.spansU = 4;
    r.degreeV = 0;
    EXPECT_FALSE(rebuildSurface(sphere, r, &error));
}

}  // namespace
}  // namespace pushpin::geom

namespace pushpin::geom {
namespace {

TEST(NurbsOpsExtrude, DistanceMovesTheProfileAlongTheDirection) {
    const NurbsCurve profile = line({0, 0, 0}, {1, 0, 0}, 3);
    ExtrudeParams p;
    p.type = ExtrudeType::Distance;
    p.direction = {0, 3, 0};  // only its direction counts
    p.length = 2.0;
    std::string error;
    const auto s = extrudeCurve(profile, nullptr, p, &error);
    ASSERT_TRUE(s) << error;
    EXPECT_EQ(s->degreeU(), 1);
    for (double u : {0.0, 0.25, 1.0})
        for (double v : {0.0, 0.5, 1.0}) {
            const glm::dvec3 q = s->point(u, v);
            EXPECT_NEAR(glm::length(q - (profile.point(v) + glm::dvec3(0, 2 * u, 0))), 0.0, 1e-12);
        }
    p.length = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(extrudeCurve(profile, nullptr, p, &error));
    p.type = ExtrudeType::Tube;
    p.length = 1.0;
    EXPECT_FALSE(extrudeCurve(profile, nullptr, p, &error));  // no path
}

TEST(NurbsOpsExtrude, FlatAndTubeAlongAStraightPathAreTheSameCylinder) {
    NurbsCircleParams c;
    c.normal = {0, 1, 0};
    const NurbsCurve circle = *makeNurbCircle(c, nullptr);
    const NurbsCurve path = line({0, 5, 0}, {0, 0, 0}, 1);  // runs towards the profile: taken the other way
    ExtrudeParams p;
    p.type = ExtrudeType::Flat;
    std::string error;
    const auto flat = extrudeCurve(circle, &path, p, &error);
    ASSERT_TRUE(flat) << error;
    p.type = ExtrudeType::Tube;
    const auto tube = extrudeCurve(circle, &path, p, &error);
    ASSERT_TRUE(tube) << error;
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
            const double fu = i / 8.0, fv = j / 8.0;
            const glm::dvec3 a = flat->point(flat->uMin() + fu * (flat->uMax() - flat->uMin()), flat->vMin() + fv * (flat->vMax() - flat->vMin()));
            const glm::dvec3 b = tube->point(tube->uMin() + fu * (tube->uMax() - tube->uMin()), tube->vMin() + fv * (tube->vMax() - tube->vMin()));
            EXPECT_NEAR(glm::length(a - b), 0.0, 1e-6) << fu << " " << fv;
            // The profile's own points, lifted from y = 0 (the path's nearer end) to 5.
            const glm::dvec3 onProfile = circle.point(circle.tMin() + fv * (circle.tMax() - circle.tMin()));
            EXPECT_NEAR(glm::length(a - (onProfile + glm::dvec3(0, 5 * fu, 0))), 0.0, 1e-9) << fu << " " << fv;
        }
}

TEST(NurbsOpsExtrude, ATubeRoundAQuarterArcKeepsItsRadius) {
    // A circle of radius 0.25 facing +X at (0, 0, 0), carried round a quarter circle of radius 4
    // in the XZ plane: every point stays 0.25 from the path's arc.
    NurbsCircleParams c;
    c.normal = {1, 0, 0};
    c.radius = 0.25;
    const NurbsCurve circle = *makeNurbCircle(c, nullptr);
    std::vector<glm::dvec4> cvs;
    for (int i = 0; i <= 64; ++i) {
        const double a = 0.5 * kPi * i / 64.0;
        cvs.emplace_back(4.0 * std::sin(a), 0.0, 4.0 - 4.0 * std::cos(a), 1.0);
    }
    std::vector<double> knots = {0};
    for (int i = 0; i <= 64; ++i) knots.push_back(i);
    knots.push_back(64);
    std::string error;
    const auto arc = NurbsCurve::create(1, NurbsForm::Open, knots, cvs, false, &error);
    ASSERT_TRUE(arc) << error;
    ExtrudeParams p;
    const auto tube = extrudeCurve(circle, &*arc, p, &error);
    ASSERT_TRUE(tube) << error;
    double worst = 0.0;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j) {
            const glm::dvec3 q = tube->point(tube->uMin() + (tube->uMax() - tube->uMin()) * i / 20.0,
                                             tube->vMin() + (tube->vMax() - tube->vMin()) * j / 20.0);
            // Distance from the arc of radius 4 about (0, y, 4) in XZ.
            const double rho = std::hypot(q.x, q.z - 4.0);
            worst = std::max(worst, std::abs(std::hypot(rho - 4.0, q.y) - 0.25));
        }
    EXPECT_LT(worst, 0.01);
}

}  // namespace
}  // namespace pushpin::geom
