// core/geom/poly_split.cpp: polySplit on a geom::Mesh.
#include "core/geom/poly_split.h"

#include "core/geom/detail/face_edit.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

namespace pushpin::geom {

namespace {

using detail::Corner;
using detail::FaceLoops;

// Fractions this close to a point already on the edge land on it.
constexpr double kSameFraction = 1e-6;

glm::dvec3 loopNormal(const std::vector<Corner>& loop, const std::vector<glm::vec3>& points) {
    glm::dvec3 n(0.0);
    for (size_t i = 0; i < loop.size(); ++i) {
        const glm::dvec3 a(points[loop[i].point]), b(points[loop[(i + 1) % loop.size()].point]);
        n += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    return n;
}

// Whether `p` lies inside `loop`, both taken into the plane perpendicular to `normal`.
bool insideLoop(const std::vector<Corner>& loop, const std::vector<glm::vec3>& points, const glm::dvec3& p,
                const glm::dvec3& normal) {
    const glm::dvec3 an = glm::abs(normal);
    const int drop = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    bool inside = false;
    for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
        const glm::dvec3 a(points[loop[i].point]), b(points[loop[j].point]);
        if ((a[v] > p[v]) != (b[v] > p[v]) && p[u] < (b[u] - a[u]) * (p[v] - a[v]) / (b[v] - a[v]) + a[u]) inside = !inside;
    }
    return inside;
}

class Splitter {
public:
    Splitter(Mesh& work, const SplitParams& params) : m_work(work), m_params(params), m_editor(work) {
        m_inputEdges = work.edges;
        m_inputPoints = work.points.size();
        m_facesOf.resize(work.points.size());
        for (size_t f = 0; f < work.faceCount(); ++f) {
            m_origin.push_back(uint32_t(f));
            for (uint32_t fv = work.faceVertexBegin(f); fv < work.faceVertexEnd(f); ++fv) addFaceOf(work.faceVertices[fv], uint32_t(f));
        }
        for (size_t e = 0; e < work.edges.size(); ++e) m_edgeOf.emplace(edgeKey(work.edges[e].v0, work.edges[e].v1), uint32_t(e));
        m_smoothCos = std::cos(std::clamp(params.smoothingAngle, 0.0, 3.14159265358979323846));
    }

    void run(SplitResult& r) {
        int64_t previous = -1;
        std::vector<FreePoint> pending;
        for (const SplitPoint& sp : m_params.points) {
            if (sp.kind == SplitPoint::Kind::Face) {
                if (previous < 0) {
                    ++r.skippedCuts;
                    continue;
                }
                pending.push_back({sp.position, sp.index, 0});
                continue;
            }
            const uint32_t at = edgePoint(uint32_t(sp.index), std::clamp(sp.fraction, 0.0, 1.0));
            if (previous >= 0 && !cut(uint32_t(previous), pending, at)) ++r.skippedCuts;
            pending.clear();
            previous = at;
        }
        if (!pending.empty()) ++r.skippedCuts;
    }

    detail::FaceEditor& editor() { return m_editor; }

private:
    struct FreePoint {
        glm::dvec3 position;
        int64_t face;
        uint32_t point;
    };

    void addFaceOf(uint32_t point, uint32_t f) {
        std::vector<uint32_t>& list = m_facesOf[point];
        if (std::find(list.begin(), list.end(), f) == list.end()) list.push_back(f);
    }
    void removeFaceOf(uint32_t point, uint32_t f) {
        std::vector<uint32_t>& list = m_facesOf[point];
        list.erase(std::remove(list.begin(), list.end(), f), list.end());
    }
    uint32_t newPoint(const glm::vec3& p) {
        m_work.points.push_back(p);
        m_facesOf.emplace_back();
        return uint32_t(m_work.points.size() - 1);
    }
    void addEdge(uint32_t a, uint32_t b, bool smooth) {
        m_edgeOf[edgeKey(a, b)] = uint32_t(m_work.edges.size());
        m_work.edges.push_back({a, b, smooth});
    }

