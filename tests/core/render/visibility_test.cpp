// Tests for core/render/visibility.h: exact-area rasterization, per-pixel resolution of hidden
// surfaces, surface merging and compositing. The coverage oracles are computed independently here
// (convex polygon clipped against the pixel, shoelace area).
#include "core/render/visibility.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

namespace pushpin::render {
namespace {

constexpr double kPi = std::numbers::pi;

struct Pt {
    double x, y;
};

// Area of a convex polygon (either winding) intersected with pixel (px, py): the polygon is
// clipped by the four sides of the pixel square, then measured with the shoelace formula.
double exactArea(const std::vector<Pt>& polygon, int px, int py) {
    std::vector<Pt> poly = polygon, next;
    auto clip = [&](auto inside, auto cross) {
        next.clear();
        for (size_t i = 0; i < poly.size(); ++i) {
            const Pt a = poly[i], b = poly[(i + 1) % poly.size()];
            if (inside(a)) next.push_back(a);
            if (inside(a) != inside(b)) next.push_back(cross(a, b));
        }
        poly.swap(next);
    };
    const double x0 = px, x1 = px + 1, y0 = py, y1 = py + 1;
    auto atX = [](double x) {
        return [x](Pt a, Pt b) { return Pt{x, a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)}; };
    };
    auto atY = [](double y) {
        return [y](Pt a, Pt b) { return Pt{a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y), y}; };
    };
    clip([&](Pt p) { return p.x >= x0; }, atX(x0));
    clip([&](Pt p) { return p.x <= x1; }, atX(x1));
    clip([&](Pt p) { return p.y >= y0; }, atY(y0));
    clip([&](Pt p) { return p.y <= y1; }, atY(y1));
    double a2 = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Pt a = poly[i], b = poly[(i + 1) % poly.size()];
        a2 += a.x * b.y - b.x * a.y;
    }
    return std::fabs(0.5 * a2);
}

// A pixel's fragments in (object, triangle) order: the rasterizer files them by pixel without
// keeping their order.
std::vector<Fragment> byObjectAndTriangle(std::span<const Fragment> fragments) {
    std::vector<Fragment> v(fragments.begin(), fragments.end());
    std::sort(v.begin(), v.end(), [](const Fragment& a, const Fragment& b) {
        return a.object != b.object ? a.object < b.object : a.triangle < b.triangle;
    });
    return v;
}

ScreenTriangle makeTriangle(Pt a, Pt b, Pt c, uint32_t object, uint32_t triangle, double z = 1.0) {
    ScreenTriangle t;
    t.x[0] = a.x; t.y[0] = a.y;
    t.x[1] = b.x; t.y[1] = b.y;
    t.x[2] = c.x; t.y[2] = c.y;
    t.z[0] = t.z[1] = t.z[2] = z;
    t.object = object;
    t.triangle = triangle;
    return t;
}

void setPlaneDepth(ScreenTriangle& t, double z0, double dzdx, double dzdy) {
    for (int i = 0; i < 3; ++i) t.z[i] = z0 + dzdx * t.x[i] + dzdy * t.y[i];
}

// Fan triangulation of a convex polygon with soft neighbours (fan triangle t = (p0, p[t+1],
// p[t+2]); its edge 0 meets triangle t−1, its edge 2 meets triangle t+1).
struct Fan {
    std::vector<ScreenTriangle> triangles;
    std::vector<uint32_t> neighbors;
};

Fan makeFan(const std::vector<Pt>& poly, uint32_t object, double z0, double dzdx, double dzdy) {
    Fan fan;
    const uint32_t n = uint32_t(poly.size()) - 2;
    for (uint32_t t = 0; t < n; ++t) {
        ScreenTriangle tri = makeTriangle(poly[0], poly[t + 1], poly[t + 2], object, t);
        setPlaneDepth(tri, z0, dzdx, dzdy);
        fan.triangles.push_back(tri);
        fan.neighbors.push_back(t > 0 ? t - 1 : kNoTriangle);
        fan.neighbors.push_back(kNoTriangle);
        fan.neighbors.push_back(t + 1 < n ? t + 1 : kNoTriangle);
    }
    return fan;
}

// A grid of `cells` × `cells` square cells `cellSize` pixels wide, turned by `angle` about
// `origin`, two triangles per cell, every edge soft (neighbours named on both sides, kNoTriangle
// on the border), on the depth plane z0 + 0.01·x + 0.02·y.
Fan softGrid(int cells, double cellSize, double angle, Pt origin, uint32_t object, double z0) {
    auto vertex = [&](int i, int j) {
        const double u = i * cellSize, v = j * cellSize;
        return Pt{origin.x + std::cos(angle) * u - std::sin(angle) * v,
                  origin.y + std::sin(angle) * u + std::cos(angle) * v};
    };
    auto cellTri = [&](int i, int j, int k) {
        return (i < 0 || j < 0 || i >= cells || j >= cells) ? kNoTriangle : uint32_t(2 * (j * cells + i) + k);
    };
    Fan grid;
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const Pt v00 = vertex(i, j), v10 = vertex(i + 1, j), v11 = vertex(i + 1, j + 1), v01 = vertex(i, j + 1);
            ScreenTriangle t0 = makeTriangle(v00, v10, v11, object, cellTri(i, j, 0));
            ScreenTriangle t1 = makeTriangle(v00, v11, v01, object, cellTri(i, j, 1));
            setPlaneDepth(t0, z0, 0.01, 0.02);
            setPlaneDepth(t1, z0, 0.01, 0.02);
            grid.triangles.push_back(t0);
            grid.triangles.push_back(t1);
            grid.neighbors.insert(grid.neighbors.end(), {cellTri(i, j - 1, 1), cellTri(i + 1, j, 1), cellTri(i, j, 1)});
            grid.neighbors.insert(grid.neighbors.end(), {cellTri(i, j, 0), cellTri(i, j + 1, 0), cellTri(i - 1, j, 0)});
        }
    }
    return grid;
}

// A random convex polygon: a rotated ellipse sampled at sorted random angles, or a thin sliver.
std::vector<Pt> randomPolygon(std::mt19937& rng, Pt centre, int kind) {
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double rot = uni(rng) * 2 * kPi;
    const double c = std::cos(rot), s = std::sin(rot);
    std::vector<Pt> local;
    if (kind == 0) {  // sliver 0.01 px wide
        const double len = 0.3 + uni(rng) * 6.0, w = 0.01;
        local = {{-len / 2, -w / 2}, {len / 2, -w / 2}, {len / 2, w / 2}, {-len / 2, w / 2}};
    } else {
        const double rx = kind == 1 ? 0.03 + 0.4 * uni(rng) : 0.2 + 5.0 * uni(rng);
        const double ry = rx * (0.2 + 0.8 * uni(rng));
        const int n = 3 + int(uni(rng) * 6);
        std::vector<double> angles(static_cast<size_t>(n));
        for (double& a : angles) a = uni(rng) * 2 * kPi;
        std::sort(angles.begin(), angles.end());
        for (double a : angles) local.push_back({rx * std::cos(a), ry * std::sin(a)});
    }
    std::vector<Pt> poly;
    for (const Pt& p : local) poly.push_back({centre.x + c * p.x - s * p.y, centre.y + s * p.x + c * p.y});
    if (uni(rng) < 0.5) std::reverse(poly.begin(), poly.end());
    return poly;
}

double polygonArea(const std::vector<Pt>& poly) {
    double a2 = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Pt a = poly[i], b = poly[(i + 1) % poly.size()];
        a2 += a.x * b.y - b.x * a.y;
    }
    return std::fabs(0.5 * a2);
}

// Sum of the composite alphas of one pixel with opaque white shades.
float resolvedAlpha(PixelResolver& resolver, std::span<const Fragment> fragments) {
    resolver.resolve(fragments);
    const size_t n = resolver.groups().size();
    std::vector<SurfaceShade> shades(n);
    for (SurfaceShade& s : shades) s.color[0] = s.color[1] = s.color[2] = 1.0f;
    std::vector<SurfaceContribution> out(n);
    resolver.composite(shades, out);
    float alpha = 0;
    for (const SurfaceContribution& c : out) alpha += c.alpha;
    return alpha;
}

Fragment fullFragment(uint32_t object, uint32_t triangle, float z, const SubsamplePattern& p,
                      uint32_t flags = 0) {
    Fragment f;
    f.object = object;
    f.triangle = triangle;
    f.mask = p.active;
    f.area = 1.0f;
    f.z0 = z;
    f.flags = flags;
    return f;
}

// Active sub-samples in the left half of the pixel (u < 0.5).
uint64_t leftHalf(const SubsamplePattern& p) {
    uint64_t m = 0;
    for (int b = 0; b < kSubsampleCount; ++b) {
        if (b % kSubsampleGrid < kSubsampleGrid / 2) m |= uint64_t(1) << b;
    }
    return m & p.active;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSameGroup(const SurfaceGroup& a, const SurfaceGroup& b) {
    EXPECT_EQ(a.object, b.object);
    EXPECT_EQ(a.memberBegin, b.memberBegin);
    EXPECT_EQ(a.memberCount, b.memberCount);
    EXPECT_EQ(a.mask, b.mask);
    EXPECT_EQ(a.visibleMask, b.visibleMask);
    EXPECT_TRUE(sameBits(a.area, b.area));
    EXPECT_TRUE(sameBits(a.coverage, b.coverage));
    EXPECT_TRUE(sameBits(a.cu, b.cu));
    EXPECT_TRUE(sameBits(a.cv, b.cv));
    EXPECT_TRUE(sameBits(a.depth, b.depth));
    EXPECT_EQ(a.transparent, b.transparent);
}

// ---------------------------------------------------------------------------------------------
// Rasterizer

TEST(TileRasterizer, FullPixelsHaveUnitAreaAndAllActiveBits) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer r(p);
    r.reset({0, 0, 8, 8});
    r.add(makeTriangle({-100, -100}, {100, -100}, {0, 100}, 0, 0));
    r.finish();
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
            const auto f = r.fragments(x, y);
            ASSERT_EQ(f.size(), 1u);
            EXPECT_EQ(f[0].area, 1.0f);
            EXPECT_EQ(f[0].mask, p.active);
            EXPECT_EQ(f[0].cu, 0.5f);
            EXPECT_EQ(f[0].cv, 0.5f);
        }
    }
    EXPECT_EQ(r.stats().fragments, 64u);
    EXPECT_EQ(r.stats().trianglesRasterized, 1u);
}

