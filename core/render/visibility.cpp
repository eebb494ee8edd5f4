// core/render/visibility.cpp: Exact Area Sampling rasterization, per-pixel hidden-surface
// resolution and compositing (reference/algorithms.md §2: Carpenter's A-buffer with exact areas).
#include "core/render/visibility.h"

#include "core/util/counting_sort.h"
#include "core/util/release.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

namespace pushpin::render {

namespace {
template <class T>
uint64_t capacityBytes(const std::vector<T>& v) {
    return uint64_t(v.capacity()) * sizeof(T);
}
}  // namespace

uint64_t TileRasterizer::bytes() const {
    return m_fragments.bytes() + capacityBytes(m_pixelStart) + capacityBytes(m_pixelFill) + capacityBytes(m_rowStart) +
           capacityBytes(m_columnStart);
}

void TileRasterizer::releaseMemory() {
    m_fragments.release();
    util::release(m_pixelStart);
    util::release(m_pixelFill);
    util::release(m_rowStart);
    util::release(m_columnStart);
    m_region = {};
}

void PixelResolver::releaseMemory() {
    util::release(m_groups);
    util::release(m_members);
    util::release(m_parent);
    util::release(m_triangleTable);
    util::release(m_visible);
    util::release(m_sorted);
    util::release(m_order);
    util::release(m_far);
    util::release(m_groupFar);
    util::release(m_groupArea);
}

uint64_t PixelResolver::bytes() const {
    return capacityBytes(m_groups) + capacityBytes(m_members) + capacityBytes(m_parent) + capacityBytes(m_triangleTable) + capacityBytes(m_visible) +
           capacityBytes(m_sorted) + capacityBytes(m_order) + capacityBytes(m_far) + capacityBytes(m_groupFar) +
           capacityBytes(m_groupArea);
}

namespace {

constexpr double kMinFragmentArea = 1e-12;     // pixels²; smaller clipped areas are dropped
constexpr double kFullPixelArea = 1.0 - 1e-6;  // a group at least this large covers the pixel
constexpr float kDepthRelEpsilon = 1e-5f;      // "nearer" for sliver tests, relative to |depth|
// How far behind an occluding depth a surface must start to be skipped, relative to |depth|:
// far more than the float rounding of a fragment's depth plane and than kDepthRelEpsilon.
constexpr double kOcclusionMargin = 1e-3;
constexpr float kInf = std::numeric_limits<float>::infinity();

// Sub-sample centres, pixel-local (exact in binary: odd multiples of 1/16).
struct SubsampleCentres {
    double coord[kSubsampleGrid];   // (i + 0.5) / 8
    float u[kSubsampleCount], v[kSubsampleCount];
    constexpr SubsampleCentres() : coord{}, u{}, v{} {
        for (int i = 0; i < kSubsampleGrid; ++i) coord[i] = (i + 0.5) / kSubsampleGrid;
        for (int b = 0; b < kSubsampleCount; ++b) {
            u[b] = float(coord[b % kSubsampleGrid]);
            v[b] = float(coord[b / kSubsampleGrid]);
        }
    }
};
constexpr SubsampleCentres kCentre;

inline int lowestBit(uint64_t m) { return std::countr_zero(m); }

// NaN compares as +inf so that every depth comparison is a total order.
inline float depthKey(float z) { return z == z ? z : kInf; }

inline bool nearerBy(float a, float b) {  // a nearer than b beyond a small relative epsilon
    const float eps = kDepthRelEpsilon * std::max(std::fabs(a), std::fabs(b));
    return a < b - eps;
}

inline float toFloat(double d) {
    if (!(d == d)) return 0.0f;
    return float(std::clamp(d, -double(FLT_MAX), double(FLT_MAX)));
}

inline float clamp01(float t) { return t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f; }

inline uint32_t floatBits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// A total order on fragments: (object, triangle) first, the remaining fields only to make exact
// duplicates and caller-made oddities sort the same way whatever the input order.
bool fragmentLess(const Fragment& a, const Fragment& b) {
    if (a.object != b.object) return a.object < b.object;
    if (a.triangle != b.triangle) return a.triangle < b.triangle;
    if (a.flags != b.flags) return a.flags < b.flags;
    if (a.mask != b.mask) return a.mask < b.mask;
    const float fa[6] = {a.area, a.cu, a.cv, a.z0, a.dzdu, a.dzdv};
    const float fb[6] = {b.area, b.cu, b.cv, b.z0, b.dzdu, b.dzdv};
    for (int i = 0; i < 6; ++i) {
        if (floatBits(fa[i]) != floatBits(fb[i])) return floatBits(fa[i]) < floatBits(fb[i]);
    }
    return false;
}

// The active sub-sample nearest a pixel-local point (ties: the lower bit).
int nearestActiveBit(uint64_t active, float cu, float cv) {
    int best = -1;
    float bestD = kInf;
    for (uint64_t m = active; m; m &= m - 1) {
        const int b = lowestBit(m);
        const float du = kCentre.u[b] - cu, dv = kCentre.v[b] - cv;
        const float d = du * du + dv * dv;
        if (best < 0 || d < bestD) {
            best = b;
            bestD = d;
        }
    }
    return best < 0 ? 0 : best;
}

// One triangle edge as E(p) = a·(p.x − ox) + b·(p.y − oy), positive inside. The origin is the
// lexicographically smaller endpoint, so the two triangles that share an edge compute exactly
// negated values at every point (IEEE rounding is symmetric): a sub-sample centre on or next to
// the edge is inside exactly one of them, given the top-left tie rule.
struct Edge {
    double a = 0, b = 0, ox = 0, oy = 0;
    bool topLeft = false;  // owns points with E == 0: gradient points right, or straight down
};

Edge makeEdge(double px, double py, double qx, double qy) {
    Edge e;
    const bool forward = px < qx || (px == qx && py < qy);
    const double ox = forward ? px : qx, oy = forward ? py : qy;
    const double dx = forward ? qx - px : px - qx, dy = forward ? qy - py : py - qy;
    // For the edge p→q, E = cross(q − p, point − p) = (q−p).x·(y − p.y) − (q−p).y·(x − p.x).
    e.a = forward ? -dy : dy;
    e.b = forward ? dx : -dx;
    e.ox = ox;
    e.oy = oy;
    e.topLeft = e.a > 0 || (e.a == 0 && e.b > 0);
    return e;
}

// Sutherland–Hodgman: the pixel square clipped by the triangle's half-planes, in pixel-local
// coordinates. Clipping the square (rather than the triangle) keeps every vertex inside [0,1]²,
// which stays accurate for triangles much larger than a pixel.
struct ClipPolygon {
    static constexpr int kMax = 8;  // 4 corners + one vertex per clipping edge
    double u[kMax], v[kMax];
    int n = 0;
};

void clipByEdge(const ClipPolygon& in, ClipPolygon& out, double e00, double a, double b) {
    out.n = 0;
    if (in.n == 0) return;
    double e[ClipPolygon::kMax];
    for (int i = 0; i < in.n; ++i) e[i] = e00 + a * in.u[i] + b * in.v[i];
    for (int i = 0; i < in.n; ++i) {
        const int j = i + 1 == in.n ? 0 : i + 1;
        const bool inI = e[i] >= 0, inJ = e[j] >= 0;
        if (inI && out.n < ClipPolygon::kMax) {
            out.u[out.n] = in.u[i];
            out.v[out.n] = in.v[i];
            ++out.n;
        }
        if (inI != inJ && out.n < ClipPolygon::kMax) {
            const double t = e[i] / (e[i] - e[j]);
            out.u[out.n] = in.u[i] + t * (in.u[j] - in.u[i]);
            out.v[out.n] = in.v[i] + t * (in.v[j] - in.v[i]);
            ++out.n;
        }
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// TileRasterizer

TileRasterizer::TileRasterizer(const SubsamplePattern& pattern) : m_pattern(pattern) {}

void TileRasterizer::reserveFragments(size_t fragments) {
    if (fragments <= m_fragments.capacity()) return;
    // The pages grow in place, so the growth is all a budget is told, and a step of half the
    // capacity keeps the calls few without leaving much spare.
    const size_t capacity = std::max(fragments, m_fragments.capacity() + m_fragments.capacity() / 2);
    if (m_growHook) m_growHook(util::PageArray<Fragment>::bytesFor(capacity) - m_fragments.bytes());
    m_fragments.reserve(capacity);
}

void TileRasterizer::reset(const PixelRect& region) {
    m_region = region;
    m_fragments.clear();
    m_pixelStart.clear();
}

void TileRasterizer::add(const ScreenTriangle& tri) {
    double x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        x[i] = tri.x[i];
        y[i] = tri.y[i];
        z[i] = tri.z[i];
        if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) {
            ++m_stats.trianglesDegenerate;
            return;
        }
    }
    double area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (!std::isfinite(area2) || area2 == 0.0) {
        ++m_stats.trianglesDegenerate;
        return;
    }
    if (area2 < 0) {  // normalise the winding so that the inside is where all edge functions are ≥ 0
        std::swap(x[1], x[2]);
        std::swap(y[1], y[2]);
        std::swap(z[1], z[2]);
        area2 = -area2;
    }
    // Depth plane z = z[0] + dzdx·(x − x[0]) + dzdy·(y − y[0]) (Cramer's rule on the two edges).
    const double dzdx = ((z[1] - z[0]) * (y[2] - y[0]) - (z[2] - z[0]) * (y[1] - y[0])) / area2;
    const double dzdy = ((x[1] - x[0]) * (z[2] - z[0]) - (x[2] - x[0]) * (z[1] - z[0])) / area2;
    if (!std::isfinite(dzdx) || !std::isfinite(dzdy)) {
        ++m_stats.trianglesDegenerate;
        return;
    }

    // Pixel bounds, clamped in double before converting so huge coordinates cannot overflow.
    const double minX = std::min({x[0], x[1], x[2]}), maxX = std::max({x[0], x[1], x[2]});
    const double minY = std::min({y[0], y[1], y[2]}), maxY = std::max({y[0], y[1], y[2]});
    const double lx = std::max(double(m_region.x0), std::floor(minX));
    const double hx = std::min(double(m_region.x1), std::ceil(maxX));
    const double ly = std::max(double(m_region.y0), std::floor(minY));
    const double hy = std::min(double(m_region.y1), std::ceil(maxY));
    if (!(lx < hx) || !(ly < hy)) return;
    const int bx0 = int(lx), bx1 = int(hx), by0 = int(ly), by1 = int(hy);

    const Edge edge[3] = {makeEdge(x[0], y[0], x[1], y[1]), makeEdge(x[1], y[1], x[2], y[2]),
                          makeEdge(x[2], y[2], x[0], y[0])};
    const uint64_t active = m_pattern.active;
    const bool manyBits = m_pattern.count > 8;
    const float fdzdu = toFloat(dzdx), fdzdv = toFloat(dzdy);
    const uint32_t flags = tri.transparent ? kFragmentTransparent : 0u;
    const int regionWidth = m_region.width();
    const size_t before = m_fragments.size();
    reserveFragments(before + size_t(bx1 - bx0) * size_t(by1 - by0));

    for (int py = by0; py < by1; ++py) {
        // Every value of a fragment is a fixed expression of its pixel's coordinates and the
        // triangle (never stepped from the region's first pixel), so a pixel's fragments are the
        // same bits whatever tile or region rendered them.
        for (int px = bx0; px < bx1; ++px) {
            bool outside = false, full = true;
            double e00[3];
            int crossing[3], nCrossing = 0;
            for (int k = 0; k < 3; ++k) {
                const double c00 = edge[k].a * (px - edge[k].ox) + edge[k].b * (py - edge[k].oy);
                const double c10 = edge[k].a * (px + 1 - edge[k].ox) + edge[k].b * (py - edge[k].oy);
                const double c01 = edge[k].a * (px - edge[k].ox) + edge[k].b * (py + 1 - edge[k].oy);
                const double c11 = edge[k].a * (px + 1 - edge[k].ox) + edge[k].b * (py + 1 - edge[k].oy);
                e00[k] = c00;
                const double lo = std::min(std::min(c00, c10), std::min(c01, c11));
                const double hi = std::max(std::max(c00, c10), std::max(c01, c11));
                if (hi <= 0) outside = true;
                if (lo < 0) {
                    full = false;
                    crossing[nCrossing++] = k;
                }
            }
            if (outside) continue;

            Fragment f;
            f.object = tri.object;
            f.triangle = tri.triangle;
            f.flags = flags;
            f.dzdu = fdzdu;
            f.dzdv = fdzdv;
            f.z0 = toFloat(z[0] + dzdx * (px - x[0]) + dzdy * (py - y[0]));
            if (full) {
                f.mask = active;
                f.area = 1.0f;
                f.cu = f.cv = 0.5f;
            } else {
                // Exact area and centroid of the pixel square clipped by the crossing edges.
                ClipPolygon poly[2];
                poly[0].n = 4;
                poly[0].u[0] = 0; poly[0].v[0] = 0;
                poly[0].u[1] = 1; poly[0].v[1] = 0;
                poly[0].u[2] = 1; poly[0].v[2] = 1;
                poly[0].u[3] = 0; poly[0].v[3] = 1;
                int cur = 0;
                for (int c = 0; c < nCrossing; ++c) {
                    const int k = crossing[c];
                    clipByEdge(poly[cur], poly[cur ^ 1], e00[k], edge[k].a, edge[k].b);
                    cur ^= 1;
                }
                const ClipPolygon& p = poly[cur];
                double a2 = 0, cx = 0, cy = 0;
                for (int i = 0; i < p.n; ++i) {
                    const int j = i + 1 == p.n ? 0 : i + 1;
                    const double cr = p.u[i] * p.v[j] - p.u[j] * p.v[i];
                    a2 += cr;
                    cx += (p.u[i] + p.u[j]) * cr;
                    cy += (p.v[i] + p.v[j]) * cr;
                }
                const double area = 0.5 * a2;
                if (!(area > kMinFragmentArea)) continue;
                f.area = float(std::min(area, 1.0));
                f.cu = float(std::clamp(cx / (3.0 * a2), 0.0, 1.0));
                f.cv = float(std::clamp(cy / (3.0 * a2), 0.0, 1.0));

                // Mask: sub-sample centres inside every crossing edge (top-left rule on E == 0).
                // Each value is a fixed expression of the pixel, the centre and the edge's canonical
                // coefficients, so neighbouring triangles see exactly negated values.
                uint64_t mask = active;
                for (int c = 0; c < nCrossing && mask; ++c) {
                    const Edge& e = edge[crossing[c]];
                    const double dx0 = double(px) - e.ox, dy0 = double(py) - e.oy;
                    if (manyBits) {
                        // All 64 centres, row by row, without branches (same values as below).
                        double ax[kSubsampleGrid];
                        for (int i = 0; i < kSubsampleGrid; ++i) ax[i] = e.a * (dx0 + kCentre.coord[i]);
                        uint64_t inside = 0;
                        for (int j = 0; j < kSubsampleGrid; ++j) {
                            const double by = e.b * (dy0 + kCentre.coord[j]);
                            unsigned row = 0;
                            if (e.topLeft) {
                                for (int i = 0; i < kSubsampleGrid; ++i) row |= unsigned(ax[i] + by >= 0) << i;
                            } else {
                                for (int i = 0; i < kSubsampleGrid; ++i) row |= unsigned(ax[i] + by > 0) << i;
                            }
                            inside |= uint64_t(row) << (kSubsampleGrid * j);
                        }
                        mask &= inside;
                    } else {
                        for (uint64_t m = mask; m; m &= m - 1) {
                            const int b = lowestBit(m);
                            const double ev = e.a * (dx0 + kCentre.coord[b % kSubsampleGrid]) +
                                              e.b * (dy0 + kCentre.coord[b / kSubsampleGrid]);
                            if (ev < 0 || (ev == 0 && !e.topLeft)) mask &= ~(uint64_t(1) << b);
                        }
                    }
                }
                f.mask = mask;
            }
            f.pixel = uint32_t((py - m_region.y0) * regionWidth + (px - m_region.x0));
            m_fragments.pushWithinCapacity(f);
        }
    }
    const size_t added = m_fragments.size() - before;
    if (added > 0) {
        ++m_stats.trianglesRasterized;
        m_stats.fragments += added;
    }
}

void TileRasterizer::finish() {
    const size_t width = size_t(m_region.width()), rows = size_t(m_region.height()), pixels = width * rows;
    if (m_growHook) {
        auto growth = [](const std::vector<uint32_t>& v, size_t n) {
            return n > v.capacity() ? uint64_t(n) * sizeof(uint32_t) : 0;
        };
        const uint64_t more = growth(m_pixelStart, pixels + 1) + growth(m_pixelFill, std::max(width, rows)) +
                              growth(m_rowStart, rows + 1) + growth(m_columnStart, width + 1);
        if (more > 0) m_growHook(more);
    }
    m_pixelStart.assign(pixels + 1, 0);
    if (pixels > 0) {
        // By row first, then each row by column: each pass files into a few places at a time, which
        // stay in the caches, where filing straight by pixel would scatter over the whole tile.
        const uint32_t w = uint32_t(width);
        util::fileByKeyInPlace(rows, m_fragments, [w](const Fragment& f) { return f.pixel / w; }, m_rowStart, m_pixelFill);
        for (size_t r = 0; r < rows; ++r) {
            std::span<Fragment> row(m_fragments.data() + m_rowStart[r], m_rowStart[r + 1] - m_rowStart[r]);
            util::fileByKeyInPlace(width, row, [w](const Fragment& f) { return f.pixel % w; }, m_columnStart, m_pixelFill);
            for (size_t c = 0; c < width; ++c) m_pixelStart[r * width + c] = m_rowStart[r] + m_columnStart[c];
        }
    }
    m_pixelStart[pixels] = uint32_t(m_fragments.size());
}

std::span<const Fragment> TileRasterizer::sortedFragments() const {
    if (!finished()) return {};
    return std::span<const Fragment>(m_fragments.data(), m_fragments.size());
}

std::span<const Fragment> TileRasterizer::fragments(int x, int y) const {
    const size_t pixels = size_t(m_region.width()) * size_t(m_region.height());
    if (!m_region.contains(x, y) || m_pixelStart.size() != pixels + 1 || !finished()) return {};
    const size_t p = size_t(y - m_region.y0) * size_t(m_region.width()) + size_t(x - m_region.x0);
    return std::span<const Fragment>(m_fragments.data() + m_pixelStart[p], m_pixelStart[p + 1] - m_pixelStart[p]);
}

void TileRasterizer::reorderPixel(int x, int y, std::span<const Fragment> reordered) {
    const std::span<const Fragment> at = fragments(x, y);
    if (at.size() != reordered.size())
        throw std::invalid_argument("TileRasterizer::reorderPixel: not the pixel's fragment count");
    std::copy(reordered.begin(), reordered.end(), m_fragments.data() + (at.data() - m_fragments.data()));
}

// ---------------------------------------------------------------------------------------------
// PixelResolver

PixelResolver::PixelResolver(const SubsamplePattern& pattern, std::span<const ObjectTopology> topology)
    : m_pattern(pattern), m_topology(topology), m_nearestDepth(kInf) {}

namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

void unite(std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
    a = findRoot(parent, a);
    b = findRoot(parent, b);
    if (a == b) return;
    if (a < b) parent[b] = a;  // the smallest index is the root: groups numbered by first member
    else parent[a] = b;
}


// Whether a triangle whose neighbour entries are `nb` (null: none at hand) names triangle `b` as a
// neighbour across a soft edge.
bool namesSoftNeighbour(const uint32_t* nb, uint32_t b) {
    if (!nb) return false;
    return (!(nb[0] & kHardEdgeBit) && nb[0] == b) || (!(nb[1] & kHardEdgeBit) && nb[1] == b) ||
           (!(nb[2] & kHardEdgeBit) && nb[2] == b);
}

// Joins the fragments of one object whose triangles are the same or soft-edge neighbours (either
// naming the other). `sorted` says whether F is in fragmentLess order; unsorted input is joined
// pair by pair (meant for a few fragments). Sorted input is taken one object's run at a time: a
// short run pair by pair; in a long one the fragments of one triangle are joined in a row, and
// each triangle's soft neighbours are looked up in a hash table of the run's triangles (`table`,
// scratch), each giving the first fragment of its triangle. The partition is the same either way
// (the fragments of a triangle are joined already); unite() makes the smallest index each group's
// root, so the groups do not depend on the order of the joins.
void joinSoftNeighbours(std::span<const Fragment> F, bool sorted, std::span<const ObjectTopology> topology,
                        std::vector<uint32_t>& parent, std::vector<uint64_t>& table) {
    static const ObjectTopology kNoTopology{};
    auto topologyOf = [&](uint32_t object) -> const ObjectTopology& {
        return object < topology.size() ? topology[object] : kNoTopology;
    };
    // Each fragment's neighbour entries are looked up once (an object in pieces finds them by two
    // binary searches), then every pair is compared.
    constexpr size_t kMostPairwise = 16;
    auto pairwise = [&](size_t a, size_t b, bool sameObject) {
        std::array<const uint32_t*, kMostPairwise> nb;
        for (size_t i = a; i < b; ++i) nb[i - a] = topologyOf(F[i].object).neighborsOf(F[i].triangle);
        for (size_t i = a; i < b; ++i)
            for (size_t j = i + 1; j < b; ++j)
                if ((sameObject || F[i].object == F[j].object) &&
                    (F[i].triangle == F[j].triangle || namesSoftNeighbour(nb[i - a], F[j].triangle) ||
                     namesSoftNeighbour(nb[j - a], F[i].triangle)))
                    unite(parent, uint32_t(i), uint32_t(j));
    };
    if (!sorted) {
        if (F.size() > kMostPairwise) throw std::logic_error("joinSoftNeighbours: too many unsorted fragments");
        pairwise(0, F.size(), false);
        return;
    }
    constexpr size_t kPairwiseRun = 8;
    static_assert(kPairwiseRun <= kMostPairwise);
    constexpr uint64_t kEmpty = ~uint64_t(0);  // no triangle id is 2^32 − 1 (kNoTriangle)
    for (size_t a = 0, b = 0; a < F.size(); a = b) {
        const uint32_t object = F[a].object;
        b = a + 1;
        while (b < F.size() && F[b].object == object) ++b;
        if (b - a <= kPairwiseRun) {
            pairwise(a, b, true);
            continue;
        }
        // Open addressing, at most half full: triangle << 32 | its first fragment.
        int bits = 4;
        while ((size_t(1) << bits) < 2 * (b - a)) ++bits;
        const size_t mask = (size_t(1) << bits) - 1;
        auto home = [&](uint32_t t) { return size_t((uint64_t(t) * 0x9e3779b97f4a7c15ull) >> (64 - bits)); };
        table.assign(mask + 1, kEmpty);
        for (size_t i = a; i < b; ++i) {
            if (i > a && F[i - 1].triangle == F[i].triangle) {
                unite(parent, uint32_t(i - 1), uint32_t(i));
                continue;
            }
            size_t h = home(F[i].triangle);
            while (table[h] != kEmpty) h = (h + 1) & mask;
            table[h] = uint64_t(F[i].triangle) << 32 | uint32_t(i);
        }
        const ObjectTopology& topo = topologyOf(object);
        for (size_t i = a; i < b; ++i) {
            if (i > a && F[i - 1].triangle == F[i].triangle) continue;
            const uint32_t* neighbors = topo.neighborsOf(F[i].triangle);
            if (!neighbors) continue;
            for (int k = 0; k < 3; ++k) {
                const uint32_t nb = neighbors[k];
                if (nb & kHardEdgeBit) continue;  // hard edge, or kNoTriangle
                for (size_t h = home(nb); table[h] != kEmpty; h = (h + 1) & mask)
                    if (uint32_t(table[h] >> 32) == nb) {
                        unite(parent, uint32_t(i), uint32_t(table[h]));
                        break;
                    }
            }
        }
    }
}
}  // namespace

void PixelResolver::resolve(std::span<const Fragment> input) {
    m_groups.clear();
    m_members.clear();
    m_nearestDepth = kInf;
    m_opaqueCoverage = 0.0f;
    const size_t n = input.size();
    if (n == 0) return;
    ++m_stats.pixels;
    const uint64_t active = m_pattern.active;

    // Canonical order, so nothing below depends on the order of the input; sanitise caller data.
    m_sorted.assign(input.begin(), input.end());
    for (Fragment& f : m_sorted) {
        f.mask &= active;
        f.area = (f.area > 0.0f && f.area <= FLT_MAX) ? f.area : 0.0f;
        f.cu = f.cu == f.cu ? std::clamp(f.cu, 0.0f, 1.0f) : 0.5f;
        f.cv = f.cv == f.cv ? std::clamp(f.cv, 0.0f, 1.0f) : 0.5f;
    }
    std::sort(m_sorted.begin(), m_sorted.end(), fragmentLess);
    const std::vector<Fragment>& F = m_sorted;

    // a. Opaque visibility per sub-sample: nearest opaque fragment; ties go to the one met first,
    //    which in the canonical order is the smaller object, then the smaller triangle.
    int winner[kSubsampleCount];
    float winDepth[kSubsampleCount];
    std::fill(std::begin(winner), std::end(winner), -1);
    std::fill(std::begin(winDepth), std::end(winDepth), kInf);
    for (size_t i = 0; i < n; ++i) {
        const Fragment& f = F[i];
        if (f.flags & kFragmentTransparent) continue;
        for (uint64_t m = f.mask; m; m &= m - 1) {
            const int b = lowestBit(m);
            const float d = depthKey(f.depthAt(kCentre.u[b], kCentre.v[b]));
            if (winner[b] < 0 || d < winDepth[b]) {
                winner[b] = int(i);
                winDepth[b] = d;
            }
        }
    }
    m_visible.assign(n, 0);
    for (int b = 0; b < kSubsampleCount; ++b) {
        if (winner[b] >= 0) m_visible[size_t(winner[b])] |= uint64_t(1) << b;
    }
    for (size_t i = 0; i < n; ++i) {
        const Fragment& f = F[i];
        if (!(f.flags & kFragmentTransparent)) continue;
        uint64_t vis = 0;
        for (uint64_t m = f.mask; m; m &= m - 1) {
            const int b = lowestBit(m);
            const float d = depthKey(f.depthAt(kCentre.u[b], kCentre.v[b]));
            bool seen = winner[b] < 0 || d < winDepth[b];
            if (!seen && d == winDepth[b]) {  // same tie-break as between opaque fragments
                const Fragment& w = F[size_t(winner[b])];
                seen = f.object != w.object ? f.object < w.object : f.triangle < w.triangle;
            }
            if (seen) vis |= uint64_t(1) << b;
        }
        m_visible[i] = vis;
    }

    // b. Surface groups: union–find over soft-edge neighbours of one object (and duplicates).
    m_parent.resize(n);
    for (size_t i = 0; i < n; ++i) m_parent[i] = uint32_t(i);
    joinSoftNeighbours(F, true, m_topology, m_parent, m_triangleTable);
    // Replace roots by group ids numbered in order of first member (roots are the smallest index).
    uint32_t groupCount = 0;
    for (size_t i = 0; i < n; ++i) m_parent[i] = findRoot(m_parent, uint32_t(i));
    for (size_t i = 0; i < n; ++i) {
        m_parent[i] = m_parent[i] == i ? groupCount++ : m_parent[m_parent[i]];
    }
    std::vector<uint32_t>& groupOf = m_parent;
    m_stats.surfaces += groupCount;
    m_stats.mergedFragments += n - groupCount;

    // Member lists: fragment indices grouped by group, ascending within a group.
    m_groups.resize(groupCount);
    for (uint32_t i = 0; i < n; ++i) ++m_groups[groupOf[i]].memberCount;
    uint32_t begin = 0;
    for (SurfaceGroup& g : m_groups) {
        g.memberBegin = begin;
        begin += g.memberCount;
        g.memberCount = 0;
    }
    m_order.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        SurfaceGroup& g = m_groups[groupOf[i]];
        m_order[g.memberBegin + g.memberCount++] = i;
    }

