// core/geom/poly_extrude_edge.cpp: polyExtrudeEdge on a geom::Mesh.
#include "core/geom/poly_extrude_edge.h"

#include "core/geom/finite.h"
#include "core/geom/union_find.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pushpin::geom {

namespace {

struct Region {
    std::vector<uint32_t> edges;   // ascending
    std::vector<uint32_t> points;  // first-use order
};

}  // namespace

bool extrudeEdges(Mesh& mesh, const ExtrudeEdgesParams& params, ExtrudeEdgesResult* result, std::string* error) {
    if (result) *result = {};
    auto fail = [&](const char* message) {
        if (error) *error = message;
        return false;
    };
    Mesh work = mesh;
    completeEdges(work, true);
    const size_t edgeCount = work.edges.size();
    std::vector<uint32_t> selected;
    for (size_t e = 0; e < std::min(edgeCount, params.edges.size()); ++e)
        if (params.edges[e]) selected.push_back(uint32_t(e));
    if (selected.empty()) return true;
    const int divisions = std::max(1, params.divisions);
    const glm::dmat4 objectFromSpace = glm::inverse(params.space);
    if (!isFinite(params.space) || !isFinite(objectFromSpace)) return fail("the extrusion's space is not invertible");

    // Regions: chains of selected edges through shared points (or each edge alone).
    std::vector<Region> regions;
    {
        LowestRootSets sets(edgeCount);
        if (params.keepFacesTogether) {
            std::unordered_map<uint32_t, uint32_t> edgeAt;  // point → first selected edge on it
            for (uint32_t e : selected)
                for (uint32_t p : {uint32_t(work.edges[e].v0), uint32_t(work.edges[e].v1)}) {
                    const auto [it, fresh] = edgeAt.try_emplace(p, e);
                    if (!fresh) sets.join(it->second, e);
                }
        }
        std::unordered_map<uint32_t, size_t> regionOf;
        std::unordered_map<uint32_t, size_t> pointRegion;  // a point's region once listed (points are in one region each)
        for (uint32_t e : selected) {
            const auto [it, fresh] = regionOf.try_emplace(sets.find(e), regions.size());
            if (fresh) regions.emplace_back();
            Region& r = regions[it->second];
            r.edges.push_back(e);
            for (uint32_t p : {uint32_t(work.edges[e].v0), uint32_t(work.edges[e].v1)}) {
                // Kept together, a point is in one region; apart, each edge lists its own two.
                if (!params.keepFacesTogether) {
                    if (r.points.empty() || r.points.back() != p) r.points.push_back(p);
                    continue;
                }
                if (pointRegion.try_emplace(p, it->second).second) r.points.push_back(p);
            }
        }
    }
    size_t newPoints = 0;
    for (const Region& r : regions) newPoints += r.points.size() * size_t(divisions);
    if (work.points.size() + newPoints > kMaxEdgeExtrudedPoints) return fail("the extrusion would make too many points");

    // Each selected edge's direction in the first face that runs along it, and that face.
    std::unordered_map<uint64_t, uint32_t> selectedEdge;
    for (uint32_t e : selected) selectedEdge.emplace(edgeKey(work.edges[e].v0, work.edges[e].v1), e);
    std::unordered_map<uint32_t, std::pair<uint32_t, uint32_t>> along;  // edge → (a, b) as its face runs it
    std::unordered_map<uint32_t, std::vector<uint32_t>> facesOn;
    for (size_t f = 0; f < work.faceCount(); ++f)
        for (uint32_t l = work.faceLoopStarts[f]; l < work.faceLoopStarts[f + 1]; ++l) {
            const std::span<const uint32_t> lp = work.loop(l);
            for (size_t k = 0; k < lp.size(); ++k) {
                const auto it = selectedEdge.find(edgeKey(lp[k], lp[(k + 1) % lp.size()]));
                if (it == selectedEdge.end()) continue;
                along.try_emplace(it->second, lp[k], lp[(k + 1) % lp.size()]);
                facesOn[it->second].push_back(uint32_t(f));
            }
        }

    auto spacePoint = [&](uint32_t p) { return glm::dvec3(params.space * glm::dvec4(glm::dvec3(work.points[p]), 1.0)); };
    // Per region, where each of its points goes (object space).
    std::vector<std::vector<glm::dvec3>> ends(regions.size());
    for (size_t r = 0; r < regions.size(); ++r) {
        const Region& reg = regions[r];
        glm::dvec3 z(0.0), x(0.0), centre(0.0);
        for (uint32_t e : reg.edges) {
            for (uint32_t f : facesOn[e]) {
                const std::span<const uint32_t> outer = work.faceOuterLoop(f);
                glm::dvec3 n(0.0);
                for (size_t k = 0; k < outer.size(); ++k) n += glm::cross(spacePoint(outer[k]), spacePoint(outer[(k + 1) % outer.size()]));
                if (glm::length(n) > 0.0) z += glm::normalize(n);
            }
            const auto ab = along.find(e);
            const uint32_t a = ab != along.end() ? ab->second.first : work.edges[e].v0;
            const uint32_t b = ab != along.end() ? ab->second.second : work.edges[e].v1;
            const glm::dvec3 d = spacePoint(b) - spacePoint(a);
            // Chains may run both ways: line each edge up with the first before adding it.
            x += glm::dot(d, x) < 0.0 ? -d : d;
        }
        for (uint32_t p : reg.points) centre += spacePoint(p);
        centre /= double(reg.points.size());
        z = glm::length(z) > 0.0 ? glm::normalize(z) : glm::dvec3(0.0, 0.0, 1.0);
        x -= z * glm::dot(x, z);
        if (!(glm::length(x) > 1e-300))
            x = std::abs(z.x) < 0.9 ? glm::cross(z, glm::dvec3(1, 0, 0)) : glm::cross(z, glm::dvec3(0, 1, 0));
        x = glm::normalize(x);
        const glm::dmat3 frame(x, glm::cross(z, x), z);
        const glm::dmat3 toLocal = glm::transpose(frame);
        for (uint32_t p : reg.points) {
            const glm::dvec3 pos = spacePoint(p);
            const glm::dvec3 moved = centre + frame * (params.localScale * (toLocal * (pos - centre))) + frame * params.localTranslate;
            const glm::dvec3 end = glm::dvec3(objectFromSpace * (params.transform * glm::dvec4(moved, 1.0)));
            if (!isFinite(end)) return fail("the extruded edges' points are not finite");
            ends[r].push_back(end);
        }
    }

    // Points, faces and edges, region by region and ring by ring.
    std::unordered_map<uint64_t, bool> made;
    for (const MeshEdge& e : work.edges) made.emplace(edgeKey(e.v0, e.v1), true);
    auto addEdge = [&](uint32_t a, uint32_t b, bool smooth) {
        if (made.emplace(edgeKey(a, b), true).second) work.edges.push_back({a, b, smooth});
    };
    size_t walls = 0;
    for (size_t r = 0; r < regions.size(); ++r) {
        const Region& reg = regions[r];
        std::unordered_map<uint32_t, size_t> slot;
        for (size_t i = 0; i < reg.points.size(); ++i) slot.emplace(reg.points[i], i);
        std::vector<uint32_t> below(reg.points);  // the ring the next one stands on
        for (int k = 1; k <= divisions; ++k) {
            const double t = double(k) / double(divisions);
            std::vector<uint32_t> ring;
            for (size_t i = 0; i < reg.points.size(); ++i) {
                const glm::dvec3 from(work.points[reg.points[i]]);
                ring.push_back(uint32_t(work.points.size()));
                work.points.push_back(glm::vec3(from + (ends[r][i] - from) * t));
            }
            for (uint32_t e : reg.edges) {
                const auto ab = along.find(e);
                const uint32_t a = ab != along.end() ? ab->second.first : work.edges[e].v0;
                const uint32_t b = ab != along.end() ? ab->second.second : work.edges[e].v1;
                const size_t ia = slot.at(a), ib = slot.at(b);
                work.addFace({below[ib], below[ia], ring[ia], ring[ib]});
                ++walls;
                addEdge(below[ia], ring[ia], true);
                addEdge(below[ib], ring[ib], true);
                addEdge(ring[ia], ring[ib], work.edges[e].smooth);
            }
            below = std::move(ring);
        }
    }
    if (result) *result = {regions.size(), walls};
    mesh = std::move(work);
    return true;
}

}  // namespace pushpin::geom
