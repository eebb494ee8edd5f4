// Tests of core/geom/nurbs_primitives.h: Maya's NURBS primitives against CVs Maya wrote to files, and
// their geometric properties (radius, flatness, extents, apex, torus distances).
#include "core/geom/nurbs_primitives.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

namespace pushpin::geom {
namespace {

constexpr double kPi = std::numbers::pi;

double maxRadiusError(const NurbsSurface& s, const glm::dvec3& center, double radius, int n) {
    double worst = 0.0;
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
            const double u = s.uMin() + (s.uMax() - s.uMin()) * i / n;
            const double v = s.vMin() + (s.vMax() - s.vMin()) * j / n;
            worst = std::max(worst, std::abs(glm::length(s.point(u, v) - center) - radius));
        }
    }
    return worst;
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol, const char* what) {
    EXPECT_NEAR(glm::length(a - b), 0.0, tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x
                                               << ", " << b.y << ", " << b.z << ")";
}

TEST(NurbsPrimitives, DefaultCubicSphereReproducesMayasCvsAndKnots) {
    // Values from a default nurbsSphere (axis +Y) stored by Maya with its .cc data
    // (tws0002/pop2-project CarrotTop.ma, rightEyeShape1).
    NurbsSphereParams p;
    p.axis = {0, 1, 0};
    std::string err;
    auto s = makeNurbSphere(p, &err);
    ASSERT_TRUE(s.has_value()) << err;
    ASSERT_EQ(s->cvCountU(), 7);
    ASSERT_EQ(s->cvCountV(), 11);
    EXPECT_EQ(s->formU(), NurbsForm::Open);
    EXPECT_EQ(s->formV(), NurbsForm::Periodic);
    EXPECT_EQ(mayaKnotsFromTextbook(s->knotsU()), (std::vector<double>{0, 0, 0, 1, 2, 3, 4, 4, 4}));
    std::vector<double> kv;
    for (int k = -2; k <= 10; ++k) kv.push_back(k);
    EXPECT_EQ(mayaKnotsFromTextbook(s->knotsV()), kv);
    const double tol = 1e-13;
    expectNear(s->cvPoint(0, 5), {0, -1, 0}, tol, "south pole");
    expectNear(s->cvPoint(1, 0), {0.19991679083637254, -1, -0.19991679083637298}, tol, "row 1 cv 0");
    expectNear(s->cvPoint(1, 1), {0.2827250369469036, -1, 0}, tol, "row 1 cv 1");
    expectNear(s->cvPoint(2, 0), {0.61642997969058899, -0.78361162489122427, -0.61642997969058999}, tol, "row 2 cv 0");
    expectNear(s->cvPoint(2, 3), {0, -0.78361162489122427, 0.87176363753180319}, tol, "row 2 cv 3");
    expectNear(s->cvPoint(3, 1), {1.2264094625656803, 0, 0}, tol, "row 3 cv 1");
    expectNear(s->cvPoint(3, 6), {-0.86720244749154174, 0, -0.86720244749154141}, tol, "row 3 cv 6");
    expectNear(s->cvPoint(4, 1), {0.87176363753180341, 0.78361162489122449, 0}, tol, "row 4 cv 1");
    expectNear(s->cvPoint(5, 2), {0.1999167908363727, 1, 0.19991679083637293}, tol, "row 5 cv 2");
    expectNear(s->cvPoint(6, 9), {0, 1, 0}, tol, "north pole");
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_EQ(s->cv(i, j), s->cv(i, j + 8)) << "wrap-around CVs repeat";
}

TEST(NurbsPrimitives, CubicCylinderReproducesMayasCvsAndKnots) {
    // An 8-span cylinder (radius 1, heightRatio 2, axis +Y) as Maya stored it in an "Orig" shape.
    NurbsCylinderParams p;
    p.axis = {0, 1, 0};
    p.spans = 8;
    std::string err;
    auto s = makeNurbCylinder(p, &err);
    ASSERT_TRUE(s.has_value()) << err;
    ASSERT_EQ(s->cvCountU(), 11);
    ASSERT_EQ(s->cvCountV(), 11);
    EXPECT_EQ(mayaKnotsFromTextbook(s->knotsU()),
              (std::vector<double>{0, 0, 0, 0.25, 0.5, 0.75, 1, 1.25, 1.5, 1.75, 2, 2, 2}));
    const double tol = 1e-13;
    expectNear(s->cvPoint(0, 0), {0.78361162489122382, -1, -0.78361162489122516}, tol, "cv 0 0");
    expectNear(s->cvPoint(0, 1), {1.1081941875543879, -1, 0}, tol, "cv 0 1");
    expectNear(s->cvPoint(1, 3), {0, -0.91666666666666663, 1.1081941875543879}, tol, "cv 1 3");
    expectNear(s->cvPoint(2, 5), {-1.1081941875543881, -0.75, 0}, tol, "cv 2 5");
    expectNear(s->cvPoint(5, 0), {0.78361162489122382, 0, -0.78361162489122504}, tol, "cv 5 0");
    expectNear(s->cvPoint(10, 2), {0.78361162489122427, 1, 0.78361162489122438}, tol, "cv 10 2");
}

TEST(NurbsPrimitives, CubicSphereIsExactAtKnotsAndBulgesSlightlyBetween) {
    NurbsSphereParams p;
    p.axis = {0, 1, 0};
    auto s = makeNurbSphere(p, nullptr);
    ASSERT_TRUE(s.has_value());
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 8; ++j) EXPECT_NEAR(glm::length(s->point(i, j)), 1.0, 1e-14) << i << "," << j;
    const double worst = maxRadiusError(*s, glm::dvec3(0.0), 1.0, 400);
    std::printf("[ measure  ] default cubic makeNurbSphere: max |r - 1| over a 401x401 grid = %.6g\n", worst);
    EXPECT_GT(worst, 1e-4);  // Maya's cubic sphere is not a true sphere …
    EXPECT_LT(worst, 3e-3);  // … but close to one.
}

