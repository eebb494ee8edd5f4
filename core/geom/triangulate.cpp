#include "core/geom/triangulate.h"

#include "core/geom/finite.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace pushpin::geom {

namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }
// Twice the signed area of (a, b, c): positive for a left turn (counter-clockwise).
double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) { return cross2(b - a, c - a); }

}  // namespace

size_t PolygonTriangulator::triangulate(std::span<const glm::dvec3> points, std::span<const uint32_t> loopStarts,
                                        const glm::dvec3& normal, std::vector<uint32_t>& triangles) {
    if (loopStarts.size() < 2) return 0;
    for (size_t l = 0; l + 1 < loopStarts.size(); ++l)
        if (loopStarts[l] > loopStarts[l + 1]) return 0;
    if (loopStarts.back() > points.size()) return 0;
    const uint32_t outerBegin = loopStarts[0], outerEnd = loopStarts[1];
    if (outerEnd - outerBegin < 3) return 0;
    for (uint32_t i = loopStarts.front(); i < loopStarts.back(); ++i)
        if (!isFinite(points[i])) return 0;

    // Projection plane: (u, v, n) right-handed, so counter-clockwise about n stays
    // counter-clockwise in the plane.
    glm::dvec3 n = normal;
    if (!isFinite(n) || glm::dot(n, n) == 0.0) {
        n = glm::dvec3(0.0);
        for (uint32_t i = outerBegin; i < outerEnd; ++i) {
            const glm::dvec3& a = points[i];
            const glm::dvec3& b = points[i + 1 < outerEnd ? i + 1 : outerBegin];
            n += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        }
    }
    const double nLength = glm::length(n);
    if (!(nLength > 0.0) || !std::isfinite(nLength)) return 0;
    n /= nLength;
    const glm::dvec3 an = glm::abs(n);
    const glm::dvec3 axis = an.x <= an.y && an.x <= an.z ? glm::dvec3(1, 0, 0)
                            : an.y <= an.z               ? glm::dvec3(0, 1, 0)
                                                         : glm::dvec3(0, 0, 1);
    const glm::dvec3 u = glm::normalize(glm::cross(axis, n));
    const glm::dvec3 v = glm::cross(n, u);
    const glm::dvec3 origin = points[outerBegin];
    m_p.assign(points.size(), glm::dvec2(0.0));
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (uint32_t i = loopStarts.front(); i < loopStarts.back(); ++i) {
        const glm::dvec3 d = points[i] - origin;
        m_p[i] = glm::dvec2(glm::dot(d, u), glm::dot(d, v));
        lo = glm::min(lo, m_p[i]);
        hi = glm::max(hi, m_p[i]);
    }
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    if (!(extent > 0.0) || !std::isfinite(extent)) return 0;
    // Relative tolerance: a cross product this small is a straight angle at float precision.
    m_epsArea = 1e-12 * extent * extent;

    // A loop as a ring of indices without consecutive repeated positions; returns twice its area.
    auto buildRing = [&](uint32_t begin, uint32_t end, std::vector<uint32_t>& out) {
        const size_t first = out.size();
        for (uint32_t i = begin; i < end; ++i)
            if (out.size() == first || m_p[out.back()] != m_p[i]) out.push_back(i);
        while (out.size() - first > 1 && m_p[out.back()] == m_p[out[first]]) out.pop_back();
        double area = 0.0;
        for (size_t k = first; k < out.size(); ++k)
            area += cross2(m_p[out[k]], m_p[out[k + 1 < out.size() ? k + 1 : first]]);
        return area;
    };

    m_ring.clear();
    const double outerArea = buildRing(outerBegin, outerEnd, m_ring);
    if (m_ring.size() < 3 || std::abs(outerArea) <= m_epsArea) return 0;
    if (outerArea < 0.0) {
        // The outer loop winds clockwise about `normal`: mirror the plane so it is
        // counter-clockwise; triangles emitted in ring order then still wind like the loop.
        for (uint32_t i = loopStarts.front(); i < loopStarts.back(); ++i) m_p[i].y = -m_p[i].y;
    }

    // Holes, clockwise in the (possibly mirrored) plane, bridged from the rightmost one leftwards
    // so that every bridge stays clear of holes not yet merged.
    m_holes.clear();
    m_holeStarts.assign(1, 0);
    for (size_t l = 1; l + 1 < loopStarts.size(); ++l) {
        const size_t first = m_holes.size();
        const double area = buildRing(loopStarts[l], loopStarts[l + 1], m_holes);
        if (m_holes.size() - first < 3 || std::abs(area) <= m_epsArea) {
            m_holes.resize(first);
            continue;
        }
        if (area > 0.0) std::reverse(m_holes.begin() + std::ptrdiff_t(first), m_holes.end());
        m_holeStarts.push_back(uint32_t(m_holes.size()));
    }
    std::vector<size_t>& order = m_order;
    order.resize(m_holeStarts.size() - 1);
    std::iota(order.begin(), order.end(), size_t(0));
    auto maxX = [&](size_t h) {
        double x = -std::numeric_limits<double>::infinity();
        for (uint32_t k = m_holeStarts[h]; k < m_holeStarts[h + 1]; ++k) x = std::max(x, m_p[m_holes[k]].x);
        return x;
    };
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return maxX(a) > maxX(b); });
    for (size_t h : order) bridgeHole(m_holeStarts[h], m_holeStarts[h + 1]);

    return clipEars(triangles);
}