    // Which fragment is an edge-neighbour (hard or soft) of some member of group `gid`.
    auto neighbourOfGroup = [&](const Fragment& f, uint32_t gid) {
        const SurfaceGroup& g = m_groups[gid];
        if (f.object != g.object || f.object >= m_topology.size()) return false;
        const ObjectTopology& topo = m_topology[f.object];
        if (topo.empty()) return false;
        auto neighbours = [&](uint32_t t, uint32_t other) {
            const uint32_t* nbs = topo.neighborsOf(t);
            if (!nbs) return false;
            for (int k = 0; k < 3; ++k) {
                const uint32_t nb = nbs[k];
                if (nb != kNoTriangle && (nb & ~kHardEdgeBit) == other) return true;
            }
            return false;
        };
        for (uint32_t k = 0; k < g.memberCount; ++k) {
            const Fragment& m = F[m_order[g.memberBegin + k]];
            if (neighbours(f.triangle, m.triangle) || neighbours(m.triangle, f.triangle)) return true;
        }
        return false;
    };

    // c, d. Group properties, and the visibility of groups without sub-samples.
    for (uint32_t gid = 0; gid < groupCount; ++gid) {
        SurfaceGroup& g = m_groups[gid];
        const uint32_t* idx = m_order.data() + g.memberBegin;
        g.object = F[idx[0]].object;
        double area = 0, wu = 0, wv = 0, su = 0, sv = 0;
        uint32_t largest = idx[0];
        for (uint32_t k = 0; k < g.memberCount; ++k) {
            const Fragment& f = F[idx[k]];
            g.mask |= f.mask;
            g.visibleMask |= m_visible[idx[k]];
            g.transparent = g.transparent || (f.flags & kFragmentTransparent);
            area += f.area;
            wu += double(f.area) * f.cu;
            wv += double(f.area) * f.cv;
            su += f.cu;
            sv += f.cv;
            if (f.area > F[largest].area) largest = idx[k];
        }
        g.area = float(area);
        if (g.visibleMask) {
            double u = 0, v = 0;
            for (uint64_t m = g.visibleMask; m; m &= m - 1) {
                u += kCentre.u[lowestBit(m)];
                v += kCentre.v[lowestBit(m)];
            }
            const int c = std::popcount(g.visibleMask);
            g.cu = float(u / c);
            g.cv = float(v / c);
        } else if (area > 0) {
            g.cu = float(wu / area);
            g.cv = float(wv / area);
        } else {
            g.cu = float(su / g.memberCount);
            g.cv = float(sv / g.memberCount);
        }
        const bool useVisible = g.visibleMask != 0;
        if (g.mask) {
            float depth = kInf;
            for (uint32_t k = 0; k < g.memberCount; ++k) {
                const Fragment& f = F[idx[k]];
                for (uint64_t m = useVisible ? m_visible[idx[k]] : f.mask; m; m &= m - 1) {
                    const int b = lowestBit(m);
                    depth = std::min(depth, depthKey(f.depthAt(kCentre.u[b], kCentre.v[b])));
                }
            }
            g.depth = depth;
        } else {
            const Fragment& big = F[largest];
            g.depth = depthKey(big.depthAt(big.cu, big.cv));
            // A sliver between sub-samples is judged at its representative sub-sample r: hidden
            // when an opaque fragment there, which is not a mesh neighbour of the sliver (a
            // neighbour meets it at a shared edge rather than lying in front of it), is nearer
            // at the sliver's centroid. The sliver's depth there is its largest member's plane.
            const int r = nearestActiveBit(active, g.cu, g.cv);
            const float own = depthKey(big.depthAt(g.cu, g.cv));
            bool hidden = false;
            for (size_t j = 0; j < n && !hidden; ++j) {
                const Fragment& o = F[j];
                if ((o.flags & kFragmentTransparent) || !((o.mask >> r) & 1)) continue;
                if (!nearerBy(depthKey(o.depthAt(g.cu, g.cv)), own)) continue;
                if (neighbourOfGroup(o, gid)) continue;
                hidden = true;
            }
            g.coverage = hidden ? 0.0f : std::min(g.area, 1.0f);
        }
    }

