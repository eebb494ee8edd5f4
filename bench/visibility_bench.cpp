// bench/visibility_bench.cpp: Exact Area Sampling visibility (core/render/visibility.h) measured
// two ways: throughput of TileRasterizer and PixelResolver, and image error against time next to
// stratified point sampling with Embree primary rays, on a scene whose exact image is known.
//
//   visibility_bench [--table | --micro] [--quick] [--runs N] [--triangles N[,N...]]
//                    [--size S] [--tile T] [--seed S] [--single-rays] [--benchmark_* flags]
//
// Table (error against time): screen-parallel layers of thin, small and a few large triangles,
// each at its own constant depth with its own flat colour. The exact image is computed by convex
// polygon clipping (each pixel's uncovered region, front to back). Every method renders the
// whole image on one thread: EAS at each edgeAntiAliasing level (rasterize, resolve, composite
// with the flat colours, box filter), and point sampling with 1..256 jittered samples per pixel
// traced by Embree 3 (16-ray packets, optionally single rays; BVH build timed separately). Errors are
// mean and max absolute differences of RGBA against the exact image.
// Micro-benchmarks (Google Benchmark): TileRasterizer::add + finish and PixelResolver::resolve
// on random mixed-size triangles (10k, 100k) and on a connected 100k-triangle mesh in 512×512,
// for each edgeAntiAliasing level, with triangles/s and fragments/s counters.
#include "bench/bench_support.h"
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <memory>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "core/render/fragment.h"
#include "core/render/visibility.h"

namespace {

using namespace pushpin::render;

struct Config {
    bool table = true;
    bool micro = true;
    int runs = 3;                      // timed runs per method; the table shows the median
    bool singleRays = false;           // also trace with rtcIntersect1 (much slower than packets here)
    std::vector<int> triangleCounts = {2000, 20000};
    int imageSize = 256;               // the error scene is imageSize × imageSize pixels
    int tileSize = 64;                 // EAS renders the image tile by tile
    uint64_t seed = 1;
};

// ---------------------------------------------------------------------------------------------
// Random numbers: splitmix64. Seeded per scene, and per pixel for the samplers, so every run and
// every method sees the same numbers.

uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

struct Rng {
    uint64_t state;
    explicit Rng(uint64_t seed) : state(mix64(seed + 0x9E3779B97F4A7C15ull)) {}
    uint64_t next() { return mix64(state += 0x9E3779B97F4A7C15ull); }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }            // [0, 1)
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

// ---------------------------------------------------------------------------------------------
// Scenes

struct Tri2 {
    double x[3], y[3];
};

// Random triangles of mixed shapes around random centres in [−margin, width + margin) ×
// [−margin, height + margin): 40% small (corners 0.3–3 px from the centre), 35% slivers (5–60 px
// long, 0.05–1 px wide), the rest medium (3–20 px), plus `largeCount` large ones (40–150 px).
// Orientation is random throughout. The large ones come first. All but the large ones are
// scaled by sqrt(pixels per triangle / 32), so the depth complexity stays about the same
// (about 2.5 in 256² with 8 large ones, 1.5 in 512² with 4) whatever the count: more triangles
// make a finer, more edge-heavy scene rather than a deeper one.
std::vector<Tri2> mixedTriangles(int count, int width, int height, int largeCount, Rng& rng) {
    constexpr double kMargin = 8.0;
    const double scale = std::sqrt(double(width) * height / (32.0 * std::max(1, count)));
    std::vector<Tri2> tris;
    tris.reserve(size_t(count));
    auto blob = [&](double cx, double cy, double rMin, double rMax) {
        Tri2 t;
        const double a0 = rng.uniform(0, 2 * M_PI);
        for (int k = 0; k < 3; ++k) {
            // Corners roughly 120° apart with jitter, so shapes range from equilateral to thin.
            const double a = a0 + k * (2 * M_PI / 3) + rng.uniform(-0.8, 0.8);
            const double r = rng.uniform(rMin, rMax);
            t.x[k] = cx + r * std::cos(a);
            t.y[k] = cy + r * std::sin(a);
        }
        return t;
    };
    for (int i = 0; i < count; ++i) {
        const double cx = rng.uniform(-kMargin, width + kMargin);
        const double cy = rng.uniform(-kMargin, height + kMargin);
        if (i < largeCount) {
            tris.push_back(blob(cx, cy, 40.0, 150.0));
            continue;
        }
        const double kind = rng.uniform();
        if (kind < 0.40) {
            tris.push_back(blob(cx, cy, 0.3 * scale, 3.0 * scale));
        } else if (kind < 0.75) {
            const double len = rng.uniform(5.0, 60.0) * scale, wid = rng.uniform(0.05, 1.0) * scale;
            const double a = rng.uniform(0, 2 * M_PI), ux = std::cos(a), uy = std::sin(a);
            const double along = rng.uniform(0.2, 0.8);  // where the apex sits along the base
            Tri2 t;
            t.x[0] = cx - 0.5 * len * ux;
            t.y[0] = cy - 0.5 * len * uy;
            t.x[1] = cx + 0.5 * len * ux;
            t.y[1] = cy + 0.5 * len * uy;
            t.x[2] = t.x[0] + along * len * ux - wid * uy;
            t.y[2] = t.y[0] + along * len * uy + wid * ux;
            tris.push_back(t);
        } else {
            tris.push_back(blob(cx, cy, 3.0 * scale, 20.0 * scale));
        }
    }
    return tris;
}

double triangleArea(const double x[3], const double y[3]) {
    return 0.5 * std::abs((x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]));
}