TEST(NurbsPrimitives, RationalSphereIsWithin1e6OfItsRadiusEverywhere) {
    struct Case {
        double radius;
        glm::dvec3 axis, pivot;
        int sections, spans;
    };
    const Case cases[] = {
        {1.0, {0, 1, 0}, {0, 0, 0}, 8, 4},
        {3.7, {1, 2, -0.5}, {4, -2, 1}, 8, 4},
        {0.02, {0, 0, -1}, {1e3, 0, 0}, 3, 2},
        {12.5, {-1, 0, 0}, {0, 5, 0}, 16, 7},
    };
    for (const Case& c : cases) {
        NurbsSphereParams p;
        p.radius = c.radius;
        p.axis = c.axis;
        p.pivot = c.pivot;
        p.sections = c.sections;
        p.spans = c.spans;
        p.degree = 2;  // makeNurbSphere's exact branch
        std::string err;
        auto s = makeNurbSphere(p, &err);
        ASSERT_TRUE(s.has_value()) << err;
        EXPECT_TRUE(s->rational());
        const double worst = maxRadiusError(*s, c.pivot, c.radius, 300);
        EXPECT_LT(worst, 1e-6 * c.radius);
        EXPECT_LT(worst, 1e-12 * (c.radius + glm::length(c.pivot)));
        // The poles lie on the axis.
        const glm::dvec3 a = glm::normalize(c.axis);
        expectNear(s->point(s->uMin(), 0.3), c.pivot - a * c.radius, 1e-12 * (1 + glm::length(c.pivot)), "south");
        expectNear(s->point(s->uMax(), 0.3), c.pivot + a * c.radius, 1e-12 * (1 + glm::length(c.pivot)), "north");
    }
}

