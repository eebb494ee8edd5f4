// Tests for core/geom/triangulate.h: ear clipping of polygons with holes.
#include "core/geom/triangulate.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace pushpin::geom {
namespace {

struct Polygon {
    std::vector<glm::dvec3> points;
    std::vector<uint32_t> loopStarts{0};
    void addLoop(std::initializer_list<glm::dvec2> loop) {
        for (const glm::dvec2& p : loop) points.push_back(glm::dvec3(p, 0.0));
        loopStarts.push_back(uint32_t(points.size()));
    }
};

// Signed area of triangle t seen along `normal`.
double signedArea(const Polygon& poly, const std::vector<uint32_t>& tris, size_t t, const glm::dvec3& normal) {
    const glm::dvec3& a = poly.points[tris[3 * t]];
    const glm::dvec3& b = poly.points[tris[3 * t + 1]];
    const glm::dvec3& c = poly.points[tris[3 * t + 2]];
    return 0.5 * glm::dot(glm::cross(b - a, c - a), glm::normalize(normal));
}

double totalArea(const Polygon& poly, const std::vector<uint32_t>& tris, const glm::dvec3& normal) {
    double sum = 0.0;
    for (size_t t = 0; t < tris.size() / 3; ++t) sum += signedArea(poly, tris, t, normal);
    return sum;
}

// Shoelace area of every loop, holes counted negative whatever their winding.
double polygonArea(const Polygon& poly) {
    double area = 0.0;
    for (size_t l = 0; l + 1 < poly.loopStarts.size(); ++l) {
        double a = 0.0;
        for (uint32_t i = poly.loopStarts[l]; i < poly.loopStarts[l + 1]; ++i) {
            const uint32_t j = i + 1 < poly.loopStarts[l + 1] ? i + 1 : poly.loopStarts[l];
            a += poly.points[i].x * poly.points[j].y - poly.points[j].x * poly.points[i].y;
        }
        area += l == 0 ? std::abs(a) / 2 : -std::abs(a) / 2;
    }
    return area;
}

void expectAllCounterClockwise(const Polygon& poly, const std::vector<uint32_t>& tris, const glm::dvec3& normal) {
    for (size_t t = 0; t < tris.size() / 3; ++t) EXPECT_GT(signedArea(poly, tris, t, normal), 0.0) << "triangle " << t;
}

const glm::dvec3 kUp(0, 0, 1);

TEST(PolygonTriangulator, SquareGivesTwoCounterClockwiseTriangles) {
    Polygon p;
    p.addLoop({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    EXPECT_EQ(tri.triangulate(p.points, p.loopStarts, kUp, out), 2u);
    ASSERT_EQ(out.size(), 6u);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), 1.0, 1e-12);
}

TEST(PolygonTriangulator, ConcaveLShapeKeepsItsArea) {
    Polygon p;
    p.addLoop({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    EXPECT_EQ(tri.triangulate(p.points, p.loopStarts, kUp, out), 4u);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), 3.0, 1e-12);
    // No triangle covers the notch (1..2, 1..2).
    for (size_t t = 0; t < out.size() / 3; ++t) {
        const glm::dvec3 c = (p.points[out[3 * t]] + p.points[out[3 * t + 1]] + p.points[out[3 * t + 2]]) / 3.0;
        EXPECT_FALSE(c.x > 1.0 && c.y > 1.0) << "triangle " << t;
    }
}

TEST(PolygonTriangulator, SquareWithHoleBridgesTheHole) {
    Polygon p;
    p.addLoop({{0, 0}, {4, 0}, {4, 4}, {0, 4}});
    p.addLoop({{1, 1}, {1, 3}, {3, 3}, {3, 1}});  // clockwise, as Maya writes holes
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    EXPECT_EQ(tri.triangulate(p.points, p.loopStarts, kUp, out), 8u);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), 12.0, 1e-12);
    for (size_t t = 0; t < out.size() / 3; ++t) {
        const glm::dvec3 c = (p.points[out[3 * t]] + p.points[out[3 * t + 1]] + p.points[out[3 * t + 2]]) / 3.0;
        EXPECT_FALSE(c.x > 1.0 && c.x < 3.0 && c.y > 1.0 && c.y < 3.0) << "triangle " << t << " covers the hole";
    }
}