    // The point at `t` along input edge `e`: an end point, a point an earlier split put there, or
    // a new point splitting the piece of the edge it falls in.
    uint32_t edgePoint(uint32_t e, double t) {
        const MeshEdge& input = m_inputEdges[e];
        auto [it, fresh] = m_stops.try_emplace(e);
        std::vector<std::pair<double, uint32_t>>& stops = it->second;
        if (fresh) stops = {{0.0, input.v0}, {1.0, input.v1}};
        size_t i = 0;
        while (i + 2 < stops.size() && stops[i + 1].first <= t) ++i;
        if (t - stops[i].first <= kSameFraction) return stops[i].second;
        if (stops[i + 1].first - t <= kSameFraction) return stops[i + 1].second;
        const uint32_t a = stops[i].second, b = stops[i + 1].second;
        const glm::vec3 position = glm::mix(m_work.points[input.v0], m_work.points[input.v1], float(t));
        const uint32_t p = newPoint(position);
        stops.insert(stops.begin() + std::ptrdiff_t(i + 1), {t, p});
        // The piece a–b keeps its index from its first point to p; the rest is appended.
        const auto piece = m_edgeOf.find(edgeKey(a, b));
        if (piece != m_edgeOf.end()) {
            const uint32_t index = piece->second;
            m_edgeOf.erase(piece);
            MeshEdge& edge = m_work.edges[index];
            const uint32_t last = edge.v1;
            const bool smooth = edge.smooth;
            edge.v1 = p;
            m_edgeOf[edgeKey(edge.v0, p)] = index;
            addEdge(p, last, smooth);
        }
        // Every loop along the piece gains p.
        const std::vector<uint32_t> faces = m_facesOf[a];
        for (uint32_t f : faces) {
            if (std::find(m_facesOf[b].begin(), m_facesOf[b].end(), f) == m_facesOf[b].end()) continue;
            for (std::vector<Corner>& loop : m_editor.face(f))
                for (size_t k = 0; k < loop.size(); ++k) {
                    const Corner& ca = loop[k];
                    const Corner& cb = loop[(k + 1) % loop.size()];
                    if (edgeKey(ca.point, cb.point) != edgeKey(a, b)) continue;
                    const double local = (t - stops[i].first) / (stops[i + 2].first - stops[i].first);
                    loop.insert(loop.begin() + std::ptrdiff_t(k + 1),
                                m_editor.cornerOnEdge(ca, cb, p, ca.point == a ? local : 1.0 - local));
                    addFaceOf(p, f);
                    break;
                }
        }
        return p;
    }

    // The face whose outer loop holds both a and b, preferring one descended from `hint`; -1 if none.
    int64_t faceWith(uint32_t a, uint32_t b, int64_t hint, const glm::dvec3* inside) {
        int64_t found = -1;
        for (uint32_t f : m_facesOf[a]) {
            if (std::find(m_facesOf[b].begin(), m_facesOf[b].end(), f) == m_facesOf[b].end()) continue;
            const std::vector<Corner>& outer = m_editor.face(f).front();
            const auto has = [&](uint32_t p) {
                return std::any_of(outer.begin(), outer.end(), [&](const Corner& c) { return c.point == p; });
            };
            if (!has(a) || !has(b)) continue;
            if (hint >= 0 && m_origin[f] == uint64_t(hint)) return f;
            if (inside && insideLoop(outer, m_work.points, *inside, loopNormal(outer, m_work.points))) return f;
            if (found < 0) found = f;
        }
        return found;
    }