TEST(NurbsPrimitives, PartialSpheresStayOnTheSphereAndInsideTheSweep) {
    NurbsSphereParams p;
    p.axis = {0, 1, 0};
    p.startSweep = 0.3;
    p.endSweep = 2.0;
    p.sections = 3;
    auto exact = makeRationalSphere(p, nullptr);
    ASSERT_TRUE(exact.has_value());
    EXPECT_LT(maxRadiusError(*exact, glm::dvec3(0.0), 1.0, 100), 1e-12);
    auto cubic = makeNurbSphere(p, nullptr);
    ASSERT_TRUE(cubic.has_value());
    EXPECT_EQ(cubic->formV(), NurbsForm::Open);
    EXPECT_EQ(cubic->cvCountV(), 6);
    for (int i = 0; i <= 4; ++i) {
        for (int j = 0; j <= 3; ++j) {
            const glm::dvec3 q = cubic->point(i, j);
            EXPECT_NEAR(glm::length(q), 1.0, 1e-13);
            if (i != 0 && i != 4) {
                EXPECT_NEAR(std::atan2(q.z, q.x), 0.3 + 1.7 * j / 3, 1e-12);
            }
        }
    }
}

TEST(NurbsPrimitives, SphereDerivativesMatchFiniteDifferencesAndNormalsPointOut) {
    NurbsSphereParams p;
    p.radius = 2.0;
    p.axis = {0, 0, 1};
    for (int degree : {2, 3}) {
        p.degree = degree;
        auto s = makeNurbSphere(p, nullptr);
        ASSERT_TRUE(s.has_value());
        const double h = 1e-6;
        for (double u : {0.0, 0.3, 1.7, 2.5, s->uMax()}) {
            for (double v : {0.1, 2.6, 5.5}) {
                const NurbsSurfacePoint q = s->evaluate(u, v);
                if (u > 0.0 && u < s->uMax()) {
                    const glm::dvec3 fu = (s->point(u + h, v) - s->point(u - h, v)) / (2 * h);
                    const glm::dvec3 fv = (s->point(u, v + h) - s->point(u, v - h)) / (2 * h);
                    EXPECT_NEAR(glm::length(q.dPdu - fu), 0.0, 1e-6);
                    EXPECT_NEAR(glm::length(q.dPdv - fv), 0.0, 1e-6);
                }
                const glm::dvec3 n = s->normal(u, v);
                EXPECT_NEAR(glm::length(n), 1.0, 1e-9) << "normal defined at poles too";
                EXPECT_GT(std::abs(glm::dot(n, glm::normalize(q.position))), 0.99);
            }
        }
    }
}

TEST(NurbsPrimitives, PlaneIsFlatWithTheRequestedExtent) {
    for (int degree : {1, 2, 3, 5, 7}) {
        NurbsPlaneParams p;
        p.width = 24;
        p.lengthRatio = 0.5;
        p.patchesU = 4;
        p.patchesV = 3;
        p.degree = degree;
        p.axis = {0, 2, 0};
        p.pivot = {1, 2, 3};
        std::string err;
        auto s = makeNurbPlane(p, &err);
        ASSERT_TRUE(s.has_value()) << err;
        EXPECT_EQ(s->cvCountU(), 4 + degree);
        EXPECT_EQ(s->cvCountV(), 3 + degree);
        EXPECT_DOUBLE_EQ(s->uMax(), 4.0);
        EXPECT_DOUBLE_EQ(s->vMax(), 3.0);
        Bounds3 b;
        for (int i = 0; i <= 20; ++i) {
            for (int j = 0; j <= 20; ++j) {
                const NurbsSurfacePoint q = s->evaluate(4.0 * i / 20, 3.0 * j / 20);
                EXPECT_NEAR(q.position.y, 2.0, 1e-12);
                expectNear(q.normal(), {0, 1, 0}, 1e-12, "normal along the axis");
                b.extend(q.position);
            }
        }
        expectNear(b.lo, {1 - 12, 2, 3 - 6}, 1e-12, "lo");
        expectNear(b.hi, {1 + 12, 2, 3 + 6}, 1e-12, "hi");
    }
}