TEST(TileRasterizer, TellsItsGrowHookBeforeEveryBufferGrows) {
    // 200 layers of full-region triangles over 32 × 32 pixels: 204,800 fragments. Before each
    // growth the hook hears what the new buffers take, so the bytes held never pass what it was
    // told beside what was held before.
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer r(p);
    uint64_t told = 0;
    int calls = 0;
    r.setGrowHook([&](uint64_t more) {
        told += more;
        ++calls;
    });
    r.reset({0, 0, 32, 32});
    for (uint32_t layer = 0; layer < 200; ++layer) {
        const uint64_t before = r.bytes();
        const uint64_t toldBefore = told;
        r.add(makeTriangle({-100, -100}, {100, -100}, {0, 100}, 0, layer, 1.0 + layer));
        EXPECT_LE(r.bytes(), before + (told - toldBefore)) << "layer " << layer;
    }
    const uint64_t before = r.bytes();
    const uint64_t toldBefore = told;
    r.finish();
    EXPECT_LE(r.bytes(), before + (told - toldBefore));
    EXPECT_EQ(r.stats().fragments, 200u * 32u * 32u);
    EXPECT_EQ(r.fragments(5, 7).size(), 200u);
    EXPECT_GT(calls, 2);
    EXPECT_LT(calls, 40) << "buffers grow at least by half";
}

TEST(TileRasterizer, HalfPixelTriangleHasExactAreaCentroidAndMask) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    TileRasterizer r(p);
    r.reset({0, 0, 1, 1});
    // Lower-left half of pixel (0, 0): (0,0), (0,1), (1,1).
    r.add(makeTriangle({0, 0}, {0, 1}, {1, 1}, 0, 0));
    r.finish();
    const auto f = r.fragments(0, 0);
    ASSERT_EQ(f.size(), 1u);
    EXPECT_NEAR(f[0].area, 0.5, 1e-7);
    EXPECT_NEAR(f[0].cu, 1.0 / 3.0, 1e-6);
    EXPECT_NEAR(f[0].cv, 2.0 / 3.0, 1e-6);
    // Centres strictly below the diagonal (v > u) are inside; none lies on it.
    uint64_t expected = 0;
    for (int b = 0; b < kSubsampleCount; ++b) {
        if (b / kSubsampleGrid > b % kSubsampleGrid) expected |= uint64_t(1) << b;
    }
    EXPECT_EQ(f[0].mask, expected);
}

TEST(TileRasterizer, MasksHoldExactlyTheCentresInsideTheTriangle) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(0.0, 6.0);
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer r(p);
        for (int trial = 0; trial < 40; ++trial) {
            r.reset({0, 0, 6, 6});
            const Pt a{uni(rng), uni(rng)}, b{uni(rng), uni(rng)}, c{uni(rng), uni(rng)};
            r.add(makeTriangle(a, b, c, 0, 0));
            r.finish();
            const double s = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
            auto side = [&](Pt p0, Pt p1, double x, double y) {
                return ((p1.x - p0.x) * (y - p0.y) - (p1.y - p0.y) * (x - p0.x)) * (s > 0 ? 1 : -1);
            };
            for (int y = 0; y < 6; ++y) {
                for (int x = 0; x < 6; ++x) {
                    const auto f = r.fragments(x, y);
                    const uint64_t mask = f.empty() ? 0 : f[0].mask;
                    for (int bit = 0; bit < kSubsampleCount; ++bit) {
                        if (!((p.active >> bit) & 1)) continue;
                        const double px = x + (bit % 8 + 0.5) / 8, py = y + (bit / 8 + 0.5) / 8;
                        const double e0 = side(a, b, px, py), e1 = side(b, c, px, py), e2 = side(c, a, px, py);
                        const double m = std::min({e0, e1, e2});
                        if (std::fabs(m) < 1e-9) continue;  // on an edge: the fill rule decides
                        EXPECT_EQ(bool((mask >> bit) & 1), m > 0)
                            << "eaa " << eaa << " trial " << trial << " pixel " << x << "," << y << " bit " << bit;
                    }
                }
            }
        }
    }
}

TEST(TileRasterizer, AreasMatchTheExactClippedArea) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(-1.0, 9.0);
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(2);
    TileRasterizer r(p);
    for (int trial = 0; trial < 50; ++trial) {
        r.reset({0, 0, 8, 8});
        const std::vector<Pt> tri = {{uni(rng), uni(rng)}, {uni(rng), uni(rng)}, {uni(rng), uni(rng)}};
        r.add(makeTriangle(tri[0], tri[1], tri[2], 0, 0));
        r.finish();
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) {
                const double want = exactArea(tri, x, y);
                const auto f = r.fragments(x, y);
                ASSERT_LE(f.size(), 1u);
                const double got = f.empty() ? 0.0 : f[0].area;
                EXPECT_NEAR(got, want, 1e-6) << "trial " << trial << " pixel " << x << "," << y;
                if (!f.empty()) {
                    EXPECT_GT(f[0].area, 0.0f);
                }
            }
        }
    }
}

TEST(TileRasterizer, DepthPlaneReproducesTheTriangleDepth) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    TileRasterizer r(p);
    r.reset({0, 0, 10, 10});
    ScreenTriangle t = makeTriangle({0.3, 0.2}, {9.7, 1.1}, {4.2, 9.9}, 0, 0);
    const double z0 = 3.0, dzdx = 0.125, dzdy = -0.0625;
    setPlaneDepth(t, z0, dzdx, dzdy);
    r.add(t);
    r.finish();
    int checked = 0;
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 10; ++x) {
            for (const Fragment& f : r.fragments(x, y)) {
                EXPECT_FLOAT_EQ(f.dzdu, float(dzdx));
                EXPECT_FLOAT_EQ(f.dzdv, float(dzdy));
                for (float u : {0.0f, 0.5f, 1.0f}) {
                    for (float v : {0.0f, 0.25f, 1.0f}) {
                        EXPECT_NEAR(f.depthAt(u, v), z0 + dzdx * (x + u) + dzdy * (y + v), 1e-5);
                    }
                }
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 30);
}

TEST(TileRasterizer, SkipsDegenerateAndNonFiniteTriangles) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer r(p);
    r.reset({0, 0, 4, 4});
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    r.add(makeTriangle({nan, 0}, {3, 0}, {0, 3}, 0, 0));
    r.add(makeTriangle({0, 0}, {3, inf}, {0, 3}, 0, 1));
    ScreenTriangle badZ = makeTriangle({0, 0}, {3, 0}, {0, 3}, 0, 2);
    badZ.z[1] = nan;
    r.add(badZ);
    r.add(makeTriangle({0, 0}, {1, 1}, {3, 3}, 0, 3));      // collinear
    r.add(makeTriangle({1, 1}, {1, 1}, {2, 3}, 0, 4));      // repeated vertex
    r.add(makeTriangle({-inf, 0}, {inf, 0}, {0, 3}, 0, 5)); // infinite
    r.finish();
    EXPECT_EQ(r.stats().trianglesDegenerate, 6u);
    EXPECT_EQ(r.stats().trianglesRasterized, 0u);
    EXPECT_EQ(r.stats().fragments, 0u);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) EXPECT_TRUE(r.fragments(x, y).empty());
    }
}

TEST(TileRasterizer, HugeCoordinatesAreClampedToTheRegion) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    TileRasterizer r(p);
    r.reset({-4, -4, 4, 4});
    // Covers everything.
    r.add(makeTriangle({-1e30, -1e30}, {1e30, -1e30}, {0, 1e30}, 0, 0));
    // A nearly vertical edge through x ≈ 0.5 with far-away vertices: the half x < 0.5 is inside.
    r.add(makeTriangle({0.5, -1e30}, {0.5, 1e30}, {-1e30, 0}, 1, 0));
    r.finish();
    EXPECT_EQ(r.stats().trianglesRasterized, 2u);
    for (int y = -4; y < 4; ++y) {
        for (int x = -4; x < 4; ++x) {
            const std::vector<Fragment> f = byObjectAndTriangle(r.fragments(x, y));
            ASSERT_GE(f.size(), 1u);
            EXPECT_EQ(f[0].object, 0u);
            EXPECT_EQ(f[0].area, 1.0f);
            const double want = x < 0 ? 1.0 : (x == 0 ? 0.5 : 0.0);
            const double got = f.size() > 1 ? f[1].area : 0.0;
            EXPECT_NEAR(got, want, 1e-6) << x << "," << y;
            for (const Fragment& fr : f) EXPECT_TRUE(std::isfinite(fr.z0));
        }
    }
}

TEST(TileRasterizer, FragmentsDoNotDependOnTheRegionThatRendersThem) {
    // The same triangles rasterized once over the whole area and once tile by tile (odd tile
    // sizes, offsets that cut triangles anywhere) give bit-identical fragments in every pixel
    // (but for the region pixel each is filed under, and their order).
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> pos(-3.0, 53.0), size(0.05, 20.0), depth(-1.0, -0.01);
    std::vector<ScreenTriangle> tris;
    for (uint32_t t = 0; t < 300; ++t) {
        ScreenTriangle s;
        double cx = pos(rng), cy = pos(rng), r = size(rng);
        for (int k = 0; k < 3; ++k) {
            s.x[k] = cx + r * std::cos(1.7 * k + t), s.y[k] = cy + r * std::sin(2.3 * k + 0.5 * t);
            s.z[k] = depth(rng);
        }
        s.object = t % 7;
        s.triangle = t;
        tris.push_back(s);
    }
    for (int eaa : {0, 3}) {
        const SubsamplePattern pattern = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer whole(pattern), tile(pattern);
        const PixelRect all{0, 0, 50, 50};
        whole.reset(all);
        for (const ScreenTriangle& t : tris) whole.add(t);
        whole.finish();
        for (int ty = 0; ty < 50; ty += 13)
            for (int tx = 0; tx < 50; tx += 17) {
                tile.reset({tx, ty, std::min(tx + 17, 50), std::min(ty + 13, 50)});
                for (const ScreenTriangle& t : tris) tile.add(t);
                tile.finish();
                for (int y = ty; y < std::min(ty + 13, 50); ++y)
                    for (int x = tx; x < std::min(tx + 17, 50); ++x) {
                        std::vector<Fragment> a = byObjectAndTriangle(whole.fragments(x, y)),
                                              b = byObjectAndTriangle(tile.fragments(x, y));
                        ASSERT_EQ(a.size(), b.size()) << x << "," << y;
                        for (Fragment& f : a) f.pixel = 0;
                        for (Fragment& f : b) f.pixel = 0;
                        EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(Fragment))) << x << "," << y;
                    }
            }
    }
}

