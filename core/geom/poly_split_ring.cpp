// core/geom/poly_split_ring.cpp: polySplitRing on a geom::Mesh.
#include "core/geom/poly_split_ring.h"

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

// A face-vertex of an edited face: its point and per-face-vertex data.
struct Corner {
    uint32_t point;
    glm::vec3 normal{0.0f};
    std::vector<int32_t> uvs;     // per UV set
    std::vector<int32_t> colors;  // per colour set
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
    const size_t uvSetCount = work.uvSets.size(), colorSetCount = work.colorSets.size();
    std::map<uint32_t, std::vector<std::vector<Corner>>> edited;
    auto editable = [&](uint32_t f) -> std::vector<std::vector<Corner>>& {
        auto [it, fresh] = edited.try_emplace(f);
        if (fresh)
            for (uint32_t l = work.faceLoopStarts[f]; l < work.faceLoopStarts[f + 1]; ++l) {
                std::vector<Corner>& loop = it->second.emplace_back();
                for (uint32_t fv = work.loopStarts[l]; fv < work.loopStarts[l + 1]; ++fv) {
                    Corner c{work.faceVertices[fv], {}, std::vector<int32_t>(uvSetCount, -1), std::vector<int32_t>(colorSetCount, -1)};
                    if (!work.normals.empty()) c.normal = work.normals[fv];
                    for (size_t s = 0; s < uvSetCount; ++s)
                        if (!work.uvSets[s].faceVertexUvs.empty()) c.uvs[s] = work.uvSets[s].faceVertexUvs[fv];
                    for (size_t s = 0; s < colorSetCount; ++s)
                        if (!work.colorSets[s].faceVertexColors.empty()) c.colors[s] = work.colorSets[s].faceVertexColors[fv];
                    loop.push_back(std::move(c));
                }
            }
        return it->second;
    };

    // New UVs: one per (UV set, pair of UVs, fraction), shared by the faces that agree.
    std::map<std::tuple<size_t, int32_t, int32_t, double>, int32_t> uvMade;
    auto midUv = [&](size_t set, int32_t a, int32_t b, double t) -> int32_t {
        if (a < 0 || b < 0) return -1;
        std::vector<glm::vec2>& uvs = work.uvSets[set].uvs;
        if (size_t(a) >= uvs.size() || size_t(b) >= uvs.size()) return -1;
        if (a == b) return a;
        const auto key = a < b ? std::make_tuple(set, a, b, t) : std::make_tuple(set, b, a, 1.0 - t);
        auto [it, fresh] = uvMade.try_emplace(key, int32_t(uvs.size()));
        if (fresh) uvs.push_back(glm::mix(uvs[size_t(a)], uvs[size_t(b)], float(t)));
        return it->second;
    };

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
            for (std::vector<Corner>& loop : editable(f))
                for (size_t i = 0; i < loop.size(); ++i) {
                    Corner& a = loop[i];
                    const Corner& b = loop[(i + 1) % loop.size()];
                    if (edgeKey(a.point, b.point) != edgeKey(p.from, p.to)) continue;
                    const double t = a.point == p.from ? p.fraction : 1.0 - p.fraction;
                    Corner c{np, glm::vec3(0.0f), std::vector<int32_t>(uvSetCount, -1), std::vector<int32_t>(colorSetCount, -1)};
                    for (size_t s = 0; s < uvSetCount; ++s) c.uvs[s] = midUv(s, a.uvs[s], b.uvs[s], t);
                    loop.insert(loop.begin() + std::ptrdiff_t(i + 1), std::move(c));
                    break;
                }
    };
    std::vector<std::pair<uint32_t, std::vector<std::vector<Corner>>>> appendedFaces;
    auto cutFace = [&](uint32_t f, uint32_t pa, uint32_t pb) {
        std::vector<std::vector<Corner>>& loops = editable(f);
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
        appendedFaces.push_back({f, {std::move(moved)}});
        addedEdges.push_back({pa, pb, true});
    };

    splitEdge(0);
    for (size_t k = 1; k < chain.size(); ++k) {
        splitEdge(k);
        if (chain[k].faceBefore >= 0) cutFace(uint32_t(chain[k].faceBefore), newPoint[k - 1], newPoint[k]);
    }
    if (closed && chain.front().faceBefore >= 0) cutFace(uint32_t(chain.front().faceBefore), newPoint.back(), newPoint.front());

    // Rebuild: faces in order (edited ones from their copies), then the appended parts.
    Mesh out = facelessCopy(work, std::move(work.points));
    const bool hasNormals = !work.normals.empty();
    auto emitLoop = [&](const std::vector<Corner>& loop) {
        for (const Corner& c : loop) {
            out.faceVertices.push_back(c.point);
            if (hasNormals) out.normals.push_back(c.normal);
            for (size_t s = 0; s < uvSetCount; ++s)
                if (!work.uvSets[s].faceVertexUvs.empty()) out.uvSets[s].faceVertexUvs.push_back(c.uvs[s]);
            for (size_t s = 0; s < colorSetCount; ++s)
                if (!work.colorSets[s].faceVertexColors.empty()) out.colorSets[s].faceVertexColors.push_back(c.colors[s]);
        }
        out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
    };
    for (size_t f = 0; f < work.faceCount(); ++f) {
        if (const auto it = edited.find(uint32_t(f)); it != edited.end()) {
            for (const std::vector<Corner>& loop : it->second) emitLoop(loop);
        } else {
            for (uint32_t l = work.faceLoopStarts[f]; l < work.faceLoopStarts[f + 1]; ++l) {
                const uint32_t begin = work.loopStarts[l], end = work.loopStarts[l + 1];
                out.faceVertices.insert(out.faceVertices.end(), work.faceVertices.begin() + begin, work.faceVertices.begin() + end);
                if (hasNormals) out.normals.insert(out.normals.end(), work.normals.begin() + begin, work.normals.begin() + end);
                for (size_t s = 0; s < uvSetCount; ++s) {
                    const std::vector<int32_t>& ids = work.uvSets[s].faceVertexUvs;
                    if (!ids.empty()) out.uvSets[s].faceVertexUvs.insert(out.uvSets[s].faceVertexUvs.end(), ids.begin() + begin, ids.begin() + end);
                }
                for (size_t s = 0; s < colorSetCount; ++s) {
                    const std::vector<int32_t>& ids = work.colorSets[s].faceVertexColors;
                    if (!ids.empty()) out.colorSets[s].faceVertexColors.insert(out.colorSets[s].faceVertexColors.end(), ids.begin() + begin, ids.begin() + end);
                }
                out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
            }
        }
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    for (const auto& [from, loops] : appendedFaces) {
        for (const std::vector<Corner>& loop : loops) emitLoop(loop);
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    out.edges = std::move(work.edges);
    out.edges.insert(out.edges.end(), addedEdges.begin(), addedEdges.end());
    if (result) {
        *result = {chain.size(), appendedFaces.size(), closed, std::vector<bool>(out.edges.size(), false)};
        for (uint32_t e : nearHalf) result->nearHalves[e] = true;
    }
    mesh = std::move(out);
    return true;
}

}  // namespace pushpin::geom