// Summed triangle area over the region's area (triangles reaching past the border count whole).
template <typename Tris>
double depthComplexity(const Tris& tris, double regionArea) {
    double sum = 0;
    for (const auto& t : tris) sum += triangleArea(t.x, t.y);
    return sum / regionArea;
}

// The error scene: screen-parallel layers. Triangle i is object i with depth depth[i] (all
// distinct) and colour color[i]; the exact image follows from 2D geometry alone.
struct LayerScene {
    int width = 0, height = 0;
    std::vector<Tri2> tris;
    std::vector<double> depth;
    std::vector<float> color;  // 3 per triangle
    std::vector<ScreenTriangle> screen;
};

LayerScene makeLayerScene(int count, int size, uint64_t seed) {
    Rng rng(seed);
    LayerScene s;
    s.width = s.height = size;
    s.tris = mixedTriangles(count, size, size, 8, rng);
    std::vector<int> order(static_cast<size_t>(count));
    std::iota(order.begin(), order.end(), 0);
    for (int i = count - 1; i > 0; --i) std::swap(order[size_t(i)], order[size_t(rng.next() % uint64_t(i + 1))]);
    for (int i = 0; i < count; ++i) {
        // Depth keys in [1, 2), 1/count apart: distinct in float as well.
        s.depth.push_back(1.0 + (order[size_t(i)] + 0.5) / count);
        for (int c = 0; c < 3; ++c) s.color.push_back(float(rng.uniform(0.05, 1.0)));
        ScreenTriangle st;
        for (int k = 0; k < 3; ++k) {
            st.x[k] = s.tris[size_t(i)].x[k];
            st.y[k] = s.tris[size_t(i)].y[k];
            st.z[k] = s.depth.back();
        }
        st.object = uint32_t(i);
        st.triangle = 0;
        s.screen.push_back(st);
    }
    return s;
}

// Every object of the layer scene is one triangle with no neighbours.
std::vector<ObjectTopology> isolatedTopology(size_t objects) {
    static const uint32_t kNone[3] = {kNoTriangle, kNoTriangle, kNoTriangle};
    return std::vector<ObjectTopology>(objects, ObjectTopology{kNone, 1});
}

// A throughput scene with the topology the resolver needs.
struct ThroughputScene {
    std::string name;
    PixelRect region;
    std::vector<ScreenTriangle> tris;
    std::vector<std::vector<uint32_t>> neighbors;  // per object: ObjectTopology::neighbors

    std::vector<ObjectTopology> topology() const {
        std::vector<ObjectTopology> t;
        for (const auto& n : neighbors) t.push_back(ObjectTopology{n.data(), uint32_t(n.size() / 3)});
        return t;
    }
};

// Random mixed triangles in size × size, each its own object, each on a tilted plane (depth
// varies across the triangle), so triangles interpenetrate as well as overlap.
ThroughputScene randomThroughputScene(int count, int size, uint64_t seed) {
    Rng rng(seed);
    ThroughputScene s;
    s.name = "random" + std::to_string(count / 1000) + "k";
    s.region = PixelRect{0, 0, size, size};
    const std::vector<Tri2> tris = mixedTriangles(count, size, size, 4, rng);
    s.neighbors.assign(size_t(count), {kNoTriangle, kNoTriangle, kNoTriangle});
    for (int i = 0; i < count; ++i) {
        ScreenTriangle st;
        const double base = rng.uniform(1.0, 2.0), gx = rng.uniform(-0.002, 0.002), gy = rng.uniform(-0.002, 0.002);
        for (int k = 0; k < 3; ++k) {
            st.x[k] = tris[size_t(i)].x[k];
            st.y[k] = tris[size_t(i)].y[k];
            st.z[k] = base + gx * (st.x[k] - size / 2) + gy * (st.y[k] - size / 2);
        }
        st.object = uint32_t(i);
        s.tris.push_back(st);
    }
    return s;
}

// One connected mesh: a jittered (gx × gy)-quad grid over size × size, two triangles per quad,
// soft edges everywhere, depth a smooth height field. Most pixels see mesh interiors, so fragment
// merging dominates the resolve.
ThroughputScene meshThroughputScene(int quadsPerSide, int size, uint64_t seed) {
    Rng rng(seed);
    ThroughputScene s;
    const int n = quadsPerSide;
    s.name = "mesh" + std::to_string(2 * n * n / 1000) + "k";
    s.region = PixelRect{0, 0, size, size};
    const double cell = double(size) / n;
    std::vector<double> vx(size_t(n + 1) * (n + 1)), vy(vx.size()), vz(vx.size());
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const size_t v = size_t(j) * (n + 1) + i;
            const bool border = i == 0 || j == 0 || i == n || j == n;
            vx[v] = i * cell + (border ? 0.0 : rng.uniform(-0.3, 0.3) * cell);
            vy[v] = j * cell + (border ? 0.0 : rng.uniform(-0.3, 0.3) * cell);
            vz[v] = 1.5 + 0.2 * std::sin(vx[v] * 0.05) * std::cos(vy[v] * 0.04);
        }
    // Quad (i, j) has corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
    // Triangle 2q is (a, b, c), triangle 2q+1 is (a, c, d); edge k joins corner k and k+1.
    auto quad = [&](int i, int j) { return (i < 0 || j < 0 || i >= n || j >= n) ? -1 : j * n + i; };
    auto tri = [&](int q, int half) { return q < 0 ? kNoTriangle : uint32_t(2 * q + half); };
    std::vector<uint32_t> nb(size_t(6) * n * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int q = quad(i, j);
            const size_t a = size_t(j) * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            const size_t corners[2][3] = {{a, b, c}, {a, c, d}};
            for (int half = 0; half < 2; ++half) {
                ScreenTriangle st;
                for (int k = 0; k < 3; ++k) {
                    st.x[k] = vx[corners[half][k]];
                    st.y[k] = vy[corners[half][k]];
                    st.z[k] = vz[corners[half][k]];
                }
                st.object = 0;
                st.triangle = uint32_t(2 * q + half);
                s.tris.push_back(st);
            }
            uint32_t* t0 = &nb[size_t(6) * q];
            t0[0] = tri(quad(i, j - 1), 1);  // a-b: the c-d edge of the quad above
            t0[1] = tri(quad(i + 1, j), 1);  // b-c: the d-a edge of the quad to the right
            t0[2] = tri(q, 1);               // c-a: the diagonal
            t0[3] = tri(q, 0);               // a-c: the diagonal
            t0[4] = tri(quad(i, j + 1), 0);  // c-d: the a-b edge of the quad below
            t0[5] = tri(quad(i - 1, j), 0);  // d-a: the b-c edge of the quad to the left
        }
    // Adjacency must be mutual: a triangle's neighbour lists the triangle back across one edge.
    for (uint32_t t = 0; t < uint32_t(2 * n * n); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t o = nb[3 * t + k];
            if (o != kNoTriangle && nb[3 * o] != t && nb[3 * o + 1] != t && nb[3 * o + 2] != t) {
                std::fprintf(stderr, "mesh topology: %u lists %u, not back\n", t, o);
                std::exit(1);
            }
        }
    s.neighbors.push_back(std::move(nb));
    return s;
}