TEST(NurbsPrimitives, CylinderHasItsRadiusAtKnotsAndItsHeight) {
    NurbsCylinderParams p;
    p.radius = 1.5;
    p.heightRatio = 4;
    p.sections = 11;
    p.spans = 4;
    p.axis = {0, 1, 0};
    auto s = makeNurbCylinder(p, nullptr);
    ASSERT_TRUE(s.has_value());
    EXPECT_DOUBLE_EQ(s->uMax(), 6.0);  // parametrised by the profile length
    for (int i = 0; i <= 8; ++i) {
        const double u = 6.0 * i / 8;
        for (int j = 0; j <= 11; ++j) {
            const glm::dvec3 q = s->point(u, j);
            EXPECT_NEAR(std::hypot(q.x, q.z), 1.5, 1e-13);
            EXPECT_NEAR(q.y, -3.0 + u, 1e-13);
        }
    }
    const double worst = [&] {
        double w = 0;
        for (int j = 0; j <= 500; ++j) {
            const glm::dvec3 q = s->point(1.0, 11.0 * j / 500);
            w = std::max(w, std::abs(std::hypot(q.x, q.z) - 1.5));
        }
        return w;
    }();
    EXPECT_LT(worst, 0.01 * 1.5);
}

TEST(NurbsPrimitives, ConeEndsInItsApex) {
    NurbsConeParams p;
    p.radius = 2;
    p.heightRatio = 1.5;
    p.axis = {0, 0, 1};
    p.pivot = {1, 1, 1};
    auto s = makeNurbCone(p, nullptr);
    ASSERT_TRUE(s.has_value());
    const glm::dvec3 apex = p.pivot + glm::dvec3(0, 0, 1.5);
    for (int j = 0; j <= 16; ++j) {
        expectNear(s->point(s->uMax(), 8.0 * j / 16), apex, 1e-13, "apex");
        const glm::dvec3 base = s->point(s->uMin(), j / 2.0);
        EXPECT_NEAR(base.z, 1.0 - 1.5, 1e-13);
        if (j % 2 == 0) {
            EXPECT_NEAR(glm::length(glm::dvec2(base.x - 1, base.y - 1)), 2.0, 1e-13);
        }
    }
    EXPECT_NEAR(s->uMax(), std::hypot(2.0, 3.0), 1e-14);
}

TEST(NurbsPrimitives, TorusPointsAreAtTheMinorRadiusFromTheTubeCircle) {
    NurbsTorusParams p;
    p.radius = 3;
    p.heightRatio = 0.25;
    p.axis = {0, 1, 0};
    for (int degree : {1, 3}) {
        p.degree = degree;
        auto s = makeNurbTorus(p, nullptr);
        ASSERT_TRUE(s.has_value());
        EXPECT_EQ(s->formU(), NurbsForm::Periodic);
        auto tubeDistance = [&](const glm::dvec3& q) { return std::hypot(std::hypot(q.x, q.z) - 3.0, q.y); };
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; j <= 8; ++j) EXPECT_NEAR(tubeDistance(s->point(i, j)), 0.75, 1e-13);
        double worst = 0;
        for (int i = 0; i <= 100; ++i)
            for (int j = 0; j <= 100; ++j) worst = std::max(worst, std::abs(tubeDistance(s->point(0.04 * i, 0.08 * j)) - 0.75));
        // 4 spans around the tube: the cubic stays within 5% of the minor radius, the polygon within 60%.
        EXPECT_LT(worst, degree == 3 ? 0.05 * 0.75 : 0.6 * 0.75);
    }
}