// Joins the hole ring m_holes[holeBegin, holeEnd) to the outer ring by a two-way bridge from the
// hole's rightmost vertex M to a vertex P of the ring that M sees (Eberly §3). Returns false (and
// leaves the ring unchanged) when no edge of the ring lies to the right of M: the hole is not
// inside the outer loop.
bool PolygonTriangulator::bridgeHole(size_t holeBegin, size_t holeEnd) {
    size_t mi = holeBegin;
    for (size_t k = holeBegin + 1; k < holeEnd; ++k) {
        const glm::dvec2& a = m_p[m_holes[k]];
        const glm::dvec2& b = m_p[m_holes[mi]];
        if (a.x > b.x || (a.x == b.x && a.y > b.y)) mi = k;
    }
    const glm::dvec2 m = m_p[m_holes[mi]];
    const size_t n = m_ring.size();

    // Nearest intersection of the ray from M towards +x with the ring's edges.
    double bestX = std::numeric_limits<double>::infinity();
    size_t bestEdge = n;
    for (size_t k = 0; k < n; ++k) {
        const glm::dvec2& a = m_p[m_ring[k]];
        const glm::dvec2& b = m_p[m_ring[(k + 1) % n]];
        if (a.y == b.y) continue;  // a horizontal edge on the ray is found through its end points
        if (m.y < std::min(a.y, b.y) || m.y > std::max(a.y, b.y)) continue;
        const double t = (m.y - a.y) / (b.y - a.y);
        const double x = a.x + t * (b.x - a.x);
        if (x >= m.x && x < bestX) {
            bestX = x;
            bestEdge = k;
        }
    }
    if (bestEdge == n) return false;

    const glm::dvec2 hit(bestX, m.y);
    const size_t ka = bestEdge, kb = (bestEdge + 1) % n;
    size_t pk;
    if (m_p[m_ring[ka]] == hit) pk = ka;
    else if (m_p[m_ring[kb]] == hit) pk = kb;
    else {
        pk = m_p[m_ring[ka]].x > m_p[m_ring[kb]].x ? ka : kb;
        // A reflex vertex inside the triangle (M, hit, P) would block the view from M to P; the
        // one making the smallest angle with the ray is visible instead.
        const glm::dvec2 p = m_p[m_ring[pk]];
        const double sign = orient(m, hit, p) >= 0.0 ? 1.0 : -1.0;
        double bestCos = -2.0, bestDist = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < n; ++k) {
            if (k == pk) continue;
            const glm::dvec2& r = m_p[m_ring[k]];
            const glm::dvec2& rp = m_p[m_ring[(k + n - 1) % n]];
            const glm::dvec2& rn = m_p[m_ring[(k + 1) % n]];
            if (orient(rp, r, rn) > m_epsArea) continue;  // convex vertices never block
            if (sign * orient(m, hit, r) < 0.0 || sign * orient(hit, p, r) < 0.0 || sign * orient(p, m, r) < 0.0)
                continue;
            const glm::dvec2 d = r - m;
            const double dist = glm::length(d);
            if (!(dist > 0.0)) continue;
            const double c = d.x / dist;
            if (c > bestCos || (c == bestCos && dist < bestDist)) {
                bestCos = c;
                bestDist = dist;
                pk = k;
            }
        }
    }

    // Earlier bridges duplicate vertices: among the copies of P, use the one whose interior
    // wedge contains the direction towards M.
    const glm::dvec2 p = m_p[m_ring[pk]];
    for (size_t k = 0; k < n; ++k) {
        if (m_p[m_ring[k]] != p) continue;
        const glm::dvec2& a = m_p[m_ring[(k + n - 1) % n]];
        const glm::dvec2& b = m_p[m_ring[(k + 1) % n]];
        const bool convex = orient(a, p, b) > 0.0;
        const double toNext = cross2(b - p, m - p), fromPrev = cross2(m - p, a - p);
        const bool inside = convex ? (toNext >= 0.0 && fromPrev >= 0.0) : (toNext >= 0.0 || fromPrev >= 0.0);
        if (inside) {
            pk = k;
            break;
        }
    }

    // ring: … P, M, (hole after M) …, M, P, …
    std::vector<uint32_t> insert;
    insert.reserve(holeEnd - holeBegin + 2);
    for (size_t k = 0; k <= holeEnd - holeBegin; ++k)
        insert.push_back(m_holes[holeBegin + (mi - holeBegin + k) % (holeEnd - holeBegin)]);
    insert.push_back(m_ring[pk]);
    m_ring.insert(m_ring.begin() + std::ptrdiff_t(pk + 1), insert.begin(), insert.end());
    return true;
}