// ---------------------------------------------------------------------------------------------
// Exact reference by convex polygon clipping.

struct P2 {
    double x, y;
};
using Poly = std::vector<P2>;

// Keeps the part of `in` where a·x + b·y + c ≥ 0 (Sutherland–Hodgman against one half-plane;
// a convex polygon stays convex and gains at most one vertex).
void clipHalfPlane(const Poly& in, double a, double b, double c, Poly& out) {
    out.clear();
    const size_t n = in.size();
    for (size_t i = 0; i < n; ++i) {
        const P2& p = in[i];
        const P2& q = in[(i + 1) % n];
        const double fp = a * p.x + b * p.y + c, fq = a * q.x + b * q.y + c;
        if (fp >= 0) out.push_back(p);
        if ((fp >= 0) != (fq >= 0)) {
            const double t = fp / (fp - fq);
            out.push_back(P2{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
        }
    }
    if (out.size() < 3) out.clear();
}

double polyArea(const Poly& p) {
    double s = 0;
    for (size_t i = 0, n = p.size(); i < n; ++i) {
        const P2& a = p[i];
        const P2& b = p[(i + 1) % n];
        s += a.x * b.y - a.y * b.x;
    }
    return 0.5 * std::abs(s);
}

// Inward half-planes of a triangle's edges: a·x + b·y + c ≥ 0 inside.
struct EdgePlanes {
    double a[3], b[3], c[3];
    bool degenerate = false;
};

EdgePlanes edgePlanes(const Tri2& t) {
    EdgePlanes e;
    const double orient = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
    e.degenerate = !(std::abs(orient) > 0);
    const double sign = orient >= 0 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        e.a[k] = -sign * (t.y[l] - t.y[k]);
        e.b[k] = sign * (t.x[l] - t.x[k]);
        e.c[k] = -(e.a[k] * t.x[k] + e.b[k] * t.y[k]);
    }
    return e;
}

// RGBA image, premultiplied, 4 values per pixel.
struct Image {
    int width = 0, height = 0;
    std::vector<double> rgba;
};

struct ReferenceStats {
    double maxCoverageDefect = 0;  // max over pixels of |visible + uncovered − 1|
    double maxFrontAreaDefect = 0; // the nearest triangle's summed visible area against its area
    double frontArea = 0;          // that area (inside the image)
    double seconds = 0;
    size_t maxPieces = 0;          // largest number of uncovered convex pieces in one pixel
};

// Each pixel starts with its square uncovered. Triangles are taken front to back: a triangle's
// visible area is the area of (uncovered ∩ triangle), and the uncovered region loses the
// triangle: a convex piece minus a convex triangle is the union of (piece outside edge 0),
// (piece inside edge 0, outside edge 1) and (inside edges 0, 1, outside edge 2), at most 3
// disjoint convex pieces. This equals, for each triangle, area(triangle ∩ pixel) minus the part
// covered by the union of the nearer triangles.
Image exactReference(const LayerScene& s, ReferenceStats& stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const size_t n = s.tris.size();
    std::vector<uint32_t> byDepth(n);
    std::iota(byDepth.begin(), byDepth.end(), 0u);
    std::sort(byDepth.begin(), byDepth.end(), [&](uint32_t a, uint32_t b) { return s.depth[a] < s.depth[b]; });
    std::vector<EdgePlanes> planes(n);
    for (size_t i = 0; i < n; ++i) planes[i] = edgePlanes(s.tris[i]);

    // Per-pixel lists of the triangles whose bounding box touches the pixel, nearest first.
    const size_t pixels = size_t(s.width) * s.height;
    std::vector<std::vector<uint32_t>> lists(pixels);
    for (uint32_t t : byDepth) {
        if (planes[t].degenerate) continue;
        const Tri2& tr = s.tris[t];
        const int x0 = std::max(0, int(std::floor(std::min({tr.x[0], tr.x[1], tr.x[2]}))));
        const int x1 = std::min(s.width - 1, int(std::floor(std::max({tr.x[0], tr.x[1], tr.x[2]}))));
        const int y0 = std::max(0, int(std::floor(std::min({tr.y[0], tr.y[1], tr.y[2]}))));
        const int y1 = std::min(s.height - 1, int(std::floor(std::max({tr.y[0], tr.y[1], tr.y[2]}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) lists[size_t(y) * s.width + x].push_back(t);
    }

    constexpr double kTinyArea = 1e-14;  // pieces smaller than this are rounding residue
    Image img{s.width, s.height, std::vector<double>(pixels * 4, 0.0)};
    std::vector<double> visibleSum(n, 0.0);
    std::vector<Poly> cur, next;
    Poly inside, tmp, rest, out;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const size_t p = size_t(y) * s.width + x;
            cur.assign(1, Poly{{double(x), double(y)}, {x + 1.0, double(y)}, {x + 1.0, y + 1.0}, {double(x), y + 1.0}});
            double alpha = 0;
            for (uint32_t t : lists[p]) {
                if (cur.empty()) break;
                const EdgePlanes& e = planes[t];
                double visible = 0;
                next.clear();
                for (const Poly& piece : cur) {
                    clipHalfPlane(piece, e.a[0], e.b[0], e.c[0], inside);
                    clipHalfPlane(inside, e.a[1], e.b[1], e.c[1], tmp);
                    clipHalfPlane(tmp, e.a[2], e.b[2], e.c[2], inside);
                    const double area = inside.empty() ? 0.0 : polyArea(inside);
                    if (area <= 0) {
                        next.push_back(piece);
                        continue;
                    }
                    visible += area;
                    rest = piece;
                    for (int k = 0; k < 3 && !rest.empty(); ++k) {
                        clipHalfPlane(rest, -e.a[k], -e.b[k], -e.c[k], out);
                        if (!out.empty() && polyArea(out) > kTinyArea) next.push_back(out);
                        clipHalfPlane(rest, e.a[k], e.b[k], e.c[k], tmp);
                        rest.swap(tmp);
                    }
                }
                cur.swap(next);
                stats.maxPieces = std::max(stats.maxPieces, cur.size());
                visibleSum[t] += visible;
                alpha += visible;
                for (int c = 0; c < 3; ++c) img.rgba[p * 4 + c] += visible * s.color[size_t(t) * 3 + c];
            }
            img.rgba[p * 4 + 3] = alpha;
            double uncovered = 0;
            for (const Poly& piece : cur) uncovered += polyArea(piece);
            stats.maxCoverageDefect = std::max(stats.maxCoverageDefect, std::abs(alpha + uncovered - 1.0));
        }

    // Nothing hides the nearest triangle that reaches into the image: its summed visible area is
    // its area inside the image (the triangle clipped to the image square).
    const Poly square{{0, 0}, {double(s.width), 0}, {double(s.width), double(s.height)}, {0, double(s.height)}};
    for (uint32_t t : byDepth) {
        const EdgePlanes& e = planes[t];
        if (e.degenerate) continue;
        clipHalfPlane(square, e.a[0], e.b[0], e.c[0], inside);
        clipHalfPlane(inside, e.a[1], e.b[1], e.c[1], tmp);
        clipHalfPlane(tmp, e.a[2], e.b[2], e.c[2], inside);
        if (inside.empty()) continue;
        stats.frontArea = polyArea(inside);
        stats.maxFrontAreaDefect = std::abs(visibleSum[t] - stats.frontArea);
        break;
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return img;
}

// ---------------------------------------------------------------------------------------------
// Timing and error

using pushpin::bench::threadCpuSeconds;

struct Timing {
    double wallMs = 0, cpuMs = 0;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

// Runs `work` `runs` times on this thread; medians of wall and thread CPU time.
Timing timeRuns(int runs, const std::function<void()>& work) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < runs; ++r) {
        const auto w0 = std::chrono::steady_clock::now();
        const double c0 = threadCpuSeconds();
        work();
        cpu.push_back(1e3 * (threadCpuSeconds() - c0));
        wall.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
    }
    return Timing{median(wall), median(cpu)};
}

struct ImageError {
    double mean = 0, max = 0, meanAlpha = 0;
};

ImageError imageError(const Image& ref, const std::vector<float>& rgba) {
    ImageError e;
    double sum = 0, sumAlpha = 0;
    for (size_t i = 0; i < ref.rgba.size(); ++i) {
        const double d = std::abs(double(rgba[i]) - ref.rgba[i]);
        sum += d;
        if (i % 4 == 3) sumAlpha += d;
        e.max = std::max(e.max, d);
    }
    e.mean = sum / double(ref.rgba.size());
    e.meanAlpha = sumAlpha / double(ref.rgba.size() / 4);
    return e;
}

// ---------------------------------------------------------------------------------------------
// EAS renderer for the layer scene

struct EasRenderer {
    const LayerScene& scene;
    SubsamplePattern pattern;
    std::vector<ObjectTopology> topology;
    TileRasterizer rasterizer;
    PixelResolver resolver;
    int tileSize;
    std::vector<std::vector<uint32_t>> bins;  // triangle indices per tile
    std::vector<SurfaceShade> shades;
    std::vector<SurfaceContribution> contributions;

    EasRenderer(const LayerScene& s, int eaa, int tile)
        : scene(s),
          pattern(SubsamplePattern::forEdgeAntiAliasing(eaa)),
          topology(isolatedTopology(s.screen.size())),
          rasterizer(pattern),
          resolver(pattern, topology),
          tileSize(tile) {}

    // Bins the triangles to tiles by bounding box, then per tile: rasterize, resolve each pixel,
    // shade each surface with its object's flat colour (opaque), composite, and sum the
    // contributions in the pixel (box filter).
    void render(std::vector<float>& rgba) {
        const int tilesX = (scene.width + tileSize - 1) / tileSize, tilesY = (scene.height + tileSize - 1) / tileSize;
        bins.resize(size_t(tilesX) * tilesY);
        for (auto& b : bins) b.clear();
        for (size_t i = 0; i < scene.screen.size(); ++i) {
            const ScreenTriangle& t = scene.screen[i];
            const double lx = std::min({t.x[0], t.x[1], t.x[2]}), hx = std::max({t.x[0], t.x[1], t.x[2]});
            const double ly = std::min({t.y[0], t.y[1], t.y[2]}), hy = std::max({t.y[0], t.y[1], t.y[2]});
            if (!(hx >= 0 && hy >= 0 && lx < scene.width && ly < scene.height)) continue;
            const int tx0 = std::max(0, int(lx) / tileSize), tx1 = std::min(tilesX - 1, int(hx) / tileSize);
            const int ty0 = std::max(0, int(ly) / tileSize), ty1 = std::min(tilesY - 1, int(hy) / tileSize);
            for (int ty = ty0; ty <= ty1; ++ty)
                for (int tx = tx0; tx <= tx1; ++tx) bins[size_t(ty) * tilesX + tx].push_back(uint32_t(i));
        }
        rgba.assign(size_t(scene.width) * scene.height * 4, 0.0f);
        for (int ty = 0; ty < tilesY; ++ty)
            for (int tx = 0; tx < tilesX; ++tx) {
                const PixelRect rect{tx * tileSize, ty * tileSize, std::min(scene.width, (tx + 1) * tileSize),
                                     std::min(scene.height, (ty + 1) * tileSize)};
                rasterizer.reset(rect);
                for (uint32_t i : bins[size_t(ty) * tilesX + tx]) rasterizer.add(scene.screen[i]);
                rasterizer.finish();
                for (int y = rect.y0; y < rect.y1; ++y)
                    for (int x = rect.x0; x < rect.x1; ++x) {
                        const std::span<const Fragment> frags = rasterizer.fragments(x, y);
                        if (frags.empty()) continue;
                        resolver.resolve(frags);
                        const std::span<const SurfaceGroup> groups = resolver.groups();
                        shades.resize(groups.size());
                        contributions.resize(groups.size());
                        for (size_t g = 0; g < groups.size(); ++g) {
                            const float* c = &scene.color[size_t(groups[g].object) * 3];
                            shades[g] = SurfaceShade{{c[0], c[1], c[2]}, {0, 0, 0}};
                        }
                        resolver.composite(shades, contributions);
                        float* px = &rgba[(size_t(y) * scene.width + x) * 4];
                        for (const SurfaceContribution& c : contributions) {
                            px[0] += c.color[0];
                            px[1] += c.color[1];
                            px[2] += c.color[2];
                            px[3] += c.alpha;
                        }
                    }
            }
    }
};

// ---------------------------------------------------------------------------------------------
// Point sampling with Embree

void embreeError(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "Embree error %d: %s\n", int(code), message ? message : "");
}

// The layer scene as one Embree triangle mesh: triangle i at z = −depth[i], so rays from z = 0
// along −z meet the nearest layer first; the primitive id is the object and gives the colour.
struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;

    EmbreeScene() {
        // One build thread, and rays are traced by the calling thread only: single-threaded.
        device = rtcNewDevice("threads=1");
        if (!device) {
            std::fprintf(stderr, "rtcNewDevice failed: %d\n", int(rtcGetDeviceError(nullptr)));
            std::exit(1);
        }
        rtcSetDeviceErrorFunction(device, embreeError, nullptr);
    }
    ~EmbreeScene() {
        if (scene) rtcReleaseScene(scene);
        rtcReleaseDevice(device);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    void build(const LayerScene& s) {
        if (scene) rtcReleaseScene(scene);
        scene = rtcNewScene(device);
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        const size_t n = s.tris.size();
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                v[9 * i + 3 * k + 0] = float(s.tris[i].x[k]);
                v[9 * i + 3 * k + 1] = float(s.tris[i].y[k]);
                v[9 * i + 3 * k + 2] = float(-s.depth[i]);
                idx[3 * i + k] = unsigned(3 * i + k);
            }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene);
        if (rtcGetDeviceError(device) != RTC_ERROR_NONE) {
            std::fprintf(stderr, "Embree scene build failed\n");
            std::exit(1);
        }
    }
};