    bool cut(uint32_t a, const std::vector<FreePoint>& free, uint32_t b) {
        if (a == b) return false;
        const int64_t hint = free.empty() ? -1 : free.front().face;
        const int64_t f = faceWith(a, b, hint, free.empty() ? nullptr : &free.front().position);
        if (f < 0) return false;
        FaceLoops& loops = m_editor.face(uint32_t(f));
        std::vector<Corner>& outer = loops.front();
        const size_t n = outer.size();
        size_t ia = n, ib = n;
        for (size_t i = 0; i < n; ++i) {
            if (outer[i].point == a) ia = i;
            if (outer[i].point == b) ib = i;
        }
        std::vector<FreePoint> inner = m_params.dropFreePoints ? std::vector<FreePoint>{} : free;
        if (inner.empty() && ((ia + 1) % n == ib || (ib + 1) % n == ia)) return true;  // already an edge
        // The free points are made once the cut is known, from its far end back.
        for (size_t i = inner.size(); i-- > 0;) inner[i].point = newPoint(glm::vec3(inner[i].position));
        const std::vector<Corner> corners = outer;
        const glm::dvec3 normal = loopNormal(corners, m_work.points);
        // Sections of a straight cut.
        if (free.empty() && m_params.subdivisions > 1)
            for (int k = 1; k < m_params.subdivisions; ++k) {
                const double t = double(k) / double(m_params.subdivisions);
                const glm::dvec3 p = glm::mix(glm::dvec3(m_work.points[a]), glm::dvec3(m_work.points[b]), t);
                inner.push_back({p, f, newPoint(glm::vec3(p))});
            }
        std::vector<glm::dvec3> loopPoints;
        for (const Corner& c : corners) loopPoints.emplace_back(m_work.points[c.point]);
        std::vector<Corner> path;  // the free points, A to B
        for (const FreePoint& fp : inner) {
            const std::vector<double> w = detail::polygonWeights(loopPoints, fp.position, normal);
            path.push_back(m_editor.cornerFromWeights(corners, w, fp.point));
        }
        std::vector<Corner> one, two;  // A forward to B, B forward to A, along the face
        for (size_t i = ia;; i = (i + 1) % n) {
            one.push_back(corners[i]);
            if (i == ib) break;
        }
        for (size_t i = ib;; i = (i + 1) % n) {
            two.push_back(corners[i]);
            if (i == ia) break;
        }
        one.insert(one.end(), path.rbegin(), path.rend());
        two.insert(two.end(), path.begin(), path.end());
        // The part with more of the input mesh's corners keeps the face; on a tie, the part from A
        // forward to B is appended. (Maya's recorded extrusion bounds after real scenes' splits
        // agree: a pocket cut off one edge through free points is appended, whichever way the
        // face runs along that edge, and so is the A-to-B part of a cut across a quad.)
        const auto inOne = [&](size_t i) { return (i + n - ia) % n <= (ib + n - ia) % n; };
        size_t inputInOne = 0, inputInTwo = 0;
        for (size_t i = 0; i < n; ++i)
            if (i != ia && i != ib && corners[i].point < m_inputPoints) ++(inOne(i) ? inputInOne : inputInTwo);
        const bool oneKept = inputInOne > inputInTwo;
        std::vector<Corner>& keptLoop = oneKept ? one : two;
        std::vector<Corner>& movedLoop = oneKept ? two : one;
        const uint32_t firstPoint = corners.front().point;
        if (const auto at = std::find_if(keptLoop.begin(), keptLoop.end(), [&](const Corner& c) { return c.point == firstPoint; });
            at != keptLoop.end())
            std::rotate(keptLoop.begin(), at, keptLoop.end());
        const glm::dvec3 nOne = loopNormal(one, m_work.points), nTwo = loopNormal(two, m_work.points);
        // Holes go with the part they lie in.
        FaceLoops kept{keptLoop}, moved{movedLoop};
        for (size_t h = 1; h < loops.size(); ++h) {
            const glm::dvec3 p(m_work.points[loops[h].front().point]);
            (insideLoop(movedLoop, m_work.points, p, normal) ? moved : kept).push_back(std::move(loops[h]));
        }
        const uint32_t appended = m_editor.append(std::move(moved));
        m_origin.push_back(m_origin[size_t(f)]);
        m_editor.face(uint32_t(f)) = std::move(kept);
        // Incidence: the corners of the appended part that are not on the kept one left f.
        for (size_t i = 0; i < n; ++i)
            if (i != ia && i != ib && inOne(i) == !oneKept) removeFaceOf(corners[i].point, uint32_t(f));
        for (const std::vector<Corner>& loop : m_editor.face(appended))
            for (const Corner& c : loop) addFaceOf(c.point, appended);
        for (const Corner& c : path) addFaceOf(c.point, uint32_t(f));
        // The new edges, A to B along the cut.
        const double lengths = glm::length(nOne) * glm::length(nTwo);
        // Soft when the parts meet at less than the smoothing angle.
        const bool smooth = lengths > 0.0 && glm::dot(nOne, nTwo) / lengths > m_smoothCos;
        uint32_t from = a;
        for (const Corner& c : path) {
            addEdge(from, c.point, smooth);
            from = c.point;
        }
        addEdge(from, b, smooth);
        return true;
    }