TEST(NurbsPrimitives, CubeFacesCloseTheBoxWithOutwardNormals) {
    NurbsCubeParams p;
    p.width = 2;
    p.lengthRatio = 3;
    p.heightRatio = 0.5;
    p.patchesU = 2;
    p.patchesV = 3;
    p.axis = {0, 1, 0};
    p.pivot = {5, 0, 0};
    std::string err;
    auto faces = makeNurbCube(p, &err);
    ASSERT_TRUE(faces.has_value()) << err;
    ASSERT_EQ(faces->size(), 6u);
    Bounds3 all;
    const glm::dvec3 expectedNormals[6] = {{0, 1, 0}, {0, -1, 0}, {-1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    for (size_t f = 0; f < 6; ++f) {
        const NurbsSurface& s = (*faces)[f];
        const double um = 0.5 * (s.uMin() + s.uMax()), vm = 0.5 * (s.vMin() + s.vMax());
        expectNear(s.normal(um, vm), expectedNormals[f], 1e-12, "face normal");
        all.extend(s.bounds());
    }
    expectNear(all.lo, {4, -0.5, -3}, 1e-12, "lo");
    expectNear(all.hi, {6, 0.5, 3}, 1e-12, "hi");
}

TEST(NurbsPrimitives, CircleMatchesMayasCvLayout) {
    // Maya's 8-section circle with normal +Y has CV 0 at 45° between +X and −Z and CV 1 on −Z; with
    // normal +X CV 1 is on +Y (CVs from nurbsCircle shapes stored in .ma files).
    NurbsCircleParams p;
    p.normal = {0, 1, 0};
    auto c = makeNurbCircle(p, nullptr);
    ASSERT_TRUE(c.has_value());
    ASSERT_EQ(c->cvCount(), 11);
    const double k = 3.0 / (2.0 + std::sqrt(0.5));
    expectNear(glm::dvec3(c->cvs()[0]), k * glm::dvec3(std::sqrt(0.5), 0, -std::sqrt(0.5)), 1e-13, "cv0");
    expectNear(glm::dvec3(c->cvs()[1]), k * glm::dvec3(0, 0, -1), 1e-13, "cv1");
    p.normal = {1, 0, 0};
    auto cx = makeNurbCircle(p, nullptr);
    ASSERT_TRUE(cx.has_value());
    expectNear(glm::dvec3(cx->cvs()[1]), k * glm::dvec3(0, 1, 0), 1e-13, "cv1 normal x");
    for (int i = 0; i <= 8; ++i) EXPECT_NEAR(glm::length(cx->point(i)), 1.0, 1e-14);
}

TEST(NurbsPrimitives, UnusableAttributesAreReportedNotBuilt) {
    std::string err;
    NurbsSphereParams s;
    s.radius = 0;
    EXPECT_FALSE(makeNurbSphere(s, &err));
    EXPECT_NE(err.find("radius"), std::string::npos);
    s = {};
    s.radius = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(makeNurbSphere(s, &err));
    s = {};
    s.degree = 4;
    EXPECT_FALSE(makeNurbSphere(s, &err));
    EXPECT_NE(err.find("degree 4"), std::string::npos);
    s = {};
    s.sections = 2;
    EXPECT_FALSE(makeNurbSphere(s, &err));
    EXPECT_NE(err.find("sections"), std::string::npos);
    s = {};
    s.axis = glm::dvec3(0.0);
    EXPECT_FALSE(makeNurbSphere(s, &err));
    EXPECT_NE(err.find("axis"), std::string::npos);
    s = {};
    s.endSweep = s.startSweep;
    EXPECT_FALSE(makeRationalSphere(s, &err));
    NurbsPlaneParams pl;
    pl.patchesU = 0;
    EXPECT_FALSE(makeNurbPlane(pl, &err));
    NurbsTorusParams t;
    t.minorSweep = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(makeNurbTorus(t, &err));
    NurbsCubeParams cu;
    cu.heightRatio = -1;
    EXPECT_FALSE(makeNurbCube(cu, &err));
    NurbsCircleParams ci;
    ci.normal = glm::dvec3(0.0);
    EXPECT_FALSE(makeNurbCircle(ci, &err));
}

}  // namespace
}  // namespace pushpin::geom
