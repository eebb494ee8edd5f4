// core/geom/poly_split_ring.cpp: polySplitRing on a geom::Mesh.
#include "core/geom/poly_split_ring.h"

#include "core/geom/detail/face_edit.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_map>

namespace pushpin::geom {

namespace {

// One step of the walk: the ring edge, its end the fraction is measured from, and the fraction.
struct RingPoint {
    uint32_t edge;
    uint32_t from, to;
    double fraction;
    int64_t faceBefore = -1;  // the quad crossed to reach this edge (-1 for the walk's first point)
};

}  // namespace

bool splitRing(Mesh& mesh, const SplitRingParams& params, SplitRingResult* result, std::string* error) {
    if (result) *result = {};
    auto fail = [&](std::string message) {
        if (error) *error = std::move(message);
        return false;
    };
    if (!std::isfinite(params.weight)) return fail("the split weight is not finite");
    const double weight = std::clamp(params.weight, 0.0, 1.0);
    Mesh work = mesh;
    completeEdges(work, true);
    std::vector<bool> ring(work.edges.size(), false);
    for (size_t e = 0; e < std::min(ring.size(), params.edges.size()); ++e) ring[e] = params.edges[e];
    int64_t root = params.rootEdge;
    if (root < 0)
        for (size_t e = 0; e < ring.size() && root < 0; ++e)
            if (ring[e]) root = int64_t(e);
    if (root < 0) return true;  // nothing selected
    if (size_t(root) >= ring.size() || !ring[size_t(root)])
        return fail("the root edge e[" + std::to_string(root) + "] is not one of the ring's edges");

    std::unordered_map<uint64_t, uint32_t> edgeOf;
    for (size_t e = 0; e < work.edges.size(); ++e) edgeOf.emplace(edgeKey(work.edges[e].v0, work.edges[e].v1), uint32_t(e));
    // Faces on each ring edge, by any of their loops (the walk itself crosses only quads without
    // holes; a split edge's point goes into every loop along it).
    std::unordered_map<uint32_t, std::vector<uint32_t>> facesOn;
    for (size_t f = 0; f < work.faceCount(); ++f)
        for (uint32_t l = work.faceLoopStarts[f]; l < work.faceLoopStarts[f + 1]; ++l) {
            const std::span<const uint32_t> lp = work.loop(l);
            for (size_t k = 0; k < lp.size(); ++k)
                if (const auto it = edgeOf.find(edgeKey(lp[k], lp[(k + 1) % lp.size()])); it != edgeOf.end() && ring[it->second])
                    facesOn[it->second].push_back(uint32_t(f));
        }

    // The point opposite `p` across quad f, or nothing when f is not a plain quad or the opposite
    // edge is not in the ring.
    auto across = [&](const RingPoint& p, uint32_t f) -> std::optional<RingPoint> {
        if (work.holeCount(f) != 0) return std::nullopt;
        const std::span<const uint32_t> q = work.faceOuterLoop(f);
        if (q.size() != 4) return std::nullopt;
        for (size_t i = 0; i < 4; ++i) {
            const uint32_t u = q[i], w = q[(i + 1) % 4];
            if (edgeKey(u, w) != edgeKey(p.from, p.to)) continue;
            const uint32_t opposite2 = q[(i + 2) % 4], opposite3 = q[(i + 3) % 4];  // joined to w and u
            const auto it = edgeOf.find(edgeKey(opposite2, opposite3));
            if (it == edgeOf.end() || !ring[it->second]) return std::nullopt;
            RingPoint next;
            next.edge = it->second;
            next.from = p.from == u ? opposite3 : opposite2;
            next.to = p.from == u ? opposite2 : opposite3;
            next.fraction = p.fraction;
            next.faceBefore = f;
            return next;
        }
        return std::nullopt;
    };
    auto otherFace = [&](uint32_t edge, int64_t notThis) -> int64_t {
        for (uint32_t f : facesOn[edge])
            if (int64_t(f) != notThis) return f;
        return -1;
    };

    const MeshEdge& r = work.edges[size_t(root)];
    RingPoint start{uint32_t(root), params.fromFirst ? r.v0 : r.v1, params.fromFirst ? r.v1 : r.v0, weight};
    // The first face: the one in which the root runs in its own direction.
    int64_t firstFace = -1;
    for (uint32_t f : facesOn[uint32_t(root)]) {
        const std::span<const uint32_t> lp = work.faceOuterLoop(f);
        for (size_t k = 0; k < lp.size(); ++k)
            if (lp[k] == r.v0 && lp[(k + 1) % lp.size()] == r.v1) firstFace = f;
    }
    if (firstFace < 0 && !facesOn[uint32_t(root)].empty()) firstFace = facesOn[uint32_t(root)].front();
    std::vector<RingPoint> forward{start};
    bool closed = false;
    std::vector<bool> visited(work.edges.size(), false);
    visited[size_t(root)] = true;
    for (int64_t f = firstFace; f >= 0;) {
        std::optional<RingPoint> next = across(forward.back(), uint32_t(f));
        if (!next) break;
        if (next->edge == uint32_t(root)) {
            closed = true;
            forward.front().faceBefore = f;
            break;
        }
        if (visited[next->edge]) break;
        visited[next->edge] = true;
        forward.push_back(*next);
        f = otherFace(next->edge, f);
    }
    std::vector<RingPoint> chain;
    if (!closed) {
        // Walk the other way from the root too; the loop runs from that far end to the first one.
        std::vector<RingPoint> backward;
        RingPoint at = start;
        for (int64_t f = otherFace(uint32_t(root), firstFace); f >= 0;) {
            std::optional<RingPoint> next = across(at, uint32_t(f));
            if (!next || visited[next->edge]) break;
            visited[next->edge] = true;
            backward.push_back(*next);
            at = *next;
            f = otherFace(next->edge, f);
        }
        // Reversed, each point's "face before" is the face after it in the backward walk.
        for (size_t i = backward.size(); i-- > 0;) {
            RingPoint p = backward[i];
            p.faceBefore = i + 1 < backward.size() ? backward[i + 1].faceBefore : -1;
            chain.push_back(p);
        }
        RingPoint rootPoint = start;
        rootPoint.faceBefore = backward.empty() ? -1 : backward.front().faceBefore;
        chain.push_back(rootPoint);
        chain.insert(chain.end(), forward.begin() + 1, forward.end());
    } else {
        chain = forward;
    }
    if (chain.size() < 2 && !closed) return fail("the ring crosses no quad");
    if (work.points.size() + chain.size() > kMaxSplitPoints) return fail("the split would make too many points");

    // Editable copies of the faces the loop touches: the crossed quads and every face on a split edge.
    detail::FaceEditor editor(work);
    using detail::Corner;

    std::vector<uint32_t> newPoint(chain.size());
    std::vector<uint32_t> nearHalf;
    std::vector<MeshEdge> addedEdges;
    auto splitEdge = [&](size_t k) {
        const RingPoint& p = chain[k];
        const uint32_t np = uint32_t(work.points.size());
        newPoint[k] = np;
        work.points.push_back(glm::mix(work.points[p.from], work.points[p.to], float(p.fraction)));
        MeshEdge& e = work.edges[p.edge];
        const uint32_t v1 = e.v1;
        // The half towards `from`: the kept index when `from` is the edge's first point, else the
        // new half (its index once appended after the existing edges).
        nearHalf.push_back(p.from == e.v0 ? p.edge : uint32_t(work.edges.size() + addedEdges.size()));
        addedEdges.push_back({np, v1, e.smooth});
        e.v1 = np;
        // Insert the point into every loop that runs along the edge.
        for (uint32_t f : facesOn[p.edge])
            for (std::vector<Corner>& loop : editor.face(f))
                for (size_t i = 0; i < loop.size(); ++i) {
                    Corner& a = loop[i];
                    const Corner& b = loop[(i + 1) % loop.size()];
                    if (edgeKey(a.point, b.point) != edgeKey(p.from, p.to)) continue;
                    const double t = a.point == p.from ? p.fraction : 1.0 - p.fraction;
                    loop.insert(loop.begin() + std::ptrdiff_t(i + 1), editor.cornerOnEdge(a, b, np, t));
                    break;
                }
    };
    size_t appendedFaces = 0;
    auto cutFace = [&](uint32_t f, uint32_t pa, uint32_t pb) {
        detail::FaceLoops& loops = editor.face(f);
        std::vector<Corner>& outer = loops.front();
        size_t ia = outer.size(), ib = outer.size();
        for (size_t i = 0; i < outer.size(); ++i) {
            if (outer[i].point == pa) ia = i;
            if (outer[i].point == pb) ib = i;
        }
        if (ia == outer.size() || ib == outer.size()) return;
        std::vector<Corner> one, two;  // ia → ib and ib → ia
        for (size_t i = ia;; i = (i + 1) % outer.size()) {
            one.push_back(outer[i]);
            if (i == ib) break;
        }
        for (size_t i = ib;; i = (i + 1) % outer.size()) {
            two.push_back(outer[i]);
            if (i == ia) break;
        }
        // The part from the new point back round to the earlier one keeps the face; the part
        // the walk cut off (earlier point forward to the new one) is appended.
        const uint32_t firstPoint = work.faceVertices[work.faceVertexBegin(f)];
        std::vector<Corner>& kept = two;
        std::vector<Corner>& moved = one;
        // Keep the kept part starting where the face started, when it holds that corner.
        const auto at = std::find_if(kept.begin(), kept.end(), [&](const Corner& c) { return c.point == firstPoint; });
        if (at != kept.end()) std::rotate(kept.begin(), at, kept.end());
        outer = std::move(kept);
        editor.append({std::move(moved)});
        ++appendedFaces;
        addedEdges.push_back({pa, pb, true});
    };

    splitEdge(0);
    for (size_t k = 1; k < chain.size(); ++k) {
        splitEdge(k);
        if (chain[k].faceBefore >= 0) cutFace(uint32_t(chain[k].faceBefore), newPoint[k - 1], newPoint[k]);
    }
    if (closed && chain.front().faceBefore >= 0) cutFace(uint32_t(chain.front().faceBefore), newPoint.back(), newPoint.front());

    // Faces in order (edited ones from their copies), then the appended parts.
    work.edges.insert(work.edges.end(), addedEdges.begin(), addedEdges.end());
    Mesh out = editor.rebuild();
    if (result) {
        *result = {chain.size(), appendedFaces, closed, std::vector<bool>(out.edges.size(), false)};
        for (uint32_t e : nearHalf) result->nearHalves[e] = true;
    }
    mesh = std::move(out);
    return true;
}

}  // namespace pushpin::geom