    // f. Front-to-back order: depth, object, smallest member triangle (the first member, as members
    //    are in canonical order), then the first member's canonical index.
    std::sort(m_groups.begin(), m_groups.end(), [&](const SurfaceGroup& a, const SurfaceGroup& b) {
        if (a.depth != b.depth) return a.depth < b.depth;
        if (a.object != b.object) return a.object < b.object;
        const uint32_t fa = m_order[a.memberBegin], fb = m_order[b.memberBegin];
        if (F[fa].triangle != F[fb].triangle) return F[fa].triangle < F[fb].triangle;
        return fa < fb;
    });
    m_members.reserve(n);
    for (SurfaceGroup& g : m_groups) {
        const uint32_t newBegin = uint32_t(m_members.size());
        for (uint32_t k = 0; k < g.memberCount; ++k) m_members.push_back(F[m_order[g.memberBegin + k]]);
        g.memberBegin = newBegin;
    }

    // e. Coverage, front to back. A group that covers the whole pixel and is partly hidden gets
    //    what the nearer opaque groups leave, which keeps an edge in front of it exact even when
    //    the sub-samples misjudge the edge's area; any other group scales its exact area by the
    //    visible fraction of its sub-samples.
    //    An opaque group that covers the whole pixel closes it: a full group behind it gets nothing,
    //    even where the coverages in front, rounded to float, sum to a hair under 1.
    double opaqueBefore = 0;
    bool closed = false;
    for (SurfaceGroup& g : m_groups) {
        if (g.mask) {
            if (g.area >= kFullPixelArea && (g.visibleMask != g.mask || opaqueBefore > 0)) {
                const double left = closed ? 0.0 : std::max(0.0, 1.0 - opaqueBefore);
                g.coverage = float(std::min(double(g.area), left));
            } else {
                g.coverage = g.area * float(std::popcount(g.visibleMask)) / float(std::popcount(g.mask));
            }
            g.coverage = std::clamp(g.coverage, 0.0f, 1.0f);
        }
        if (!g.transparent) {
            opaqueBefore += g.coverage;
            closed = closed || g.area >= kFullPixelArea;
        }
    }
    if (opaqueBefore > 1.0) {
        const double scale = 1.0 / opaqueBefore;
        for (SurfaceGroup& g : m_groups) {
            if (!g.transparent) g.coverage = float(g.coverage * scale);
        }
    }
    double opaque = 0;
    for (const SurfaceGroup& g : m_groups) {
        if (g.transparent) continue;
        opaque += g.coverage;
        if (g.coverage > 0) m_nearestDepth = std::min(m_nearestDepth, g.depth);
    }
    m_opaqueCoverage = float(std::min(opaque, 1.0));
}