TEST(TileRasterizer, RegionOffsetFromTheOrigin) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(2);
    TileRasterizer r(p);
    const PixelRect region{1000, -50, 1008, -44};
    r.reset(region);
    EXPECT_EQ(r.region(), region);
    const std::vector<Pt> tri = {{998.3, -52.0}, {1007.2, -47.7}, {1001.1, -40.5}};
    r.add(makeTriangle(tri[0], tri[1], tri[2], 2, 9));
    r.finish();
    double total = 0;
    for (int y = region.y0; y < region.y1; ++y) {
        for (int x = region.x0; x < region.x1; ++x) {
            const auto f = r.fragments(x, y);
            const double want = exactArea(tri, x, y);
            EXPECT_NEAR(f.empty() ? 0.0 : f[0].area, want, 1e-6) << x << "," << y;
            for (const Fragment& fr : f) {
                EXPECT_EQ(fr.object, 2u);
                EXPECT_EQ(fr.triangle, 9u);
                total += fr.area;
            }
        }
    }
    EXPECT_GT(total, 10.0);
    EXPECT_TRUE(r.fragments(999, -50).empty());
    EXPECT_TRUE(r.fragments(1008, -45).empty());
    EXPECT_TRUE(r.fragments(1003, -44).empty());
    EXPECT_TRUE(r.fragments(0, 0).empty());
}

TEST(TileRasterizer, GroupsFragmentsPerPixel) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer r(p);
    auto addAll = [&] {
        r.reset({0, 0, 4, 4});
        r.add(makeTriangle({-1, -1}, {5, -1}, {-1, 5}, 5, 0));   // upper-left
        r.add(makeTriangle({5, 5}, {-1, 5}, {5, -1}, 2, 0));     // lower-right, across the same edge
        r.add(makeTriangle({-10, -10}, {10, -10}, {0, 10}, 7, 3));
        r.finish();
    };
    addAll();
    std::vector<Fragment> first(r.sortedFragments().begin(), r.sortedFragments().end());
    size_t seen = 0;
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            const std::span<const Fragment> at = r.fragments(x, y);
            EXPECT_EQ(size_t(at.data() - r.sortedFragments().data()), seen) << "pixels follow one another";
            seen += at.size();
            for (const Fragment& f : at) EXPECT_EQ(f.pixel, uint32_t(4 * y + x));
            const std::vector<Fragment> f = byObjectAndTriangle(at);
            ASSERT_GE(f.size(), 2u);
            EXPECT_EQ(f.back().object, 7u);
            if (f.size() == 3) {
                EXPECT_EQ(f[0].object, 2u);
                EXPECT_EQ(f[1].object, 5u);
            }
        }
    }
    EXPECT_EQ(seen, r.sortedFragments().size());
    // Pixels on the diagonal x + y = 3 hold both halves.
    EXPECT_EQ(r.fragments(1, 2).size(), 3u);
    EXPECT_EQ(r.fragments(0, 0).size(), 2u);
    EXPECT_EQ(byObjectAndTriangle(r.fragments(0, 0))[0].object, 5u);
    EXPECT_EQ(byObjectAndTriangle(r.fragments(3, 3))[0].object, 2u);
    // The order within a pixel depends on the adds only.
    addAll();
    ASSERT_EQ(r.sortedFragments().size(), first.size());
    EXPECT_EQ(0, std::memcmp(first.data(), r.sortedFragments().data(), first.size() * sizeof(Fragment)));

    // A pixel's fragments can be put in another order; not in another number.
    std::vector<Fragment> reversed(r.fragments(1, 2).rbegin(), r.fragments(1, 2).rend());
    r.reorderPixel(1, 2, reversed);
    EXPECT_EQ(r.fragments(1, 2)[0].object, reversed[0].object);
    EXPECT_EQ(r.fragments(1, 2)[2].object, reversed[2].object);
    reversed.pop_back();
    EXPECT_THROW(r.reorderPixel(1, 2, reversed), std::invalid_argument);

    // reset clears the fragments; fragments() is empty before finish().
    r.reset({0, 0, 4, 4});
    EXPECT_TRUE(r.fragments(1, 1).empty());
    r.add(makeTriangle({-10, -10}, {10, -10}, {0, 10}, 7, 3));
    EXPECT_TRUE(r.fragments(1, 1).empty());
    r.finish();
    EXPECT_EQ(r.fragments(1, 1).size(), 1u);
}

TEST(TileRasterizer, EmptyRegionAndTrianglesOutsideAddNothing) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer r(p);
    r.reset({3, 3, 3, 8});
    r.add(makeTriangle({0, 0}, {10, 0}, {0, 10}, 0, 0));
    r.finish();
    EXPECT_EQ(r.stats().fragments, 0u);
    EXPECT_TRUE(r.fragments(3, 4).empty());
    r.reset({0, 0, 4, 4});
    r.add(makeTriangle({10, 10}, {12, 10}, {10, 12}, 0, 0));
    r.add(makeTriangle({0, 4}, {4, 4}, {0, 8}, 0, 1));  // touches the region's bottom edge only
    r.finish();
    EXPECT_EQ(r.stats().fragments, 0u);
    EXPECT_EQ(r.stats().trianglesRasterized, 0u);
    EXPECT_EQ(r.stats().trianglesDegenerate, 0u);
}

TEST(RasterStats, MergeAddsEveryCounter) {
    RasterStats a{1, 2, 3}, b{10, 20, 30};
    a.merge(b);
    EXPECT_EQ(a.trianglesRasterized, 11u);
    EXPECT_EQ(a.trianglesDegenerate, 22u);
    EXPECT_EQ(a.fragments, 33u);
}

// ---------------------------------------------------------------------------------------------
// Acceptance: exact coverage

TEST(PixelResolver, PolygonCoverageIsExactAtEveryLevel) {
    constexpr int kSize = 12;
    const PixelRect region{-3, 5, -3 + kSize, 5 + kSize};
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer rasterizer(p);
        std::mt19937 rng(1234 + eaa);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        int pixelsChecked = 0;
        for (int polygon = 0; polygon < 240; ++polygon) {
            const Pt centre{region.x0 + 2 + uni(rng) * (kSize - 4), region.y0 + 2 + uni(rng) * (kSize - 4)};
            const std::vector<Pt> poly = randomPolygon(rng, centre, polygon % 3);
            const Fan fan = makeFan(poly, 0, 5.0 + uni(rng), 0.05 * (uni(rng) - 0.5), 0.05 * (uni(rng) - 0.5));
            const ObjectTopology topo{fan.neighbors.data(), uint32_t(fan.triangles.size())};
            PixelResolver resolver(p, std::span<const ObjectTopology>(&topo, 1));
            rasterizer.reset(region);
            for (const ScreenTriangle& t : fan.triangles) rasterizer.add(t);
            rasterizer.finish();
            double total = 0, exactTotal = 0;
            for (int y = region.y0; y < region.y1; ++y) {
                for (int x = region.x0; x < region.x1; ++x) {
                    const double want = exactArea(poly, x, y);
                    exactTotal += want;
                    const float got = resolvedAlpha(resolver, rasterizer.fragments(x, y));
                    ASSERT_NEAR(got, want, 1e-4) << "eaa " << eaa << " polygon " << polygon << " pixel " << x << "," << y;
                    EXPECT_LE(resolver.opaqueCoverage(), 1.0f);
                    total += got;
                    if (want > 0) ++pixelsChecked;
                }
            }
            EXPECT_NEAR(total, exactTotal, 1e-3) << "eaa " << eaa << " polygon " << polygon;
            EXPECT_LE(exactTotal, polygonArea(poly) + 1e-9);
        }
        EXPECT_GT(pixelsChecked, 1500);
    }
}

TEST(PixelResolver, SharedEdgeOfTwoObjectsHasNoCrackAndNoOverlap) {
    constexpr int kSize = 10;
    const PixelRect region{0, 0, kSize, kSize};
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer rasterizer(p);
        PixelResolver resolver(p, {});
        std::mt19937 rng(99 + eaa);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        for (int trial = 0; trial < 150; ++trial) {
            // Shared edge P–Q at a random angle; the outer vertices on either side.
            const Pt P{1 + uni(rng) * 8, 1 + uni(rng) * 8}, Q{1 + uni(rng) * 8, 1 + uni(rng) * 8};
            const double dx = Q.x - P.x, dy = Q.y - P.y, len = std::hypot(dx, dy);
            if (len < 0.5) continue;
            const double along = uni(rng) - 0.5;
            const Pt mid{(P.x + Q.x) / 2 + along * dx, (P.y + Q.y) / 2 + along * dy};
            const double h1 = 0.05 + uni(rng) * 4, h2 = 0.05 + uni(rng) * 4;
            const Pt R1{mid.x - dy / len * h1, mid.y + dx / len * h1};
            const Pt R2{mid.x + dy / len * h2, mid.y - dx / len * h2};
            ScreenTriangle a = makeTriangle(P, Q, R1, 0, 0);
            ScreenTriangle b = trial % 2 ? makeTriangle(Q, P, R2, 1, 0) : makeTriangle(R2, P, Q, 1, 0);
            setPlaneDepth(a, 4.0, 0.01, -0.02);
            setPlaneDepth(b, 4.0, 0.01, -0.02);
            rasterizer.reset(region);
            rasterizer.add(a);
            rasterizer.add(b);
            rasterizer.finish();
            const std::vector<Pt> triA = {P, Q, R1}, triB = {P, Q, R2};
            for (int y = 0; y < kSize; ++y) {
                for (int x = 0; x < kSize; ++x) {
                    const auto frags = rasterizer.fragments(x, y);
                    uint64_t owned = 0;
                    for (const Fragment& f : frags) {
                        EXPECT_EQ(owned & f.mask, 0u) << "double coverage, eaa " << eaa << " trial " << trial;
                        owned |= f.mask;
                    }
                    const double want = exactArea(triA, x, y) + exactArea(triB, x, y);
                    ASSERT_NEAR(resolvedAlpha(resolver, frags), want, 1e-4)
                        << "eaa " << eaa << " trial " << trial << " pixel " << x << "," << y;
                }
            }
        }
    }
}