// Stratified jittered sampling: k×k strata per pixel, one uniform point in each, from a
// generator seeded by (seed, pixel, k). Samples are produced in an order that keeps 16
// consecutive samples close together (a 4×4 block of strata, or of pixels when k < 4), so the
// 16-ray packets are coherent; the single-ray tracer walks the same order.
template <typename Emit>
void forEachSample(int width, int height, int k, uint64_t seed, Emit&& emit) {
    const int block = k >= 4 ? 1 : 4 / k;  // pixels per block side
    const int strataBlock = std::min(k, 4);
    const double inv = 1.0 / k;
    for (int by = 0; by < height; by += block)
        for (int bx = 0; bx < width; bx += block)
            for (int y = by; y < std::min(height, by + block); ++y)
                for (int x = bx; x < std::min(width, bx + block); ++x) {
                    const uint32_t pixel = uint32_t(y * width + x);
                    Rng rng(seed ^ (uint64_t(pixel) << 8) ^ uint64_t(k) << 40);
                    for (int sy0 = 0; sy0 < k; sy0 += strataBlock)
                        for (int sx0 = 0; sx0 < k; sx0 += strataBlock)
                            for (int sy = sy0; sy < sy0 + strataBlock; ++sy)
                                for (int sx = sx0; sx < sx0 + strataBlock; ++sx) {
                                    const double u = (sx + rng.uniform()) * inv, v = (sy + rng.uniform()) * inv;
                                    emit(pixel, float(x + u), float(y + v));
                                }
                }
}