float PixelResolver::occludingDepth(std::span<const Fragment> input) {
    const uint64_t active = m_pattern.active;
    m_sorted.clear();
    for (const Fragment& in : input) {
        if (in.flags & kFragmentTransparent) continue;
        Fragment f = in;
        f.mask &= active;
        f.area = (f.area > 0.0f && f.area <= FLT_MAX) ? f.area : 0.0f;
        m_sorted.push_back(f);
    }
    const size_t n = m_sorted.size();
    if (n == 0 || active == 0) return kInf;
    // A few fragments are joined pair by pair below; more are sorted so that the fragments of a
    // triangle are found by a binary search.
    constexpr size_t kPairwise = 12;
    if (n > kPairwise) std::sort(m_sorted.begin(), m_sorted.end(), fragmentLess);
    const std::vector<Fragment>& F = m_sorted;

    // The farthest each fragment's plane reaches over the pixel square (a plane is largest at a
    // corner), and per sub-sample the nearest such reach among the fragments that hold it: every
    // depth resolve() reads inside the pixel is at most this.
    m_far.resize(n);
    float bitFar[kSubsampleCount];
    std::fill(std::begin(bitFar), std::end(bitFar), kInf);
    for (size_t i = 0; i < n; ++i) {
        const Fragment& f = F[i];
        const float far = std::max({depthKey(f.depthAt(0.0f, 0.0f)), depthKey(f.depthAt(1.0f, 0.0f)),
                                    depthKey(f.depthAt(0.0f, 1.0f)), depthKey(f.depthAt(1.0f, 1.0f))});
        m_far[i] = far;
        for (uint64_t m = f.mask; m; m &= m - 1) bitFar[lowestBit(m)] = std::min(bitFar[lowestBit(m)], far);
    }
    float cover = -kInf;
    for (uint64_t m = active; m; m &= m - 1) cover = std::max(cover, bitFar[lowestBit(m)]);
    if (cover == kInf) return kInf;

    // Surface groups among the opaque fragments, joined as resolve() joins them; each is part of
    // a group resolve() forms, so its area is a lower bound of that group's.
    m_parent.resize(n);
    for (size_t i = 0; i < n; ++i) m_parent[i] = uint32_t(i);
    joinSoftNeighbours(F, n > kPairwise, m_topology, m_parent, m_triangleTable);
    m_groupArea.assign(n, 0.0);
    m_groupFar.assign(n, -kInf);
    m_visible.assign(n, 0);  // the group's mask, at its root
    for (size_t i = 0; i < n; ++i) {
        const uint32_t r = findRoot(m_parent, uint32_t(i));
        m_groupArea[r] += F[i].area;
        m_groupFar[r] = std::max(m_groupFar[r], m_far[i]);
        m_visible[r] |= F[i].mask;
    }
    // A group that closes the pixel in resolve(); the margin absorbs the float rounding of an
    // area summed in another order.
    float closing = kInf;
    for (size_t r = 0; r < n; ++r) {
        if (m_parent[r] != r || !m_visible[r]) continue;
        if (double(float(m_groupArea[r])) >= kFullPixelArea + 1e-7) closing = std::min(closing, m_groupFar[r]);
    }
    if (closing == kInf) return kInf;
    return std::max(cover, closing);
}