size_t PolygonTriangulator::clipEars(std::vector<uint32_t>& triangles) {
    const size_t n = m_ring.size();
    if (n < 3) return 0;
    m_prev.resize(n);
    m_next.resize(n);
    m_reflex.resize(n);
    for (size_t k = 0; k < n; ++k) {
        m_prev[k] = uint32_t((k + n - 1) % n);
        m_next[k] = uint32_t((k + 1) % n);
    }
    auto pos = [&](uint32_t k) -> const glm::dvec2& { return m_p[m_ring[k]]; };
    auto turn = [&](uint32_t k) { return orient(pos(m_prev[k]), pos(k), pos(m_next[k])); };
    // "Reflex" here includes straight and degenerate corners: they may lie on an ear's edge.
    for (uint32_t k = 0; k < n; ++k) m_reflex[k] = turn(k) <= m_epsArea;

    size_t emitted = 0;
    auto emit = [&](uint32_t k) {
        triangles.push_back(m_ring[m_prev[k]]);
        triangles.push_back(m_ring[k]);
        triangles.push_back(m_ring[m_next[k]]);
        ++emitted;
    };
    auto remove = [&](uint32_t k) {
        const uint32_t a = m_prev[k], c = m_next[k];
        m_next[a] = c;
        m_prev[c] = a;
        m_reflex[a] = turn(a) <= m_epsArea;
        m_reflex[c] = turn(c) <= m_epsArea;
        return c;
    };
    auto isEar = [&](uint32_t k) {
        if (m_reflex[k]) return false;
        const uint32_t a = m_prev[k], c = m_next[k];
        const glm::dvec2 &pa = pos(a), &pb = pos(k), &pc = pos(c);
        for (uint32_t j = m_next[c]; j != a; j = m_next[j]) {
            if (!m_reflex[j]) continue;  // only reflex corners can lie inside an ear
            const glm::dvec2& q = pos(j);
            if (q == pa || q == pb || q == pc) continue;  // bridge copies of the ear's corners
            // Inclusive test: a corner on the new diagonal blocks the ear as well.
            if (orient(pa, pb, q) >= -m_epsArea && orient(pb, pc, q) >= -m_epsArea && orient(pc, pa, q) >= -m_epsArea)
                return false;
        }
        return true;
    };

    size_t remaining = n;
    uint32_t k = 0;
    size_t stall = 0;
    while (remaining > 3) {
        if (isEar(k)) {
            emit(k);
            k = remove(k);
            --remaining;
            stall = 0;
            continue;
        }
        k = m_next[k];
        if (++stall < remaining) continue;
        // No ear in a full turn: the ring self-intersects or is degenerate at float precision.
        // Clip the most convex corner anyway (keeps the area roughly right), or, when no corner
        // is convex, drop the straightest one without a triangle. Either way the ring shrinks.
        uint32_t best = k, flattest = k;
        double bestTurn = -std::numeric_limits<double>::infinity(), flattestTurn = std::numeric_limits<double>::infinity();
        uint32_t j = k;
        do {
            const double t = turn(j);
            if (t > bestTurn) bestTurn = t, best = j;
            if (std::abs(t) < flattestTurn) flattestTurn = std::abs(t), flattest = j;
            j = m_next[j];
        } while (j != k);
        if (bestTurn > m_epsArea) {
            emit(best);
            k = remove(best);
        } else {
            k = remove(flattest);
        }
        --remaining;
        stall = 0;
    }
    if (turn(k) > m_epsArea) emit(k);
    return emitted;
}

}  // namespace pushpin::geom