TEST(PixelResolver, SubsamplesOnASharedEdgeHaveExactlyOneOwner) {
    constexpr int kSize = 8;
    const PixelRect region{0, 0, kSize, kSize};
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> cell(8, 56), dir(-9, 9);
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer rasterizer(p);
        PixelResolver resolver(p, {});
        int onEdge = 0;
        for (int trial = 0; trial < 40; ++trial) {
            // The edge passes through sub-sample centres (odd multiples of 1/16) with a lattice
            // direction, so many centres lie exactly on it; the far vertices put the whole region
            // inside the union of the two triangles.
            const int ix = cell(rng), iy = cell(rng);
            int ddx = dir(rng), ddy = dir(rng);
            if (ddx == 0 && ddy == 0) ddx = 1;
            const Pt P{(ix + 0.5) / 8, (iy + 0.5) / 8};
            const double far = 4096;
            const Pt dirv{double(ddx), double(ddy)};
            const Pt R1{P.x - dirv.y * far, P.y + dirv.x * far}, R2{P.x + dirv.y * far, P.y - dirv.x * far};
            const Pt P2{P.x - dirv.x * far, P.y - dirv.y * far}, Q2{P.x + dirv.x * far, P.y + dirv.y * far};
            ScreenTriangle a = makeTriangle(P2, Q2, R1, 0, 0, 3.0);
            ScreenTriangle b = trial % 2 ? makeTriangle(Q2, P2, R2, 1, 0, 3.0) : makeTriangle(R2, P2, Q2, 1, 0, 3.0);
            rasterizer.reset(region);
            rasterizer.add(a);
            rasterizer.add(b);
            rasterizer.finish();
            for (int y = 0; y < kSize; ++y) {
                for (int x = 0; x < kSize; ++x) {
                    const auto frags = rasterizer.fragments(x, y);
                    uint64_t owned = 0;
                    for (const Fragment& f : frags) {
                        EXPECT_EQ(owned & f.mask, 0u) << "eaa " << eaa << " trial " << trial;
                        owned |= f.mask;
                    }
                    EXPECT_EQ(owned, p.active) << "eaa " << eaa << " trial " << trial << " pixel " << x << "," << y;
                    EXPECT_NEAR(resolvedAlpha(resolver, frags), 1.0, 1e-4);
                    // Count centres exactly on the line, in units of 1/16 (exact integers).
                    for (int bit = 0; bit < kSubsampleCount; ++bit) {
                        if (!((p.active >> bit) & 1)) continue;
                        const long sx = 16L * x + 2 * (bit % 8) + 1, sy = 16L * y + 2 * (bit / 8) + 1;
                        const long px16 = 2L * ix + 1, py16 = 2L * iy + 1;
                        if (long(ddx) * (sy - py16) - long(ddy) * (sx - px16) == 0) ++onEdge;
                    }
                }
            }
        }
        EXPECT_GT(onEdge, 20) << "eaa " << eaa;
    }
}

// ---------------------------------------------------------------------------------------------
// Merging

TEST(PixelResolver, SoftEdgeMergesAndHardEdgeSeparates) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer rasterizer(p);
    rasterizer.reset({0, 0, 4, 4});
    // A quad split along its diagonal through pixel (1, 1): triangles 0 and 1 share edge 2 / edge 0.
    const Pt a{-1, -1}, b{5, -1}, c{5, 5}, d{-1, 5};
    rasterizer.add(makeTriangle(a, b, c, 0, 0, 2.0));
    rasterizer.add(makeTriangle(a, c, d, 0, 1, 2.0));
    rasterizer.finish();
    const auto frags = rasterizer.fragments(1, 1);
    ASSERT_EQ(frags.size(), 2u);

    const uint32_t soft[6] = {kNoTriangle, kNoTriangle, 1, 0, kNoTriangle, kNoTriangle};
    const ObjectTopology softTopo{soft, 2};
    PixelResolver merging(p, std::span<const ObjectTopology>(&softTopo, 1));
    merging.resolve(frags);
    ASSERT_EQ(merging.groups().size(), 1u);
    const SurfaceGroup& g = merging.groups()[0];
    EXPECT_EQ(g.memberCount, 2u);
    EXPECT_NEAR(g.area, 1.0, 1e-6);
    EXPECT_EQ(g.mask, p.active);
    EXPECT_EQ(g.visibleMask, p.active);
    EXPECT_NEAR(g.coverage, 1.0, 1e-6);
    EXPECT_EQ(merging.stats().mergedFragments, 1u);
    EXPECT_EQ(merging.stats().surfaces, 1u);
    EXPECT_EQ(merging.members().size(), 2u);

    const uint32_t hard[6] = {kNoTriangle, kNoTriangle, 1 | kHardEdgeBit, 0 | kHardEdgeBit, kNoTriangle, kNoTriangle};
    const ObjectTopology hardTopo{hard, 2};
    PixelResolver separate(p, std::span<const ObjectTopology>(&hardTopo, 1));
    separate.resolve(frags);
    ASSERT_EQ(separate.groups().size(), 2u);
    EXPECT_EQ(separate.stats().mergedFragments, 0u);
    EXPECT_NEAR(separate.groups()[0].coverage + separate.groups()[1].coverage, 1.0, 1e-6);
    EXPECT_NEAR(resolvedAlpha(separate, frags), 1.0, 1e-6);

    // Without topology for the object, nothing merges either.
    PixelResolver none(p, {});
    none.resolve(frags);
    EXPECT_EQ(none.groups().size(), 2u);
}

TEST(PixelResolver, DenseSoftMeshMergesIntoOneSurfacePerPixel) {
    // A rotated grid of 0.37-pixel cells, two triangles per cell, every edge soft; 22 px wide, it
    // covers the whole 8×8 region.
    const Fan grid = softGrid(60, 0.37, 0.3, {-4.0, -8.0}, 0, 2.0);
    const std::vector<ScreenTriangle>& tris = grid.triangles;
    const std::vector<uint32_t>& neighbors = grid.neighbors;
    const ObjectTopology topo{neighbors.data(), uint32_t(tris.size())};
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer rasterizer(p);
        rasterizer.reset({0, 0, 8, 8});
        for (const ScreenTriangle& t : tris) rasterizer.add(t);
        rasterizer.finish();
        PixelResolver resolver(p, std::span<const ObjectTopology>(&topo, 1));
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) {
                const auto frags = rasterizer.fragments(x, y);
                ASSERT_GT(frags.size(), 8u);
                EXPECT_NEAR(resolvedAlpha(resolver, frags), 1.0, 1e-4);
                ASSERT_EQ(resolver.groups().size(), 1u) << "eaa " << eaa << " pixel " << x << "," << y;
                EXPECT_EQ(resolver.groups()[0].memberCount, frags.size());
                EXPECT_EQ(resolver.groups()[0].mask, p.active);
            }
        }
        EXPECT_EQ(resolver.stats().mergedFragments, rasterizer.stats().fragments - 64);
    }
}

TEST(PixelResolver, SurfaceGroupsAreTheSoftNeighbourComponentsOfEachObject) {
    // Two overlapping soft grids of small cells (object 1 under object 0) with random hard edges,
    // and one neighbour named soft on one side only. Every pixel holds many fragments of each
    // object, short runs and long; the groups must be the connected components of "same object
    // and the same triangle or a soft neighbour named by either", found here pair by pair.
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    constexpr int kCells = 40;
    std::vector<std::vector<uint32_t>> neighborStore(2);
    std::vector<ScreenTriangle> tris;
    for (uint32_t object = 0; object < 2; ++object) {
        Fan grid = object == 0 ? softGrid(kCells, 0.29, 0.3, {-3.0, -6.0}, 0, 2.0)
                               : softGrid(kCells, 0.61, -0.7, {-6.0, -9.0}, 1, 3.0);
        tris.insert(tris.end(), grid.triangles.begin(), grid.triangles.end());
        std::vector<uint32_t>& nb = neighborStore[object];
        nb = std::move(grid.neighbors);
        // Hard edges on both sides of about a third of the shared edges.
        for (uint32_t t = 0; t < nb.size() / 3; ++t) {
            for (int k = 0; k < 3; ++k) {
                const uint32_t other = nb[3 * t + k];
                if ((other & kHardEdgeBit) || other < t || uni(rng) > 0.35) continue;  // hard or none
                nb[3 * t + k] |= kHardEdgeBit;
                for (int m = 0; m < 3; ++m)
                    if (nb[3 * other + m] == t) nb[3 * other + m] |= kHardEdgeBit;
            }
        }
    }
    // In the cell of object 0 under pixel (3, 3), the second triangle names the first soft and the
    // first names the second hard; every other edge of the two is hard on both sides.
    {
        const double u = std::cos(0.3) * (3.5 + 3.0) + std::sin(0.3) * (3.5 + 6.0);
        const double v = -std::sin(0.3) * (3.5 + 3.0) + std::cos(0.3) * (3.5 + 6.0);
        const uint32_t first = uint32_t(2 * (int(v / 0.29) * kCells + int(u / 0.29)));
        std::vector<uint32_t>& nb = neighborStore[0];
        for (uint32_t t : {first, first + 1}) {
            for (int k = 0; k < 3; ++k) {
                const uint32_t other = nb[3 * t + k] & ~kHardEdgeBit;
                nb[3 * t + k] |= kHardEdgeBit;
                if (other >= nb.size() / 3) continue;
                for (int m = 0; m < 3; ++m)
                    if ((nb[3 * other + m] & ~kHardEdgeBit) == t) nb[3 * other + m] |= kHardEdgeBit;
            }
        }
        nb[3 * (first + 1) + 0] = first;  // the diagonal, soft on this side only
    }
    const std::vector<ObjectTopology> topo = {{neighborStore[0].data(), uint32_t(neighborStore[0].size() / 3)},
                                              {neighborStore[1].data(), uint32_t(neighborStore[1].size() / 3)}};
    auto softNamed = [&](const Fragment& a, const Fragment& b) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t n = topo[a.object].neighbors[3 * size_t(a.triangle) + k];
            if (!(n & kHardEdgeBit) && n == b.triangle) return true;
        }
        return false;
    };
    auto byBytes = [](const Fragment& a, const Fragment& b) { return std::memcmp(&a, &b, sizeof(Fragment)) < 0; };
    using Partition = std::vector<std::vector<Fragment>>;
    auto canonical = [&](Partition p) {
        for (auto& g : p) std::sort(g.begin(), g.end(), byBytes);
        std::sort(p.begin(), p.end(), [&](const auto& a, const auto& b) { return byBytes(a[0], b[0]); });
        return p;
    };
    const SubsamplePattern pattern = SubsamplePattern::forEdgeAntiAliasing(1);
    TileRasterizer rasterizer(pattern);
    rasterizer.reset({0, 0, 6, 6});
    for (const ScreenTriangle& t : tris) rasterizer.add(t);
    rasterizer.finish();
    PixelResolver resolver(pattern, topo);
    size_t longRuns = 0, splitPixels = 0;
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 6; ++x) {
            const auto frags = rasterizer.fragments(x, y);
            const size_t n = frags.size();
            std::vector<uint32_t> root(n);
            for (uint32_t i = 0; i < n; ++i) root[i] = i;
            auto find = [&](uint32_t i) {
                while (root[i] != i) i = root[i];
                return i;
            };
            size_t ofObject0 = 0;
            for (size_t i = 0; i < n; ++i) {
                ofObject0 += frags[i].object == 0;
                for (size_t j = i + 1; j < n; ++j)
                    if (frags[i].object == frags[j].object &&
                        (frags[i].triangle == frags[j].triangle || softNamed(frags[i], frags[j]) ||
                         softNamed(frags[j], frags[i])))
                        root[find(uint32_t(j))] = find(uint32_t(i));
            }
            longRuns += ofObject0 > 8;
            Partition want(n);
            for (uint32_t i = 0; i < n; ++i) want[find(i)].push_back(frags[i]);
            std::erase_if(want, [](const auto& g) { return g.empty(); });
            resolver.resolve(frags);
            Partition got;
            for (const SurfaceGroup& g : resolver.groups())
                got.emplace_back(resolver.members().begin() + g.memberBegin,
                                 resolver.members().begin() + g.memberBegin + g.memberCount);
            splitPixels += want.size() > 2;
            ASSERT_EQ(got.size(), want.size()) << "pixel " << x << "," << y;
            want = canonical(std::move(want));
            got = canonical(std::move(got));
            for (size_t g = 0; g < want.size(); ++g) {
                ASSERT_EQ(got[g].size(), want[g].size());
                for (size_t k = 0; k < want[g].size(); ++k)
                    EXPECT_EQ(std::memcmp(&got[g][k], &want[g][k], sizeof(Fragment)), 0);
            }
        }
    }
    EXPECT_GT(longRuns, 20u);
    EXPECT_GT(splitPixels, 10u);
}