struct PointSampler {
    const LayerScene& scene;
    RTCScene rtc;
    uint64_t seed;

    void shade(std::vector<float>& rgba, uint32_t pixel, unsigned geomID, unsigned primID) const {
        if (geomID == RTC_INVALID_GEOMETRY_ID) return;
        float* px = &rgba[size_t(pixel) * 4];
        const float* c = &scene.color[size_t(primID) * 3];
        px[0] += c[0];
        px[1] += c[1];
        px[2] += c[2];
        px[3] += 1.0f;
    }

    void normalize(std::vector<float>& rgba, int k) const {
        const float w = 1.0f / float(k * k);
        for (float& f : rgba) f *= w;
    }

    void renderSingle(int k, std::vector<float>& rgba) const {
        rgba.assign(size_t(scene.width) * scene.height * 4, 0.0f);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        forEachSample(scene.width, scene.height, k, seed, [&](uint32_t pixel, float x, float y) {
            RTCRayHit rh;
            rh.ray.org_x = x;
            rh.ray.org_y = y;
            rh.ray.org_z = 0.0f;
            rh.ray.dir_x = 0.0f;
            rh.ray.dir_y = 0.0f;
            rh.ray.dir_z = -1.0f;
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = 0xffffffffu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(rtc, &ctx, &rh);
            shade(rgba, pixel, rh.hit.geomID, rh.hit.primID);
        });
        normalize(rgba, k);
    }