bool occludedBehind(float occludingDepth, double nearestDepthKey) {
    if (!std::isfinite(occludingDepth) || !std::isfinite(nearestDepthKey)) return false;
    const double seal = occludingDepth;
    return nearestDepthKey > seal + kOcclusionMargin * std::max(std::fabs(seal), std::fabs(nearestDepthKey));
}

const Fragment& PixelResolver::memberAt(const SurfaceGroup& group, int bit) const {
    return surfaceMemberAt(m_members, group, bit);
}

const Fragment& surfaceMemberAt(std::span<const Fragment> members, const SurfaceGroup& group, int bit) {
    const Fragment* first = members.data() + group.memberBegin;
    const Fragment* best = nullptr;
    float bestDepth = kInf;
    if (bit >= 0 && bit < kSubsampleCount) {
        for (uint32_t k = 0; k < group.memberCount; ++k) {
            const Fragment& f = first[k];
            if (!((f.mask >> bit) & 1)) continue;
            const float d = depthKey(f.depthAt(kCentre.u[bit], kCentre.v[bit]));
            if (!best || d < bestDepth) {
                best = &f;
                bestDepth = d;
            }
        }
    }
    if (best) return *best;
    best = first;
    for (uint32_t k = 1; k < group.memberCount; ++k) {
        if (first[k].area > best->area) best = first + k;
    }
    return *best;
}