TEST(PixelResolver, FoldedSurfaceGivesTwoGroupsUnlessJoinedInThePixel) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    // Triangles 0–1–2 of one object in a strip; 0 (front, z 1) and 2 (back, z 3) overlap here.
    const uint32_t neighbors[9] = {1, kNoTriangle, kNoTriangle, 0, 2, kNoTriangle, 1, kNoTriangle, kNoTriangle};
    const ObjectTopology topo{neighbors, 3};
    PixelResolver resolver(p, std::span<const ObjectTopology>(&topo, 1));
    Fragment front = fullFragment(0, 0, 1.0f, p);
    front.mask = leftHalf(p);
    front.area = 0.5f;
    front.cu = 0.25f;
    const Fragment back = fullFragment(0, 2, 3.0f, p);
    const Fragment frags[2] = {front, back};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.members()[resolver.groups()[0].memberBegin].triangle, 0u);
    EXPECT_FLOAT_EQ(resolver.groups()[0].coverage, 0.5f);
    EXPECT_FLOAT_EQ(resolver.groups()[1].coverage, 0.5f);  // full surface, partly hidden: 1 − 0.5
    EXPECT_EQ(resolver.groups()[1].visibleMask, p.active & ~leftHalf(p));

    // With triangle 1 in the pixel too, the three join transitively into one surface.
    Fragment middle = fullFragment(0, 1, 2.0f, p);
    middle.mask = 0;
    middle.area = 0.01f;
    const Fragment joined[3] = {front, back, middle};
    resolver.resolve(joined);
    EXPECT_EQ(resolver.groups().size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Occlusion and transparency

TEST(PixelResolver, EdgeInFrontOfAFullSurfaceIsExact) {
    constexpr int kSize = 8;
    const PixelRect region{0, 0, kSize, kSize};
    const uint32_t bgNeighbors[6] = {kNoTriangle, kNoTriangle, 1, 0, kNoTriangle, kNoTriangle};
    const ObjectTopology topo[2] = {{nullptr, 0}, {bgNeighbors, 2}};
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        TileRasterizer rasterizer(p);
        PixelResolver resolver(p, topo);
        std::mt19937 rng(31 + eaa);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        int partial = 0;
        for (int trial = 0; trial < 25; ++trial) {
            const std::vector<Pt> front = {{uni(rng) * kSize, uni(rng) * kSize},
                                           {uni(rng) * kSize, uni(rng) * kSize},
                                           {uni(rng) * kSize, uni(rng) * kSize}};
            rasterizer.reset(region);
            rasterizer.add(makeTriangle({-2, -2}, {kSize + 2, -2}, {kSize + 2, kSize + 2}, 1, 0, 10.0));
            rasterizer.add(makeTriangle({-2, -2}, {kSize + 2, kSize + 2}, {-2, kSize + 2}, 1, 1, 10.0));
            ScreenTriangle ft = makeTriangle(front[0], front[1], front[2], 0, 0);
            setPlaneDepth(ft, 1.0, 0.02, 0.03);
            rasterizer.add(ft);
            rasterizer.finish();
            for (int y = 0; y < kSize; ++y) {
                for (int x = 0; x < kSize; ++x) {
                    const double want = exactArea(front, x, y);
                    const float alpha = resolvedAlpha(resolver, rasterizer.fragments(x, y));
                    EXPECT_NEAR(alpha, 1.0, 1e-4) << "eaa " << eaa << " trial " << trial;
                    float frontCov = 0, backCov = 0;
                    for (const SurfaceGroup& g : resolver.groups()) (g.object == 0 ? frontCov : backCov) += g.coverage;
                    ASSERT_NEAR(frontCov, want, 1e-4) << "eaa " << eaa << " trial " << trial << " pixel " << x << "," << y;
                    ASSERT_NEAR(backCov, 1.0 - want, 1e-4) << "eaa " << eaa << " trial " << trial << " pixel " << x << "," << y;
                    EXPECT_NEAR(resolver.opaqueCoverage(), 1.0, 1e-4);
                    if (want > 0 && want < 1) ++partial;
                }
            }
        }
        EXPECT_GT(partial, 100);
    }
}

TEST(PixelResolver, TransparentSurfaceLetsTheBackThrough) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    PixelResolver resolver(p, {});
    const Fragment frags[2] = {fullFragment(1, 0, 5.0f, p), fullFragment(0, 0, 1.0f, p, kFragmentTransparent)};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    const SurfaceGroup& front = resolver.groups()[0];
    const SurfaceGroup& back = resolver.groups()[1];
    EXPECT_TRUE(front.transparent);
    EXPECT_FALSE(back.transparent);
    EXPECT_EQ(front.visibleMask, p.active);
    EXPECT_EQ(back.visibleMask, p.active);
    EXPECT_FLOAT_EQ(front.coverage, 1.0f);
    EXPECT_FLOAT_EQ(back.coverage, 1.0f);
    EXPECT_FLOAT_EQ(resolver.opaqueCoverage(), 1.0f);
    EXPECT_FLOAT_EQ(resolver.nearestDepth(), 5.0f);  // transparent surfaces do not count

    SurfaceShade shades[2];
    for (int c = 0; c < 3; ++c) {
        shades[0].color[c] = 0.1f * (c + 1);  // premultiplied: already scaled by opacity 0.5
        shades[0].transparency[c] = 0.5f;
        shades[1].color[c] = 1.0f - 0.25f * c;
    }
    SurfaceContribution out[2];
    resolver.composite(shades, out);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(out[0].color[c], 0.1f * (c + 1), 1e-6);
        EXPECT_NEAR(out[1].color[c], 0.5f * (1.0f - 0.25f * c), 1e-6);
    }
    EXPECT_NEAR(out[0].alpha, 0.5, 1e-6);
    EXPECT_NEAR(out[1].alpha, 0.5, 1e-6);

    // Per-channel transparency filters the back colour channel by channel.
    shades[0].transparency[0] = 1.0f;
    shades[0].transparency[1] = 0.25f;
    shades[0].transparency[2] = 0.0f;
    resolver.composite(shades, out);
    EXPECT_NEAR(out[1].color[0], 1.0, 1e-6);
    EXPECT_NEAR(out[1].color[1], 0.25 * 0.75, 1e-6);
    EXPECT_NEAR(out[1].color[2], 0.0, 1e-6);
    EXPECT_NEAR(out[0].alpha + out[1].alpha, 1.0, 1e-6);
    EXPECT_NEAR(out[0].alpha, (0.0 + 0.75 + 1.0) / 3, 1e-6);
}

TEST(PixelResolver, PartialTransparentSurfaceOverOpaqueComposites) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    PixelResolver resolver(p, {});
    Fragment glass = fullFragment(0, 0, 1.0f, p, kFragmentTransparent);
    glass.mask = leftHalf(p);
    glass.area = 0.5f;
    glass.cu = 0.25f;
    const Fragment frags[2] = {glass, fullFragment(1, 0, 2.0f, p)};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_FLOAT_EQ(resolver.groups()[0].coverage, 0.5f);
    EXPECT_FLOAT_EQ(resolver.groups()[1].coverage, 1.0f);
    SurfaceShade shades[2];
    for (int c = 0; c < 3; ++c) {
        shades[0].color[c] = 0.2f;
        shades[0].transparency[c] = 0.5f;
        shades[1].color[c] = 1.0f;
    }
    SurfaceContribution out[2];
    resolver.composite(shades, out);
    EXPECT_NEAR(out[0].color[0], 0.5 * 0.2, 1e-6);
    EXPECT_NEAR(out[0].alpha, 0.5 * 0.5, 1e-6);
    EXPECT_NEAR(out[1].color[0], 0.5 * 0.5 + 0.5, 1e-6);  // half behind glass, half clear
    EXPECT_NEAR(out[0].alpha + out[1].alpha, 1.0, 1e-6);
    EXPECT_NEAR(out[0].cu, 0.25, 1e-6);
}