    void renderPacket16(int k, std::vector<float>& rgba) const {
        rgba.assign(size_t(scene.width) * scene.height * 4, 0.0f);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        RTCRayHit16 rh;
        alignas(64) int valid[16];
        uint32_t pixels[16];
        int count = 0;
        auto flush = [&] {
            for (int i = 0; i < 16; ++i) {
                valid[i] = i < count ? -1 : 0;
                rh.ray.org_z[i] = 0.0f;
                rh.ray.dir_x[i] = 0.0f;
                rh.ray.dir_y[i] = 0.0f;
                rh.ray.dir_z[i] = -1.0f;
                rh.ray.tnear[i] = 0.0f;
                rh.ray.tfar[i] = INFINITY;
                rh.ray.time[i] = 0.0f;
                rh.ray.mask[i] = 0xffffffffu;
                rh.ray.id[i] = unsigned(i);
                rh.ray.flags[i] = 0;
                rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, rtc, &ctx, &rh);
            for (int i = 0; i < count; ++i) shade(rgba, pixels[i], rh.hit.geomID[i], rh.hit.primID[i]);
            count = 0;
        };
        forEachSample(scene.width, scene.height, k, seed, [&](uint32_t pixel, float x, float y) {
            rh.ray.org_x[count] = x;
            rh.ray.org_y[count] = y;
            pixels[count++] = pixel;
            if (count == 16) flush();
        });
        if (count > 0) flush();
        normalize(rgba, k);
    }
};

// ---------------------------------------------------------------------------------------------
// The error-against-time table

const char* levelName(int eaa) {
    static const char* names[4] = {"Highest", "High", "Medium", "Low"};
    return names[std::clamp(eaa, 0, 3)];
}

struct Row {
    std::string method;
    std::string setting;
    int samples = 0;  // point samples per pixel; 0 for EAS
    int eaa = -1;     // EAS level; −1 for point sampling
    Timing time;
    ImageError error;
};

