// core/geom/poly_bevel.cpp: polyBevel (one flat segment) on a geom::Mesh.
#include "core/geom/poly_bevel.h"

#include "core/geom/detail/face_edit.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

namespace pushpin::geom {

namespace {

using detail::Corner;

struct Use {
    uint32_t face;
    uint32_t at;  // position in the face's outer loop of the edge's first point as the face runs it
};

}  // namespace

bool bevelEdges(Mesh& mesh, const BevelParams& params, BevelResult* result, std::string* error) {
    if (result) *result = {};
    auto fail = [&](const char* message) {
        if (error) *error = message;
        return false;
    };
    if (!std::isfinite(params.offset) || params.offset < 0.0) return fail("the bevel offset is not a finite, non-negative number");
    if (!std::isfinite(params.smoothingAngle)) return fail("the smoothing angle is not finite");
    Mesh work = mesh;
    completeEdges(work, true);
    std::unordered_map<uint64_t, uint32_t> edgeOf;
    for (size_t e = 0; e < work.edges.size(); ++e) edgeOf.emplace(edgeKey(work.edges[e].v0, work.edges[e].v1), uint32_t(e));
    std::vector<std::vector<Use>> uses(work.edges.size());
    for (size_t f = 0; f < work.faceCount(); ++f)
        for (uint32_t l = work.faceLoopStarts[f]; l < work.faceLoopStarts[f + 1]; ++l) {
            const std::span<const uint32_t> lp = work.loop(l);
            for (size_t k = 0; k < lp.size(); ++k) {
                const auto it = edgeOf.find(edgeKey(lp[k], lp[(k + 1) % lp.size()]));
                if (it != edgeOf.end() && l == work.faceLoopStarts[f]) uses[it->second].push_back({uint32_t(f), uint32_t(k)});
                else if (it != edgeOf.end()) uses[it->second].push_back({uint32_t(f), UINT32_MAX});  // on a hole
            }
        }
    // The edges bevelled: selected, with exactly two faces running them opposite ways on their outer loops.
    std::vector<bool> bevelled(work.edges.size(), false);
    std::vector<bool> atPoint(work.points.size(), false);
    BevelResult r;
    for (size_t e = 0; e < std::min(params.edges.size(), work.edges.size()); ++e) {
        if (!params.edges[e]) continue;
        const std::vector<Use>& u = uses[e];
        const bool manifold = u.size() == 2 && u[0].at != UINT32_MAX && u[1].at != UINT32_MAX && u[0].face != u[1].face &&
                              work.faceOuterLoop(u[0].face)[u[0].at] != work.faceOuterLoop(u[1].face)[u[1].at];
        if (!manifold) {
            ++r.skippedEdges;
            continue;
        }
        bevelled[e] = true;
        ++r.bevelledEdges;
        atPoint[work.edges[e].v0] = atPoint[work.edges[e].v1] = true;
    }
    if (r.bevelledEdges == 0) {
        if (result) *result = r;
        return true;
    }
    for (size_t f = 0; f < work.faceCount(); ++f) {
        if (work.holeCount(f) == 0) continue;
        for (uint32_t fv = work.faceVertexBegin(f); fv < work.faceVertexEnd(f); ++fv)
            if (atPoint[work.faceVertices[fv]]) return fail("a face with holes meets a bevelled edge");
    }

    // Each point's offset: at most half its shortest edge.
    std::vector<double> shortest(work.points.size(), std::numeric_limits<double>::infinity());
    for (const MeshEdge& e : work.edges) {
        const double len = glm::length(glm::dvec3(work.points[e.v1]) - glm::dvec3(work.points[e.v0]));
        shortest[e.v0] = std::min(shortest[e.v0], len);
        shortest[e.v1] = std::min(shortest[e.v1], len);
    }
    auto offsetAt = [&](uint32_t v) {
        const double half = 0.5 * (std::isfinite(shortest[v]) ? shortest[v] : 0.0);
        return params.offsetAsFraction ? std::min(1.0, params.offset) * half : std::min(params.offset, half);
    };
    auto edgeId = [&](uint32_t a, uint32_t b) { return edgeOf.at(edgeKey(a, b)); };

    // Pass 1: the points slid along unselected edges, one per (point, edge), shared by the faces.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> slid;  // (point, edge) → new point
    auto slidePoint = [&](uint32_t v, uint32_t toward) -> uint32_t {
        const uint32_t e = edgeId(v, toward);
        auto [it, fresh] = slid.try_emplace({v, e}, uint32_t(work.points.size()));
        if (fresh) {
            const glm::dvec3 pv(work.points[v]), d = glm::dvec3(work.points[toward]) - pv;
            const double len = glm::length(d);
            work.points.push_back(glm::vec3(len > 0.0 ? pv + d * (offsetAt(v) / len) : pv));
        }
        return it->second;
    };
    const size_t faceCount = work.faceCount();
    std::vector<std::pair<uint32_t, uint32_t>> neededSlides;
    for (size_t f = 0; f < faceCount; ++f) {
        const std::span<const uint32_t> lp = work.faceOuterLoop(f);
        const size_t n = lp.size();
        for (size_t k = 0; k < n; ++k) {
            const uint32_t v = lp[k], u = lp[(k + n - 1) % n], w = lp[(k + 1) % n];
            if (!atPoint[v]) continue;
            const bool inB = bevelled[edgeId(u, v)], outB = bevelled[edgeId(v, w)];
            if (inB != outB) slidePoint(v, inB ? w : u);
        }
    }

    // Pass 2: the faces' new corners.
    detail::FaceEditor editor(work);
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> cornerPoint;  // (face, loop position) → its one new point
    for (size_t f = 0; f < faceCount; ++f) {
        const std::vector<uint32_t> lp(work.faceOuterLoop(f).begin(), work.faceOuterLoop(f).end());
        const size_t n = lp.size();
        if (std::none_of(lp.begin(), lp.end(), [&](uint32_t v) { return atPoint[v]; })) continue;
        const std::vector<Corner> old = editor.face(uint32_t(f)).front();
        std::vector<Corner> loop;
        for (size_t k = 0; k < n; ++k) {
            const uint32_t v = lp[k], u = lp[(k + n - 1) % n], w = lp[(k + 1) % n];
            const Corner& cv = old[k];
            if (!atPoint[v]) {
                loop.push_back(cv);
                continue;
            }
            const Corner& cu = old[(k + n - 1) % n];
            const Corner& cw = old[(k + 1) % n];
            const glm::dvec3 pv(work.points[v]), pu(work.points[u]), pw(work.points[w]);
            const double lu = glm::length(pu - pv), lw = glm::length(pw - pv);
            const double a = lu > 0.0 ? offsetAt(v) / lu : 0.0, b = lw > 0.0 ? offsetAt(v) / lw : 0.0;
            const Corner along[3] = {cv, cu, cw};
            auto moved = [&](double toU, double toW, uint32_t point) {
                const double weights[3] = {1.0 - toU - toW, toU, toW};
                Corner c = editor.cornerFromWeights(along, weights, point);
                c.colors = cv.colors;
                return c;
            };
            const bool inB = bevelled[edgeId(u, v)], outB = bevelled[edgeId(v, w)];
            if (inB && outB) {
                const uint32_t p = uint32_t(work.points.size());
                work.points.push_back(glm::vec3(pv + (pu - pv) * a + (pw - pv) * b));
                loop.push_back(moved(a, b, p));
                cornerPoint[{uint32_t(f), uint32_t(k)}] = p;
            } else if (inB || outB) {
                const uint32_t p = slid.at({v, edgeId(v, inB ? w : u)});
                loop.push_back(inB ? moved(0.0, b, p) : moved(a, 0.0, p));
                cornerPoint[{uint32_t(f), uint32_t(k)}] = p;
            } else {
                const auto in = slid.find({v, edgeId(u, v)}), out = slid.find({v, edgeId(v, w)});
                if (in != slid.end()) loop.push_back(moved(a, 0.0, in->second));
                if (in == slid.end() || out == slid.end()) loop.push_back(cv);
                if (out != slid.end()) loop.push_back(moved(0.0, b, out->second));
            }
        }
        editor.face(uint32_t(f)).front() = std::move(loop);
    }

    auto plain = [&](uint32_t point) {
        return Corner{point, glm::vec3(0.0f), std::vector<int32_t>(work.uvSets.size(), -1),
                      std::vector<int32_t>(work.colorSets.size(), -1)};
    };
    // One quad per bevelled edge, between the two faces' moved edges.
    for (size_t e = 0; e < work.edges.size(); ++e) {
        if (!bevelled[e]) continue;
        const Use& one = uses[e][0];
        const Use& two = uses[e][1];
        const size_t n1 = work.faceOuterLoop(one.face).size(), n2 = work.faceOuterLoop(two.face).size();
        const uint32_t oneA = cornerPoint.at({one.face, one.at}), oneB = cornerPoint.at({one.face, uint32_t((one.at + 1) % n1)});
        const uint32_t twoB = cornerPoint.at({two.face, two.at}), twoA = cornerPoint.at({two.face, uint32_t((two.at + 1) % n2)});
        editor.append({{plain(oneB), plain(oneA), plain(twoA), plain(twoB)}});
        ++r.newFaces;
    }
    // One polygon per point whose moved corners leave a gap round it.
    std::vector<std::vector<Use>> cornersAt(work.points.size());
    for (size_t f = 0; f < faceCount; ++f) {
        const std::span<const uint32_t> lp = work.faceOuterLoop(f);
        for (size_t k = 0; k < lp.size(); ++k)
            if (lp[k] < atPoint.size() && atPoint[lp[k]]) cornersAt[lp[k]].push_back({uint32_t(f), uint32_t(k)});
    }
    for (uint32_t v = 0; v < atPoint.size(); ++v) {
        if (!atPoint[v] || cornersAt[v].empty()) continue;
        // The faces round v in turn: the next one runs this one's outgoing edge at v as its incoming one.
        std::unordered_map<uint32_t, size_t> byIncoming;  // the point before v → that corner
        for (size_t i = 0; i < cornersAt[v].size(); ++i) {
            const Use& d = cornersAt[v][i];
            const std::span<const uint32_t> lq = work.faceOuterLoop(d.face);
            byIncoming.emplace(lq[(d.at + lq.size() - 1) % lq.size()], i);
        }
        std::vector<Use> ring{cornersAt[v].front()};
        bool closed = false;
        while (ring.size() <= cornersAt[v].size()) {
            const Use& c = ring.back();
            const std::span<const uint32_t> lp = work.faceOuterLoop(c.face);
            const uint32_t w = lp[(c.at + 1) % lp.size()];
            const auto found = byIncoming.find(w);
            const Use* next = found == byIncoming.end() ? nullptr : &cornersAt[v][found->second];
            if (next && next->face == c.face && next->at == c.at) next = nullptr;
            if (!next) break;
            if (next->face == ring.front().face && next->at == ring.front().at) {
                closed = true;
                break;
            }
            ring.push_back(*next);
        }
        if (!closed) continue;  // a border point: its gap opens onto the border
        // The corners' new points in ring order, then as a polygon facing out.
        std::vector<uint32_t> cycle;
        for (const Use& c : ring) {
            const std::span<const uint32_t> lp = work.faceOuterLoop(c.face);
            const size_t n = lp.size();
            const uint32_t u = lp[(c.at + n - 1) % n], w = lp[(c.at + 1) % n];
            const bool inB = bevelled[edgeId(u, v)], outB = bevelled[edgeId(v, w)];
            if (inB || outB) {
                cycle.push_back(cornerPoint.at({c.face, c.at}));
                continue;
            }
            const auto in = slid.find({v, edgeId(u, v)}), out = slid.find({v, edgeId(v, w)});
            if (in != slid.end()) cycle.push_back(in->second);
            if (in == slid.end() || out == slid.end()) cycle.push_back(v);
            if (out != slid.end()) cycle.push_back(out->second);
        }
        std::vector<uint32_t> distinct;
        for (uint32_t p : cycle)
            if (distinct.empty() || distinct.back() != p) distinct.push_back(p);
        while (distinct.size() > 1 && distinct.front() == distinct.back()) distinct.pop_back();
        if (distinct.size() < 3) continue;
        std::reverse(distinct.begin(), distinct.end());  // the ring runs clockwise seen from outside
        std::vector<Corner> patch;
        for (uint32_t p : distinct) patch.push_back(plain(p));
        editor.append({std::move(patch)});
        ++r.newFaces;
    }

    // Edges: the ones that stay keep their flags; new ones are soft below the smoothing angle.
    std::unordered_map<uint64_t, bool> flags;
    for (const MeshEdge& e : work.edges) flags.emplace(edgeKey(e.v0, e.v1), e.smooth);
    Mesh out = editor.rebuild();
    out.edges = deriveEdges(out, true);
    std::unordered_map<uint64_t, std::vector<uint32_t>> facesOn;
    for (size_t f = 0; f < out.faceCount(); ++f) {
        const std::span<const uint32_t> lp = out.faceOuterLoop(f);
        for (size_t k = 0; k < lp.size(); ++k) facesOn[edgeKey(lp[k], lp[(k + 1) % lp.size()])].push_back(uint32_t(f));
    }
    const double cosLimit = std::cos(std::clamp(params.smoothingAngle, 0.0, 3.14159265358979323846));
    for (MeshEdge& e : out.edges) {
        const uint64_t key = edgeKey(e.v0, e.v1);
        if (const auto it = flags.find(key); it != flags.end()) {
            e.smooth = it->second;
            continue;
        }
        const std::vector<uint32_t>& fs = facesOn[key];
        e.smooth = fs.size() == 2 && glm::dot(out.faceNormal(fs[0]), out.faceNormal(fs[1])) > cosLimit;
    }
    removeUnusedPoints(out);
    if (result) *result = r;
    mesh = std::move(out);
    return true;
}

}  // namespace pushpin::geom