TEST(PixelResolver, TransparentBehindOpaqueIsHidden) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(2);
    PixelResolver resolver(p, {});
    const Fragment frags[2] = {fullFragment(0, 0, 1.0f, p), fullFragment(1, 0, 2.0f, p, kFragmentTransparent)};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.groups()[1].visibleMask, 0u);
    EXPECT_FLOAT_EQ(resolver.groups()[1].coverage, 0.0f);
    EXPECT_NEAR(resolvedAlpha(resolver, frags), 1.0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Slivers, ties, order

TEST(PixelResolver, SliverBehindAnOpaqueSurfaceIsHidden) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(3);
    PixelResolver resolver(p, {});
    Fragment sliver = fullFragment(1, 0, 2.0f, p);
    sliver.mask = 0;
    sliver.area = 0.05f;
    sliver.cu = 0.9f;
    sliver.cv = 0.1f;
    const Fragment behind[2] = {fullFragment(0, 0, 1.0f, p), sliver};
    resolver.resolve(behind);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.groups()[1].object, 1u);
    EXPECT_FLOAT_EQ(resolver.groups()[1].coverage, 0.0f);
    EXPECT_NEAR(resolvedAlpha(resolver, behind), 1.0, 1e-6);

    // In front: visible with its exact area; the full surface behind keeps the rest.
    sliver.z0 = 0.5f;
    const Fragment inFront[2] = {fullFragment(0, 0, 1.0f, p), sliver};
    resolver.resolve(inFront);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.groups()[0].object, 1u);
    EXPECT_FLOAT_EQ(resolver.groups()[0].coverage, 0.05f);
    EXPECT_NEAR(resolver.groups()[1].coverage, 0.95f, 1e-6);
    EXPECT_NEAR(resolvedAlpha(resolver, inFront), 1.0, 1e-6);
    EXPECT_FLOAT_EQ(resolver.nearestDepth(), 0.5f);
}

TEST(PixelResolver, SliverNextToItsMeshNeighbourStaysVisible) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(3);
    // Triangle 1 folds away from triangle 0 across a hard edge; 0 is nearer at the sliver.
    const uint32_t neighbors[6] = {1 | kHardEdgeBit, kNoTriangle, kNoTriangle, 0 | kHardEdgeBit, kNoTriangle, kNoTriangle};
    const ObjectTopology topo{neighbors, 2};
    Fragment big = fullFragment(0, 0, 1.0f, p);
    big.area = 0.9f;
    Fragment sliver = fullFragment(0, 1, 2.0f, p);
    sliver.mask = 0;
    sliver.area = 0.1f;
    sliver.cu = 0.95f;
    const Fragment frags[2] = {big, sliver};
    PixelResolver withTopology(p, std::span<const ObjectTopology>(&topo, 1));
    withTopology.resolve(frags);
    ASSERT_EQ(withTopology.groups().size(), 2u);
    EXPECT_FLOAT_EQ(withTopology.groups()[1].coverage, 0.1f);
    EXPECT_NEAR(resolvedAlpha(withTopology, frags), 1.0, 1e-6);
    // Not neighbours: the nearer fragment hides it.
    PixelResolver without(p, {});
    without.resolve(frags);
    ASSERT_EQ(without.groups().size(), 2u);
    EXPECT_FLOAT_EQ(without.groups()[1].coverage, 0.0f);
}

TEST(PixelResolver, TiesGoToTheSmallerObjectThenTriangle) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    PixelResolver resolver(p, {});
    const Fragment objects[2] = {fullFragment(3, 0, 2.0f, p), fullFragment(1, 7, 2.0f, p)};
    resolver.resolve(objects);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.groups()[0].object, 1u);
    EXPECT_EQ(resolver.groups()[0].visibleMask, p.active);
    EXPECT_EQ(resolver.groups()[1].visibleMask, 0u);
    EXPECT_FLOAT_EQ(resolver.groups()[0].coverage, 1.0f);
    EXPECT_FLOAT_EQ(resolver.groups()[1].coverage, 0.0f);

    const Fragment triangles[2] = {fullFragment(4, 9, 2.0f, p), fullFragment(4, 2, 2.0f, p)};
    resolver.resolve(triangles);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_EQ(resolver.members()[resolver.groups()[0].memberBegin].triangle, 2u);
    EXPECT_EQ(resolver.groups()[0].visibleMask, p.active);
    EXPECT_FLOAT_EQ(resolver.opaqueCoverage(), 1.0f);
}

TEST(PixelResolver, ResultDoesNotDependOnFragmentOrder) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    // Three objects: a soft fan (0), a transparent polygon (1), a hard-edged fan (2).
    std::vector<std::vector<uint32_t>> neighborStore;
    std::vector<ObjectTopology> topo;
    std::vector<ScreenTriangle> tris;
    for (uint32_t object = 0; object < 3; ++object) {
        const std::vector<Pt> poly = randomPolygon(rng, {2 + uni(rng) * 2, 2 + uni(rng) * 2}, 2);
        Fan fan = makeFan(poly, object, 1 + object + uni(rng), 0.3 * (uni(rng) - 0.5), 0.3 * (uni(rng) - 0.5));
        if (object == 2) {
            for (uint32_t& nb : fan.neighbors) {
                if (nb != kNoTriangle) nb |= kHardEdgeBit;
            }
        }
        for (ScreenTriangle& t : fan.triangles) {
            t.transparent = object == 1;
            tris.push_back(t);
        }
        neighborStore.push_back(fan.neighbors);
    }
    for (const auto& n : neighborStore) topo.push_back({n.data(), uint32_t(n.size() / 3)});
    TileRasterizer rasterizer(p);
    rasterizer.reset({0, 0, 6, 6});
    for (const ScreenTriangle& t : tris) rasterizer.add(t);
    rasterizer.finish();

    PixelResolver resolver(p, topo);
    int busy = 0;
    for (int y = 0; y < 6; ++y) {
        for (int x = 0; x < 6; ++x) {
            const auto frags = rasterizer.fragments(x, y);
            std::vector<Fragment> shuffled(frags.begin(), frags.end());
            resolver.resolve(frags);
            const std::vector<SurfaceGroup> groups(resolver.groups().begin(), resolver.groups().end());
            const std::vector<Fragment> members(resolver.members().begin(), resolver.members().end());
            const float nearest = resolver.nearestDepth(), opaque = resolver.opaqueCoverage();
            const size_t n = groups.size();
            std::vector<SurfaceShade> shades(n);
            for (size_t i = 0; i < n; ++i) {
                for (int c = 0; c < 3; ++c) {
                    shades[i].color[c] = 0.3f + 0.1f * c + 0.05f * float(i);
                    shades[i].transparency[c] = 0.4f;
                }
            }
            std::vector<SurfaceContribution> want(n), got(n);
            resolver.composite(shades, want);
            if (n >= 3) ++busy;
            for (int round = 0; round < 5; ++round) {
                std::shuffle(shuffled.begin(), shuffled.end(), rng);
                resolver.resolve(shuffled);
                ASSERT_EQ(resolver.groups().size(), n);
                for (size_t i = 0; i < n; ++i) expectSameGroup(resolver.groups()[i], groups[i]);
                for (size_t i = 0; i < members.size(); ++i) {
                    EXPECT_EQ(std::memcmp(&resolver.members()[i], &members[i], sizeof(Fragment)), 0);
                }
                EXPECT_TRUE(sameBits(resolver.nearestDepth(), nearest));
                EXPECT_TRUE(sameBits(resolver.opaqueCoverage(), opaque));
                resolver.composite(shades, got);
                for (size_t i = 0; i < n; ++i) {
                    EXPECT_TRUE(sameBits(got[i].alpha, want[i].alpha));
                    for (int c = 0; c < 3; ++c) EXPECT_TRUE(sameBits(got[i].color[c], want[i].color[c]));
                }
            }
        }
    }
    EXPECT_GT(busy, 0);
}

TEST(PixelResolver, EmptyPixelHasNoSurfaces) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    PixelResolver resolver(p, {});
    resolver.resolve({});
    EXPECT_TRUE(resolver.groups().empty());
    EXPECT_TRUE(resolver.members().empty());
    EXPECT_EQ(resolver.nearestDepth(), std::numeric_limits<float>::infinity());
    EXPECT_EQ(resolver.opaqueCoverage(), 0.0f);
    EXPECT_EQ(resolver.stats().pixels, 0u);
    resolver.composite({}, {});
    // A previous result is cleared.
    const Fragment one[1] = {fullFragment(0, 0, 1.0f, p)};
    resolver.resolve(one);
    EXPECT_EQ(resolver.groups().size(), 1u);
    resolver.resolve({});
    EXPECT_TRUE(resolver.groups().empty());
    EXPECT_EQ(resolver.stats().pixels, 1u);
}

TEST(PixelResolver, NonFiniteFragmentsDoNotBreakResolution) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(2);
    PixelResolver resolver(p, {});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Fragment a = fullFragment(0, 0, nan, p);
    Fragment b = fullFragment(1, 0, 2.0f, p);
    b.area = nan;
    b.cu = nan;
    Fragment c = fullFragment(2, 0, std::numeric_limits<float>::infinity(), p);
    c.dzdu = -std::numeric_limits<float>::infinity();
    std::vector<Fragment> frags = {a, b, c};
    resolver.resolve(frags);
    const std::vector<SurfaceGroup> first(resolver.groups().begin(), resolver.groups().end());
    ASSERT_EQ(first.size(), 3u);
    std::reverse(frags.begin(), frags.end());
    resolver.resolve(frags);
    for (size_t i = 0; i < first.size(); ++i) {
        expectSameGroup(resolver.groups()[i], first[i]);
        EXPECT_GE(first[i].coverage, 0.0f);
        EXPECT_LE(first[i].coverage, 1.0f);
        EXPECT_FALSE(std::isnan(first[i].coverage));
        EXPECT_FALSE(std::isnan(first[i].depth));
    }
    EXPECT_LE(resolver.opaqueCoverage(), 1.0f);
    std::vector<SurfaceShade> shades(3);
    std::vector<SurfaceContribution> out(3);
    resolver.composite(shades, out);
    for (const SurfaceContribution& o : out) EXPECT_FALSE(std::isnan(o.alpha));
}

TEST(PixelResolver, OpaqueCoverageIsScaledToOne) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    PixelResolver resolver(p, {});
    Fragment part = fullFragment(0, 0, 2.0f, p);
    part.mask = leftHalf(p);
    part.area = 0.6f;
    Fragment sliver = fullFragment(1, 0, 1.0f, p);  // nearer, no sub-sample, overlaps `part`
    sliver.mask = 0;
    sliver.area = 0.6f;
    sliver.cu = 0.2f;
    const Fragment frags[2] = {part, sliver};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    EXPECT_NEAR(resolver.groups()[0].coverage, 0.5, 1e-6);
    EXPECT_NEAR(resolver.groups()[1].coverage, 0.5, 1e-6);
    EXPECT_NEAR(resolver.opaqueCoverage(), 1.0, 1e-6);
}