// Prints the table for one scene; returns the EAS levels (eaa) that meet the goal on it.
std::vector<int> runTable(const Config& cfg, int triangleCount) {
    std::printf("\n### Error against time: %d triangles in %d×%d px (seed %llu)\n\n", triangleCount,
                cfg.imageSize, cfg.imageSize, static_cast<unsigned long long>(cfg.seed));
    const LayerScene scene = makeLayerScene(triangleCount, cfg.imageSize, cfg.seed);
    ReferenceStats rs;
    const Image ref = exactReference(scene, rs);
    double meanAlpha = 0;
    for (size_t p = 0; p < ref.rgba.size() / 4; ++p) meanAlpha += ref.rgba[p * 4 + 3];
    meanAlpha /= double(ref.rgba.size() / 4);
    std::printf("depth complexity about %.2f\n", depthComplexity(scene.tris, double(cfg.imageSize) * cfg.imageSize));
    std::printf("exact reference: %.2f s; mean alpha %.4f; max |visible + uncovered − 1| per pixel %.2e; "
                "nearest triangle's visible area vs its area (%.2f px²) %.2e; at most %zu uncovered pieces in a pixel\n",
                rs.seconds, meanAlpha, rs.maxCoverageDefect, rs.frontArea, rs.maxFrontAreaDefect, rs.maxPieces);

    std::vector<Row> rows;
    std::vector<float> rgba;
    for (int eaa = 3; eaa >= 0; --eaa) {
        EasRenderer eas(scene, eaa, cfg.tileSize);
        Row r{"EAS", std::string(levelName(eaa)) + " (eaa " + std::to_string(eaa) + ", " +
                         std::to_string(eas.pattern.count) + " sub-samples)",
              0, eaa, {}, {}};
        r.time = timeRuns(cfg.runs, [&] { eas.render(rgba); });
        r.error = imageError(ref, rgba);
        rows.push_back(r);
    }

    EmbreeScene embree;
    const Timing build = timeRuns(cfg.runs, [&] { embree.build(scene); });
    PointSampler sampler{scene, embree.scene, cfg.seed * 0x51ED27ull + 7};
    for (int packet = cfg.singleRays ? 0 : 1; packet < 2; ++packet)
        for (int k = 1; k <= 16; k *= 2) {
            Row r{packet ? "Embree points, 16-ray packets" : "Embree points, single rays",
                  std::to_string(k * k) + " spp", k * k, -1, {}, {}};
            r.time = timeRuns(cfg.runs, [&] {
                if (packet)
                    sampler.renderPacket16(k, rgba);
                else
                    sampler.renderSingle(k, rgba);
            });
            r.error = imageError(ref, rgba);
            rows.push_back(r);
        }

    // The baseline is the faster Embree tracer at 256 samples per pixel (CPU time).
    const Row* base = nullptr;
    for (const Row& r : rows)
        if (r.samples == 256 && (!base || r.time.cpuMs < base->time.cpuMs)) base = &r;
    std::printf("Embree BVH build (one thread, median): %.2f ms CPU, %.2f ms wall — not included below\n",
                build.cpuMs, build.wallMs);
    std::printf("baseline: %s, 256 spp\n\n", base->method.c_str());
    std::printf("| method | samples / level | CPU ms (median) | wall ms (median) | mean abs err RGBA | "
                "mean abs err α | max abs err | CPU time / baseline |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const Row& r : rows)
        std::printf("| %s | %s | %.1f | %.1f | %.5f | %.5f | %.4f | %.4f |\n", r.method.c_str(), r.setting.c_str(),
                    r.time.cpuMs, r.time.wallMs, r.error.mean, r.error.meanAlpha, r.error.max,
                    r.time.cpuMs / base->time.cpuMs);

    // Goal: an EAS level with mean error ≤ the baseline's, in ≤ 1/4 of its time.
    std::printf("\nGoal (EAS reaches the mean error of 256-spp point sampling in at most a quarter of its "
                "time, single-threaded CPU time):\n");
    std::vector<int> meeting;
    for (const Row& r : rows) {
        if (r.eaa < 0) continue;
        const bool errOk = r.error.mean <= base->error.mean;
        const double ratio = r.time.cpuMs / base->time.cpuMs;
        const bool timeOk = ratio <= 0.25;
        // The fewest point samples (same tracer as the baseline) that match this level's error.
        const Row* match = nullptr;
        for (const Row& p : rows)
            if (p.method == base->method && p.error.mean <= r.error.mean && (!match || p.samples < match->samples))
                match = &p;
        std::printf("- EAS %s: error %.5f %s %.5f, time ratio %.3f %s 0.25 -> %s", levelName(r.eaa), r.error.mean,
                    errOk ? "<=" : ">", base->error.mean, ratio, timeOk ? "<=" : ">",
                    errOk && timeOk ? "meets the goal" : "does not meet the goal");
        if (match)
            std::printf("; point sampling needs %d spp for this error (%.1f ms CPU, %.2f× the EAS time)\n",
                        match->samples, match->time.cpuMs, match->time.cpuMs / r.time.cpuMs);
        else
            std::printf("; no point-sampling count up to 256 spp reaches this error\n");
        if (errOk && timeOk) meeting.push_back(r.eaa);
    }
    std::string list;
    for (int eaa : meeting) list += std::string(list.empty() ? "" : ", ") + levelName(eaa);
    std::printf("Goal on this scene: %s%s\n", meeting.empty() ? "NOT met by any EAS level" : "met by EAS ", list.c_str());
    return meeting;
}

// ---------------------------------------------------------------------------------------------
// Micro-benchmarks

std::vector<std::unique_ptr<ThroughputScene>> g_scenes;

void rasterizeAll(TileRasterizer& r, const ThroughputScene& s) {
    r.reset(s.region);
    for (const ScreenTriangle& t : s.tris) r.add(t);
    r.finish();
}

uint64_t countFragments(const TileRasterizer& r, const PixelRect& region) {
    uint64_t n = 0;
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) n += r.fragments(x, y).size();
    return n;
}

// TileRasterizer::reset + add (every triangle) + finish over the whole 512×512 region.
void BM_Rasterize(benchmark::State& state, const ThroughputScene* s, int eaa) {
    const SubsamplePattern pattern = SubsamplePattern::forEdgeAntiAliasing(eaa);
    TileRasterizer r(pattern);
    rasterizeAll(r, *s);  // grows the buffers once, as a renderer's reused rasterizer would have
    const uint64_t fragments = countFragments(r, s->region);
    for (auto _ : state) {
        rasterizeAll(r, *s);
        benchmark::ClobberMemory();
    }
    const double it = double(state.iterations());
    state.counters["triangles/s"] = benchmark::Counter(it * double(s->tris.size()), benchmark::Counter::kIsRate);
    state.counters["fragments/s"] = benchmark::Counter(it * double(fragments), benchmark::Counter::kIsRate);
    state.counters["fragments"] = double(fragments);
    state.counters["depthComplexity"] = depthComplexity(s->tris, double(s->region.width()) * s->region.height());
}