    Mesh& m_work;
    const SplitParams& m_params;
    detail::FaceEditor m_editor;
    std::vector<MeshEdge> m_inputEdges;
    size_t m_inputPoints = 0;
    std::vector<std::vector<uint32_t>> m_facesOf;  // per point, the faces using it
    std::vector<uint32_t> m_origin;                // per face, the input face it came from
    std::unordered_map<uint64_t, uint32_t> m_edgeOf;
    std::unordered_map<uint32_t, std::vector<std::pair<double, uint32_t>>> m_stops;  // per input edge
    double m_smoothCos = 1.0;
};

}  // namespace

bool splitFaces(Mesh& mesh, const SplitParams& params, SplitResult* result, std::string* error) {
    if (result) *result = {};
    auto fail = [&](std::string message) {
        if (error) *error = std::move(message);
        return false;
    };
    if (params.subdivisions < 1 || params.subdivisions > kMaxSplitSubdivisions)
        return fail("subdivision " + std::to_string(params.subdivisions) + " is outside 1 to " +
                    std::to_string(kMaxSplitSubdivisions));
    if (!std::isfinite(params.smoothingAngle)) return fail("the smoothing angle is not finite");
    Mesh work = mesh;
    completeEdges(work, true);
    size_t grows = 0;
    for (size_t i = 0; i < params.points.size(); ++i) {
        const SplitPoint& p = params.points[i];
        const std::string which = "split point " + std::to_string(i);
        if (p.kind == SplitPoint::Kind::Edge) {
            if (p.index < 0 || uint64_t(p.index) >= work.edges.size())
                return fail(which + " is on edge " + std::to_string(p.index) + ", which the mesh does not have");
            if (!std::isfinite(p.fraction)) return fail(which + " has a fraction that is not finite");
            grows += size_t(params.subdivisions);
        } else {
            if (p.index >= 0 && uint64_t(p.index) >= work.faceCount())
                return fail(which + " is in face " + std::to_string(p.index) + ", which the mesh does not have");
            if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z))
                return fail(which + " has a position that is not finite");
            ++grows;
        }
    }
    if (grows > kMaxSplitPathPoints)
        return fail("the path has " + std::to_string(grows) + " points with its sections, more than " +
                    std::to_string(kMaxSplitPathPoints));
    if (work.points.size() + grows > kMaxSplitResultPoints) return fail("the split would make too many points");
    const size_t points0 = work.points.size(), edges0 = work.edges.size(), faces0 = work.faceCount();
    Splitter splitter(work, params);
    SplitResult r;
    splitter.run(r);
    Mesh out = splitter.editor().rebuild();
    r.newPoints = out.points.size() - points0;
    r.newEdges = out.edges.size() - edges0;
    r.newFaces = out.faceCount() - faces0;
    if (result) *result = r;
    mesh = std::move(out);
    return true;
}

}  // namespace pushpin::geom