TEST(PixelResolver, GroupCentroidDepthAndMemberLookup) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    const uint32_t neighbors[6] = {1, kNoTriangle, kNoTriangle, 0, kNoTriangle, kNoTriangle};
    const ObjectTopology topo{neighbors, 2};
    PixelResolver resolver(p, std::span<const ObjectTopology>(&topo, 1));
    Fragment left = fullFragment(0, 0, 3.0f, p);
    left.mask = leftHalf(p);
    left.area = 0.5f;
    left.dzdu = -1.0f;  // depth falls to the right
    Fragment right = fullFragment(0, 1, 2.5f, p);
    right.mask = p.active & ~leftHalf(p);
    right.area = 0.4f;
    const Fragment frags[2] = {right, left};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 1u);
    const SurfaceGroup& g = resolver.groups()[0];
    EXPECT_NEAR(g.cu, 0.5, 1e-6);
    EXPECT_NEAR(g.cv, 0.5, 1e-6);
    EXPECT_NEAR(g.area, 0.9, 1e-6);
    // Left member at its right-most column u = 7/16: 3 − 7/16; the right member is 2.5 flat.
    EXPECT_NEAR(g.depth, 2.5, 1e-6);
    EXPECT_NEAR(resolver.nearestDepth(), 2.5, 1e-6);
    EXPECT_EQ(resolver.memberAt(g, 0).triangle, 0u);   // column 0: left
    EXPECT_EQ(resolver.memberAt(g, 7).triangle, 1u);   // column 7: right
    EXPECT_EQ(resolver.memberAt(g, 64).triangle, 0u);  // no such bit: the larger member
    EXPECT_NEAR(g.coverage, 0.9, 1e-6);

    // A group without sub-samples is centred at its area-weighted centroid.
    Fragment s1 = fullFragment(0, 0, 1.0f, p);
    s1.mask = 0;
    s1.area = 0.01f;
    s1.cu = 0.1f;
    s1.cv = 0.2f;
    Fragment s2 = s1;
    s2.triangle = 1;
    s2.area = 0.03f;
    s2.cu = 0.5f;
    s2.cv = 0.6f;
    const Fragment slivers[2] = {s1, s2};
    resolver.resolve(slivers);
    ASSERT_EQ(resolver.groups().size(), 1u);
    EXPECT_NEAR(resolver.groups()[0].cu, 0.4, 1e-6);
    EXPECT_NEAR(resolver.groups()[0].cv, 0.5, 1e-6);
    EXPECT_EQ(resolver.memberAt(resolver.groups()[0], 3).triangle, 1u);
    EXPECT_FLOAT_EQ(resolver.groups()[0].coverage, 0.04f);
}

TEST(PixelResolver, StatsCountPixelsSurfacesAndMerges) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    const uint32_t neighbors[6] = {1, kNoTriangle, kNoTriangle, 0, kNoTriangle, kNoTriangle};
    const ObjectTopology topo{neighbors, 2};
    PixelResolver resolver(p, std::span<const ObjectTopology>(&topo, 1));
    const Fragment frags[3] = {fullFragment(0, 0, 1.0f, p), fullFragment(0, 1, 1.0f, p), fullFragment(1, 0, 2.0f, p)};
    resolver.resolve(frags);
    resolver.resolve(std::span<const Fragment>(frags, 1));
    EXPECT_EQ(resolver.stats().pixels, 2u);
    EXPECT_EQ(resolver.stats().surfaces, 3u);
    EXPECT_EQ(resolver.stats().mergedFragments, 1u);
    ResolveStats total;
    total.merge(resolver.stats());
    total.merge(resolver.stats());
    EXPECT_EQ(total.surfaces, 6u);
}

TEST(PixelResolver, CompositeFillsOnlyWhatItHasShadesFor) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    PixelResolver resolver(p, {});
    Fragment a = fullFragment(0, 0, 1.0f, p);
    a.mask = leftHalf(p);
    a.area = 0.5f;
    Fragment b = fullFragment(1, 0, 1.0f, p);
    b.mask = p.active & ~leftHalf(p);
    b.area = 0.5f;
    const Fragment frags[2] = {a, b};
    resolver.resolve(frags);
    ASSERT_EQ(resolver.groups().size(), 2u);
    SurfaceShade shades[1];
    shades[0].color[0] = shades[0].color[1] = shades[0].color[2] = 1.0f;
    SurfaceContribution out[2];
    out[1].alpha = 7.0f;
    resolver.composite(shades, out);
    EXPECT_NEAR(out[0].alpha, 0.5, 1e-6);
    EXPECT_EQ(out[1].alpha, 0.0f);
    EXPECT_EQ(out[1].color[0], 0.0f);
}


// ------------------------------------------------------------------ occlusion (step 5a)

// A dense soft mesh of `n` × `n` quads (two triangles each) over [x0, x1] × [y0, y1] on the plane
// z0 + dzdx·x + dzdy·y, soft edges everywhere unless `hard` (then every edge is hard).
Fan makeGrid(int n, double x0, double y0, double x1, double y1, uint32_t object, double z0, double dzdx, double dzdy,
             bool hard = false) {
    Fan grid;
    auto id = [&](int i, int j, int k) { return uint32_t(2 * (j * n + i) + k); };
    const uint32_t flag = hard ? kHardEdgeBit : 0u;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Pt a{x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n};
            const Pt b{x0 + (x1 - x0) * (i + 1) / n, a.y};
            const Pt c{b.x, y0 + (y1 - y0) * (j + 1) / n};
            const Pt d{a.x, c.y};
            ScreenTriangle t0 = makeTriangle(a, b, c, object, id(i, j, 0));
            ScreenTriangle t1 = makeTriangle(a, c, d, object, id(i, j, 1));
            setPlaneDepth(t0, z0, dzdx, dzdy);
            setPlaneDepth(t1, z0, dzdx, dzdy);
            grid.triangles.push_back(t0);
            grid.triangles.push_back(t1);
            // t0 = (a, b, c): edge 0 a–b (quad below), edge 1 b–c (quad right), edge 2 c–a (t1)
            grid.neighbors.push_back(j > 0 ? id(i, j - 1, 1) | flag : kNoTriangle);
            grid.neighbors.push_back(i + 1 < n ? id(i + 1, j, 1) | flag : kNoTriangle);
            grid.neighbors.push_back(id(i, j, 1) | flag);
            // t1 = (a, c, d): edge 0 a–c (t0), edge 1 c–d (quad above), edge 2 d–a (quad left)
            grid.neighbors.push_back(id(i, j, 0) | flag);
            grid.neighbors.push_back(j + 1 < n ? id(i, j + 1, 0) | flag : kNoTriangle);
            grid.neighbors.push_back(i > 0 ? id(i - 1, j, 0) | flag : kNoTriangle);
        }
    return grid;
}

double planeFar(double z0, double dzdx, double dzdy, int x, int y) {
    double far = -1e300;
    for (int c = 0; c < 4; ++c) far = std::max(far, z0 + dzdx * (x + (c & 1)) + dzdy * (y + (c >> 1)));
    return far;
}

TEST(PixelResolver, OccludingDepthNeedsAWholeOpaqueSurfaceOverThePixel) {
    constexpr int kSize = 6;
    const PixelRect region{0, 0, kSize, kSize};
    const double z0 = 5.0, dzdx = 0.01, dzdy = 0.02;
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        // A soft mesh with 3 × 3 triangles' worth of edges in every pixel seals every pixel, at the
        // farthest its plane reaches over the pixel.
        Fan wall = makeGrid(17, -0.3, -0.4, kSize + 0.2, kSize + 0.1, 0, z0, dzdx, dzdy);
        const ObjectTopology topo[1] = {{wall.neighbors.data(), uint32_t(wall.neighbors.size() / 3)}};
        TileRasterizer rasterizer(p);
        PixelResolver resolver(p, topo);
        rasterizer.reset(region);
        for (const ScreenTriangle& t : wall.triangles) rasterizer.add(t);
        rasterizer.finish();
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                ASSERT_GT(rasterizer.fragments(x, y).size(), 4u);
                const float seal = resolver.occludingDepth(rasterizer.fragments(x, y));
                EXPECT_NEAR(seal, planeFar(z0, dzdx, dzdy, x, y), 1e-5) << "eaa " << eaa << " pixel " << x << "," << y;
                EXPECT_TRUE(occludedBehind(seal, planeFar(z0, dzdx, dzdy, x, y) * 1.002));
                EXPECT_FALSE(occludedBehind(seal, planeFar(z0, dzdx, dzdy, x, y) * 1.0005));
            }

        // A coarser soft mesh (a few fragments a pixel, joined pair by pair rather than through
        // the sorted search) seals every pixel at the same depth.
        Fan coarse = makeGrid(4, -0.3, -0.4, kSize + 0.2, kSize + 0.1, 0, z0, dzdx, dzdy);
        const ObjectTopology coarseTopo[1] = {{coarse.neighbors.data(), uint32_t(coarse.neighbors.size() / 3)}};
        PixelResolver coarseResolver(p, coarseTopo);
        rasterizer.reset(region);
        for (const ScreenTriangle& t : coarse.triangles) rasterizer.add(t);
        rasterizer.finish();
        size_t most = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                most = std::max(most, rasterizer.fragments(x, y).size());
                EXPECT_NEAR(coarseResolver.occludingDepth(rasterizer.fragments(x, y)), planeFar(z0, dzdx, dzdy, x, y), 1e-5)
                    << "eaa " << eaa << " pixel " << x << "," << y;
            }
        EXPECT_LE(most, 12u);
        EXPECT_GT(most, 1u);

        // The same mesh with hard edges seals only the pixels one triangle covers; transparent, or
        // covering part of the pixel, it seals none.
        Fan hard = makeGrid(2, -0.3, -0.4, kSize + 0.2, kSize + 0.1, 0, z0, dzdx, dzdy, true);
        const ObjectTopology hardTopo[1] = {{hard.neighbors.data(), uint32_t(hard.neighbors.size() / 3)}};
        PixelResolver hardResolver(p, hardTopo);
        rasterizer.reset(region);
        for (const ScreenTriangle& t : hard.triangles) rasterizer.add(t);
        rasterizer.finish();
        int sealed = 0, open = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const auto frags = rasterizer.fragments(x, y);
                const bool single = frags.size() == 1 && frags[0].area >= 1.0f - 1e-6f;
                const float seal = hardResolver.occludingDepth(frags);
                EXPECT_EQ(std::isfinite(seal), single) << "eaa " << eaa << " pixel " << x << "," << y;
                (single ? sealed : open)++;
            }
        EXPECT_GT(sealed, 4);
        EXPECT_GT(open, 4);

        rasterizer.reset(region);
        for (ScreenTriangle t : wall.triangles) {
            t.transparent = true;
            rasterizer.add(t);
        }
        rasterizer.finish();
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) EXPECT_EQ(resolver.occludingDepth(rasterizer.fragments(x, y)), INFINITY);

        Fan part = makeGrid(9, -0.3, -0.4, 3.5, kSize + 0.1, 0, z0, dzdx, dzdy);
        const ObjectTopology partTopo[1] = {{part.neighbors.data(), uint32_t(part.neighbors.size() / 3)}};
        PixelResolver partResolver(p, partTopo);
        rasterizer.reset(region);
        for (const ScreenTriangle& t : part.triangles) rasterizer.add(t);
        rasterizer.finish();
        for (int y = 0; y < kSize; ++y) {
            EXPECT_TRUE(std::isfinite(partResolver.occludingDepth(rasterizer.fragments(2, y))));
            EXPECT_EQ(partResolver.occludingDepth(rasterizer.fragments(3, y)), INFINITY);
            EXPECT_EQ(partResolver.occludingDepth(rasterizer.fragments(4, y)), INFINITY);
        }
    }
    EXPECT_FALSE(occludedBehind(INFINITY, 10.0));
    EXPECT_FALSE(occludedBehind(1.0f, -INFINITY));
    EXPECT_FALSE(occludedBehind(1.0f, std::nan("")));
}