// PixelResolver::resolve for every pixel of the region (fragments rasterized beforehand).
void BM_Resolve(benchmark::State& state, const ThroughputScene* s, int eaa) {
    const SubsamplePattern pattern = SubsamplePattern::forEdgeAntiAliasing(eaa);
    TileRasterizer r(pattern);
    rasterizeAll(r, *s);
    const std::vector<ObjectTopology> topology = s->topology();
    PixelResolver resolver(pattern, topology);
    uint64_t fragments = 0, pixels = 0, surfaces = 0;
    for (int y = s->region.y0; y < s->region.y1; ++y)
        for (int x = s->region.x0; x < s->region.x1; ++x) {
            const auto f = r.fragments(x, y);
            if (f.empty()) continue;
            fragments += f.size();
            ++pixels;
            resolver.resolve(f);
            surfaces += resolver.groups().size();
        }
    for (auto _ : state) {
        for (int y = s->region.y0; y < s->region.y1; ++y)
            for (int x = s->region.x0; x < s->region.x1; ++x) {
                const auto f = r.fragments(x, y);
                if (f.empty()) continue;
                resolver.resolve(f);
                benchmark::DoNotOptimize(resolver.groups().data());
            }
    }
    const double it = double(state.iterations());
    state.counters["fragments/s"] = benchmark::Counter(it * double(fragments), benchmark::Counter::kIsRate);
    state.counters["pixels/s"] = benchmark::Counter(it * double(pixels), benchmark::Counter::kIsRate);
    state.counters["surfaces/pixel"] = pixels ? double(surfaces) / double(pixels) : 0.0;
}

void registerMicroBenchmarks(bool quick) {
    constexpr int kRegion = 512;
    g_scenes.push_back(std::make_unique<ThroughputScene>(randomThroughputScene(10000, kRegion, 11)));
    if (!quick) {
        g_scenes.push_back(std::make_unique<ThroughputScene>(randomThroughputScene(100000, kRegion, 12)));
        g_scenes.push_back(std::make_unique<ThroughputScene>(meshThroughputScene(224, kRegion, 13)));
    }
    for (const auto& s : g_scenes)
        for (int eaa = 3; eaa >= 0; --eaa) {
            const std::string suffix = "/" + s->name + "/eaa" + std::to_string(eaa);
            benchmark::RegisterBenchmark(("Rasterize" + suffix).c_str(), BM_Rasterize, s.get(), eaa)
                ->Unit(benchmark::kMillisecond)
                ->MinTime(0.2);
            benchmark::RegisterBenchmark(("Resolve" + suffix).c_str(), BM_Resolve, s.get(), eaa)
                ->Unit(benchmark::kMillisecond)
                ->MinTime(0.2);
        }
}

std::vector<int> parseCounts(const char* s) {
    std::vector<int> v;
    for (const char* p = s; *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p) break;
        if (n > 0) v.push_back(int(n));
        p = *end == ',' ? end + 1 : end;
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    Config cfg;
    bool quick = false;
    std::vector<char*> rest{argv[0]};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--table") {
            cfg.table = true;
            cfg.micro = false;
        } else if (a == "--micro") {
            cfg.table = false;
            cfg.micro = true;
        } else if (a == "--single-rays") {
            cfg.singleRays = true;
        } else if (a == "--quick") {
            quick = true;
        } else if (a == "--runs" && i + 1 < argc) {
            cfg.runs = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--triangles" && i + 1 < argc) {
            cfg.triangleCounts = parseCounts(argv[++i]);
        } else if (a == "--size" && i + 1 < argc) {
            cfg.imageSize = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--tile" && i + 1 < argc) {
            cfg.tileSize = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--seed" && i + 1 < argc) {
            cfg.seed = std::strtoull(argv[++i], nullptr, 10);
        } else if (a == "--help" || a == "-h") {
            std::printf("usage: visibility_bench [--table | --micro] [--quick] [--runs N] [--triangles N[,N...]]\n"
                        "                        [--size S] [--tile T] [--seed S] [--single-rays] [--benchmark_* ...]\n"
                        "  --table        only the error-against-time table\n"
                        "  --micro        only the Google Benchmark throughput runs\n"
                        "  --quick        smaller: 1 run, 2000 triangles in 128×128, only the 10k micro scene\n"
                        "  --runs N       timed runs per table method (median shown; default 3)\n"
                        "  --triangles    triangle counts of the error scenes (default 2000,20000)\n"
                        "  --size S       error scene is S×S pixels (default 256)\n"
                        "  --tile T       EAS tile size in the table (default 64)\n"
                        "  --single-rays  also trace with rtcIntersect1 (16-ray packets always run)\n");
            return 0;
        } else {
            rest.push_back(argv[i]);
        }
    }
    if (quick) {
        cfg.runs = 1;
        cfg.triangleCounts = {2000};
        cfg.imageSize = 128;
    }
    if (cfg.table && cfg.triangleCounts.empty()) {
        std::fprintf(stderr, "visibility_bench: --triangles needs at least one positive count\n");
        return 2;
    }
    if (cfg.table) {
        std::printf("All timings are single-threaded (EAS on the calling thread; Embree device with "
                    "threads=1, rays traced by the calling thread). Tile size %d, %d run(s) per method.\n",
                    cfg.tileSize, cfg.runs);
        std::vector<int> everywhere = {3, 2, 1, 0};  // levels meeting the goal on every scene
        for (int n : cfg.triangleCounts) {
            const std::vector<int> met = runTable(cfg, n);
            std::erase_if(everywhere, [&](int eaa) { return std::find(met.begin(), met.end(), eaa) == met.end(); });
        }
        std::string list;
        for (int eaa : everywhere) list += std::string(list.empty() ? "" : ", ") + levelName(eaa);
        std::printf("\nGoal over all %zu scene(s): %s%s\n", cfg.triangleCounts.size(),
                    everywhere.empty() ? "NOT met by any EAS level on every scene" : "met on every scene by EAS ",
                    list.c_str());
    }
    if (cfg.micro) {
        registerMicroBenchmarks(quick);
        int n = int(rest.size());
        benchmark::Initialize(&n, rest.data());
        std::printf("\n");
        benchmark::RunSpecifiedBenchmarks();
        benchmark::Shutdown();
        g_scenes.clear();
    }
    return 0;
}