void PixelResolver::composite(std::span<const SurfaceShade> shades, std::span<SurfaceContribution> out) const {
    compositeSurfaces(m_pattern, m_groups, m_members, shades, out);
}

void compositeSurfaces(const SubsamplePattern& pattern, std::span<const SurfaceGroup> groups,
                       std::span<const Fragment> members, std::span<const SurfaceShade> shades,
                       std::span<SurfaceContribution> out) {
    const size_t count = std::min({groups.size(), shades.size(), out.size()});
    float T[kSubsampleCount][3];
    for (auto& t : T) t[0] = t[1] = t[2] = 1.0f;
    // Transparency per channel as the composite uses it: 0 for surfaces that cannot be transparent.
    auto transparencyOf = [&](size_t i, int c) {
        return groups[i].transparent ? clamp01(shades[i].transparency[c]) : 0.0f;
    };

    for (size_t i = 0; i < count; ++i) {
        const SurfaceGroup& g = groups[i];
        const SurfaceShade& s = shades[i];
        SurfaceContribution o;
        o.cu = g.cu;
        o.cv = g.cv;
        const float tr[3] = {transparencyOf(i, 0), transparencyOf(i, 1), transparencyOf(i, 2)};
        if (g.visibleMask) {
            const float w = g.coverage / float(std::popcount(g.visibleMask));
            double alpha = 0;
            for (uint64_t m = g.visibleMask; m; m &= m - 1) {
                float* t = T[lowestBit(m)];
                double a = 0;
                for (int c = 0; c < 3; ++c) {
                    o.color[c] += w * t[c] * s.color[c];
                    a += t[c] * (1.0f - tr[c]);
                    t[c] *= tr[c];
                }
                alpha += w * a / 3.0;
            }
            o.alpha = float(alpha);
        } else if (g.coverage > 0) {
            // No visible sub-sample: a sliver, or a full surface whose sub-samples are all taken
            // by nearer opaque ones. Its coverage already excludes what opaque surfaces hide, so
            // only transparent surfaces in front of it at its representative sub-sample r dim it
            // (an opaque neighbour that owns r would otherwise erase a sliver it does not cover).
            const int r = nearestActiveBit(pattern.active, g.cu, g.cv);
            const float own = depthKey(surfaceMemberAt(members, g, r).depthAt(kCentre.u[r], kCentre.v[r]));
            float ts[3] = {1.0f, 1.0f, 1.0f};
            for (size_t h = 0; h < i; ++h) {
                const SurfaceGroup& front = groups[h];
                if (!front.transparent || !((front.visibleMask >> r) & 1)) continue;
                const float d = depthKey(surfaceMemberAt(members, front, r).depthAt(kCentre.u[r], kCentre.v[r]));
                if (!nearerBy(d, own)) continue;
                for (int c = 0; c < 3; ++c) ts[c] *= transparencyOf(h, c);
            }
            double a = 0;
            for (int c = 0; c < 3; ++c) {
                o.color[c] = g.coverage * ts[c] * s.color[c];
                a += ts[c] * (1.0f - tr[c]);
            }
            o.alpha = float(g.coverage * a / 3.0);
        }
        out[i] = o;
    }
    for (size_t i = count; i < out.size(); ++i) out[i] = SurfaceContribution{};
}

}  // namespace pushpin::render