// The promise the renderer's skip rests on: whatever lies behind a pixel's occluding depth —
// opaque or transparent, full surfaces, edges or slivers — changes no bit of any other surface or
// of the composite, and gets nothing itself.
TEST(PixelResolver, SurfacesBehindTheOccludingDepthChangeNoBit) {
    constexpr int kSize = 6;
    const PixelRect region{0, 0, kSize, kSize};
    int sealedPixels = 0, hiddenFragments = 0, partialFront = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(trial % 4);
        std::mt19937 rng(900 + trial);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        std::vector<std::vector<uint32_t>> neighborStore;
        std::vector<ScreenTriangle> front, behind;
        // Objects 0–2: random fans in front (soft, transparent, hard-edged); object 3: the wall,
        // a soft or hard mesh, dense or coarse, sometimes not over the whole region.
        for (uint32_t object = 0; object < 3; ++object) {
            const int kind = int(uni(rng) * 3);
            Fan fan = makeFan(randomPolygon(rng, {uni(rng) * kSize, uni(rng) * kSize}, kind), object,
                              1 + object + uni(rng), 0.2 * (uni(rng) - 0.5), 0.2 * (uni(rng) - 0.5));
            if (object == 2)
                for (uint32_t& nb : fan.neighbors)
                    if (nb != kNoTriangle) nb |= kHardEdgeBit;
            for (ScreenTriangle t : fan.triangles) {
                t.transparent = object == 1;
                front.push_back(t);
            }
            neighborStore.push_back(fan.neighbors);
        }
        const double wz = 6 + uni(rng), wdx = 0.05 * (uni(rng) - 0.5), wdy = 0.05 * (uni(rng) - 0.5);
        const double wx1 = uni(rng) < 0.3 ? kSize * (0.4 + 0.5 * uni(rng)) : kSize + 0.5;
        Fan wall = makeGrid(1 + int(uni(rng) * 20), -0.5, -0.5, wx1, kSize + 0.5, 3, wz, wdx, wdy, uni(rng) < 0.25);
        for (const ScreenTriangle& t : wall.triangles) front.push_back(t);
        neighborStore.push_back(wall.neighbors);
        // Objects 4–5 behind the wall's farthest point: a soft mesh and random fans and slivers,
        // opaque and transparent.
        double wallFar = -1e300;
        for (const ScreenTriangle& t : wall.triangles)
            for (int k = 0; k < 3; ++k) wallFar = std::max(wallFar, t.z[k]);
        const double hz = wallFar * 1.003 + 0.01;
        Fan back = makeGrid(1 + int(uni(rng) * 12), -0.5 + uni(rng), -0.5 + uni(rng), kSize * uni(rng) + 1, kSize + 0.5, 4,
                            hz + 0.1, 0.01, 0.0);
        for (const ScreenTriangle& t : back.triangles) behind.push_back(t);
        neighborStore.push_back(back.neighbors);
        std::vector<uint32_t> none;
        for (int k = 0; k < 6; ++k) {
            ScreenTriangle t;
            const std::vector<Pt> poly = randomPolygon(rng, {uni(rng) * kSize, uni(rng) * kSize}, k % 3);
            Fan fan = makeFan(poly, 5, hz + 0.2 + uni(rng), 0.0, 0.01);
            for (ScreenTriangle f : fan.triangles) {
                f.triangle += uint32_t(100 * k);
                f.transparent = k % 2 == 1;
                behind.push_back(f);
            }
        }
        neighborStore.push_back(none);
        std::vector<ObjectTopology> topo;
        for (const auto& n : neighborStore) topo.push_back({n.empty() ? nullptr : n.data(), uint32_t(n.size() / 3)});

        TileRasterizer without(p), with(p);
        without.reset(region);
        with.reset(region);
        for (const ScreenTriangle& t : front) {
            without.add(t);
            with.add(t);
        }
        for (const ScreenTriangle& t : behind) with.add(t);
        without.finish();
        with.finish();
        PixelResolver a(p, topo), b(p, topo);
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const auto fa = without.fragments(x, y), fb = with.fragments(x, y);
                const float seal = a.occludingDepth(fa);
                if (!occludedBehind(seal, hz)) continue;
                ++sealedPixels;
                hiddenFragments += int(fb.size() - fa.size());
                a.resolve(fa);
                b.resolve(fb);
                std::vector<SurfaceShade> sa(a.groups().size()), sb(b.groups().size());
                auto shadeOf = [](const SurfaceGroup& g, SurfaceShade& s) {
                    for (int c = 0; c < 3; ++c) {
                        s.color[c] = 0.2f + 0.1f * float(g.object) + 0.05f * float(c);
                        s.transparency[c] = 0.3f + 0.1f * float(c);
                    }
                };
                for (size_t i = 0; i < sa.size(); ++i) shadeOf(a.groups()[i], sa[i]);
                for (size_t i = 0; i < sb.size(); ++i) shadeOf(b.groups()[i], sb[i]);
                std::vector<SurfaceContribution> ca(sa.size()), cb(sb.size());
                a.composite(sa, ca);
                b.composite(sb, cb);
                EXPECT_TRUE(sameBits(a.nearestDepth(), b.nearestDepth()));
                EXPECT_TRUE(sameBits(a.opaqueCoverage(), b.opaqueCoverage()));
                size_t k = 0;
                for (size_t i = 0; i < sb.size(); ++i) {
                    const SurfaceGroup& g = b.groups()[i];
                    if (g.object >= 4) {
                        EXPECT_EQ(g.coverage, 0.0f) << "trial " << trial << " pixel " << x << "," << y;
                        EXPECT_EQ(g.visibleMask, 0u);
                        EXPECT_EQ(cb[i].alpha, 0.0f);
                        for (int c = 0; c < 3; ++c) EXPECT_EQ(cb[i].color[c], 0.0f);
                        continue;
                    }
                    ASSERT_LT(k, sa.size());
                    const SurfaceGroup& h = a.groups()[k];
                    EXPECT_EQ(g.object, h.object);
                    EXPECT_EQ(g.mask, h.mask);
                    EXPECT_EQ(g.visibleMask, h.visibleMask);
                    EXPECT_TRUE(sameBits(g.coverage, h.coverage)) << "trial " << trial << " pixel " << x << "," << y;
                    EXPECT_TRUE(sameBits(cb[i].alpha, ca[k].alpha));
                    for (int c = 0; c < 3; ++c) EXPECT_TRUE(sameBits(cb[i].color[c], ca[k].color[c]));
                    if (g.object < 3 && g.coverage > 0 && g.coverage < 1) ++partialFront;
                    ++k;
                }
                EXPECT_EQ(k, sa.size());
            }
    }
    EXPECT_GT(sealedPixels, 500);
    EXPECT_GT(hiddenFragments, 1000);
    EXPECT_GT(partialFront, 50);
}

// An opaque surface over the whole pixel closes it: a full surface behind it gets nothing, even
// where the coverages in front of it, rounded to float, sum to a hair under one.
TEST(PixelResolver, AWholeOpaqueSurfaceClosesThePixel) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(0);
    const uint32_t fullNeighbors[6] = {kNoTriangle, kNoTriangle, 1, 0, kNoTriangle, kNoTriangle};
    const ObjectTopology topo[3] = {{nullptr, 0}, {fullNeighbors, 2}, {fullNeighbors, 2}};
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    TileRasterizer rasterizer(p);
    PixelResolver resolver(p, topo);
    int edges = 0;
    for (int trial = 0; trial < 300; ++trial) {
        rasterizer.reset({0, 0, 1, 1});
        ScreenTriangle e = makeTriangle({uni(rng) * 1.2 - 0.1, -1}, {2, -1}, {uni(rng) * 1.2 - 0.1, 2}, 0, 0, 1.0);
        rasterizer.add(e);
        for (uint32_t o = 1; o <= 2; ++o) {
            rasterizer.add(makeTriangle({-1, -1}, {2, -1}, {2, 2}, o, 0, 2.0 * o));
            rasterizer.add(makeTriangle({-1, -1}, {2, 2}, {-1, 2}, o, 1, 2.0 * o));
        }
        rasterizer.finish();
        resolver.resolve(rasterizer.fragments(0, 0));
        for (const SurfaceGroup& g : resolver.groups()) {
            if (g.object == 0 && g.coverage > 0 && g.coverage < 1) ++edges;
            if (g.object == 2) {
                EXPECT_EQ(g.coverage, 0.0f) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(edges, 200);
}

}  // namespace
}  // namespace pushpin::render