TEST(PolygonTriangulator, HoleWindingDoesNotMatter) {
    Polygon p;
    p.addLoop({{0, 0}, {4, 0}, {4, 4}, {0, 4}});
    p.addLoop({{1, 1}, {3, 1}, {3, 3}, {1, 3}});  // counter-clockwise hole
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, kUp, out);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), 12.0, 1e-12);
}

TEST(PolygonTriangulator, SeveralHolesInAConcaveFace) {
    Polygon p;
    p.addLoop({{0, 0}, {10, 0}, {10, 10}, {6, 10}, {6, 4}, {4, 4}, {4, 10}, {0, 10}});
    p.addLoop({{1, 1}, {1, 2}, {2, 2}, {2, 1}});
    p.addLoop({{7, 1}, {7, 2}, {9, 2}, {9, 1}});
    p.addLoop({{1, 5}, {1, 8}, {3, 8}, {3, 5}});
    p.addLoop({{7, 5}, {7, 9}, {8, 9}, {8, 5}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, kUp, out);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), polygonArea(p), 1e-9);
    EXPECT_EQ(out.size() / 3, 8u + 4u * 4u + 2u * 4u - 2u);  // n + 2·holes − 2
}

TEST(PolygonTriangulator, HolesSharingTheRayRow) {
    // Two holes whose rightmost vertices lie on the same horizontal line: the second bridge
    // meets the first bridge's duplicated vertices.
    Polygon p;
    p.addLoop({{0, 0}, {10, 0}, {10, 4}, {0, 4}});
    p.addLoop({{1, 1}, {1, 3}, {3, 2}});
    p.addLoop({{5, 1}, {5, 3}, {7, 2}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, kUp, out);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), polygonArea(p), 1e-9);
}

TEST(PolygonTriangulator, KeepsTheWindingOfAClockwiseLoop) {
    Polygon p;
    p.addLoop({{0, 0}, {0, 1}, {1, 1}, {1, 0}});  // clockwise about +z
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    EXPECT_EQ(tri.triangulate(p.points, p.loopStarts, kUp, out), 2u);
    for (size_t t = 0; t < 2; ++t) EXPECT_LT(signedArea(p, out, t, kUp), 0.0);
    EXPECT_NEAR(totalArea(p, out, kUp), -1.0, 1e-12);
}

TEST(PolygonTriangulator, WorksInAnyPlane) {
    // An L-shape on a tilted plane: the projection follows the normal.
    const glm::dvec3 u = glm::normalize(glm::dvec3(1, 1, 0)), v = glm::normalize(glm::dvec3(-1, 1, 2));
    const glm::dvec3 n = glm::cross(u, v);
    Polygon p;
    for (glm::dvec2 q : {glm::dvec2{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}})
        p.points.push_back(glm::dvec3(5, -3, 2) + q.x * u + q.y * v);
    p.loopStarts.push_back(6);
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, n, out);
    expectAllCounterClockwise(p, out, n);
    EXPECT_NEAR(totalArea(p, out, n), 3.0, 1e-9);
    // A zero normal falls back to the loop's Newell normal.
    std::vector<uint32_t> again;
    tri.triangulate(p.points, p.loopStarts, glm::dvec3(0.0), again);
    EXPECT_EQ(again, out);
}

TEST(PolygonTriangulator, CollinearAndRepeatedPointsKeepTheArea) {
    Polygon p;
    p.addLoop({{0, 0}, {1, 0}, {2, 0}, {2, 0}, {2, 1}, {2, 2}, {0, 2}, {0, 1}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, kUp, out);
    expectAllCounterClockwise(p, out, kUp);
    EXPECT_NEAR(totalArea(p, out, kUp), 4.0, 1e-12);
}

TEST(PolygonTriangulator, DegenerateInputGivesNoTriangles) {
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    Polygon line;
    line.addLoop({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
    EXPECT_EQ(tri.triangulate(line.points, line.loopStarts, kUp, out), 0u);
    Polygon point;
    point.addLoop({{1, 1}, {1, 1}, {1, 1}});
    EXPECT_EQ(tri.triangulate(point.points, point.loopStarts, kUp, out), 0u);
    Polygon two;
    two.addLoop({{0, 0}, {1, 0}});
    EXPECT_EQ(tri.triangulate(two.points, two.loopStarts, kUp, out), 0u);
    Polygon nan;
    nan.addLoop({{0, 0}, {1, 0}, {std::numeric_limits<double>::quiet_NaN(), 1}});
    EXPECT_EQ(tri.triangulate(nan.points, nan.loopStarts, kUp, out), 0u);
    Polygon inf;
    inf.addLoop({{0, 0}, {std::numeric_limits<double>::infinity(), 0}, {0, 1}});
    EXPECT_EQ(tri.triangulate(inf.points, inf.loopStarts, kUp, out), 0u);
    const std::vector<uint32_t> badStarts{0, 5};  // past the points
    EXPECT_EQ(tri.triangulate(line.points, badStarts, kUp, out), 0u);
    EXPECT_EQ(tri.triangulate(line.points, std::vector<uint32_t>{0}, kUp, out), 0u);
    EXPECT_TRUE(out.empty());
}

TEST(PolygonTriangulator, HoleOutsideTheOuterLoopIsIgnored) {
    Polygon p;
    p.addLoop({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    p.addLoop({{5, 5}, {5, 6}, {6, 6}, {6, 5}});
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    EXPECT_EQ(tri.triangulate(p.points, p.loopStarts, kUp, out), 2u);
    EXPECT_NEAR(totalArea(p, out, kUp), 1.0, 1e-12);
}

TEST(PolygonTriangulator, SelfIntersectingLoopTerminates) {
    Polygon p;
    p.addLoop({{0, 0}, {2, 2}, {2, 0}, {0, 2}});  // a bow tie
    PolygonTriangulator tri;
    std::vector<uint32_t> out;
    tri.triangulate(p.points, p.loopStarts, kUp, out);
    EXPECT_LE(out.size() / 3, 2u);
    for (uint32_t i : out) EXPECT_LT(i, 4u);
}

TEST(PolygonTriangulator, RandomStarPolygonsKeepTheirArea) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> radius(0.2, 1.0);
    PolygonTriangulator tri;
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 3 + trial % 40;
        Polygon p;
        for (int i = 0; i < n; ++i) {
            const double a = 2.0 * std::numbers::pi * i / n;
            const double r = radius(rng);
            p.points.push_back(glm::dvec3(r * std::cos(a), r * std::sin(a), 0.0));
        }
        p.loopStarts.push_back(uint32_t(n));
        // A small hole near the centre (inside every star with radius >= 0.2).
        if (trial % 2) {
            for (int i = 0; i < 5; ++i) {
                const double a = -2.0 * std::numbers::pi * i / 5;
                p.points.push_back(glm::dvec3(0.05 * std::cos(a), 0.05 * std::sin(a), 0.0));
            }
            p.loopStarts.push_back(uint32_t(p.points.size()));
        }
        std::vector<uint32_t> out;
        tri.triangulate(p.points, p.loopStarts, kUp, out);
        EXPECT_NEAR(totalArea(p, out, kUp), polygonArea(p), 1e-9) << "trial " << trial;
        expectAllCounterClockwise(p, out, kUp);
        EXPECT_EQ(out.size() / 3, size_t(n) - 2 + (trial % 2 ? 7u : 0u)) << "trial " << trial;
    }
}

}  // namespace
}  // namespace pushpin::geom
