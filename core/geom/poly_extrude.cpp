// core/geom/poly_extrude.cpp: polyExtrudeFace on a geom::Mesh.
#include "core/geom/poly_extrude.h"

#include "core/geom/finite.h"
#include "core/geom/union_find.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pushpin::geom {

namespace {

// A directed boundary edge a→b of a region face, with the face-vertices it runs between.
struct BoundaryEdge {
    uint32_t a, b;
    uint32_t fvA, fvB;
};

// An edge of a region's faces, as the first face to use it runs it.
struct RegionEdge {
    uint32_t a, b;
    bool boundary;  // used by only one face of the region
};

struct Region {
    std::vector<uint32_t> faces;            // ascending
    std::vector<uint32_t> points;           // first-use order
    std::unordered_map<uint32_t, size_t> slot;  // point → its index in `points`
    std::vector<uint32_t> boundaryPoints;   // first-use order
    std::vector<BoundaryEdge> boundary;     // face order, loop order
    std::vector<RegionEdge> edges;          // every edge once, face order, loop order
};

}  // namespace

bool extrudeFaces(Mesh& mesh, const ExtrudeFacesParams& params, ExtrudeFacesResult* result, std::string* error) {
    const size_t faceCount = mesh.faceCount();
    std::vector<uint32_t> selected;
    for (size_t f = 0; f < std::min(faceCount, params.faces.size()); ++f)
        if (params.faces[f]) selected.push_back(uint32_t(f));
    if (result) *result = {};
    if (selected.empty()) return true;
    const int divisions = std::max(1, params.divisions);

    // Regions.
    std::vector<int64_t> slotOf(faceCount, -1);
    for (size_t i = 0; i < selected.size(); ++i) slotOf[selected[i]] = int64_t(i);
    LowestRootSets uf(selected.size());  // selected faces joined through shared edges
    if (params.keepFacesTogether) {
        std::unordered_map<uint64_t, uint32_t> firstUse;  // edge → slot of the first selected face on it
        for (size_t i = 0; i < selected.size(); ++i) {
            const uint32_t f = selected[i];
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                const std::span<const uint32_t> lp = mesh.loop(l);
                for (size_t k = 0; k < lp.size(); ++k) {
                    auto [it, fresh] = firstUse.try_emplace(edgeKey(lp[k], lp[(k + 1) % lp.size()]), uint32_t(i));
                    if (!fresh) uf.join(it->second, uint32_t(i));
                }
            }
        }
    }
    std::vector<Region> regions;
    std::vector<int64_t> regionOfRoot(selected.size(), -1);
    for (size_t i = 0; i < selected.size(); ++i) {
        const uint32_t root = uf.find(uint32_t(i));
        if (regionOfRoot[root] < 0) {
            regionOfRoot[root] = int64_t(regions.size());
            regions.emplace_back();
        }
        regions[size_t(regionOfRoot[root])].faces.push_back(selected[i]);
    }

    // Points and boundary of each region.
    size_t newPoints = 0;
    std::vector<uint32_t> mark(mesh.points.size(), UINT32_MAX);
    for (size_t r = 0; r < regions.size(); ++r) {
        Region& reg = regions[r];
        std::unordered_map<uint64_t, int> uses;
        for (uint32_t f : reg.faces)
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                const std::span<const uint32_t> lp = mesh.loop(l);
                for (size_t k = 0; k < lp.size(); ++k) {
                    ++uses[edgeKey(lp[k], lp[(k + 1) % lp.size()])];
                    if (mark[lp[k]] != uint32_t(r)) {
                        mark[lp[k]] = uint32_t(r);
                        reg.slot.emplace(lp[k], reg.points.size());
                        reg.points.push_back(lp[k]);
                    }
                }
            }
        std::unordered_map<uint32_t, bool> onBoundary;
        for (uint32_t f : reg.faces)
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                const std::span<const uint32_t> lp = mesh.loop(l);
                const uint32_t start = mesh.loopStarts[l];
                for (size_t k = 0; k < lp.size(); ++k) {
                    const size_t k1 = (k + 1) % lp.size();
                    int& count = uses[edgeKey(lp[k], lp[k1])];
                    const bool boundary = count == 1;
                    if (count > 0) reg.edges.push_back({lp[k], lp[k1], boundary});
                    count = 0;  // listed: later uses of the edge are not listed again
                    if (!boundary) continue;
                    reg.boundary.push_back({lp[k], lp[k1], start + uint32_t(k), start + uint32_t(k1)});
                    onBoundary[lp[k]] = true;
                    onBoundary[lp[k1]] = true;
                }
            }
        for (uint32_t p : reg.points)
            if (onBoundary.count(p)) reg.boundaryPoints.push_back(p);
        newPoints += reg.points.size() + size_t(divisions - 1) * reg.boundaryPoints.size();
        if (mesh.points.size() + newPoints > kMaxExtrudedPoints || size_t(divisions) > kMaxExtrudedPoints) {
            if (error)
                *error = "the extrusion would make more than " + std::to_string(kMaxExtrudedPoints) + " points";
            return false;
        }
    }

    // Cap positions, worked out in the move space.
    const std::vector<glm::vec3> original = mesh.points;
    const glm::dmat4 objectFromSpace = glm::inverse(params.space);
    if (!isFinite(params.space) || !isFinite(objectFromSpace)) {
        if (error) *error = "the extrusion's space is not invertible";
        return false;
    }
    std::unordered_map<uint32_t, glm::dvec3> inSpace;
    auto spacePoint = [&](uint32_t p) {
        auto [it, fresh] = inSpace.try_emplace(p);
        if (fresh) it->second = glm::dvec3(params.space * glm::dvec4(glm::dvec3(original[p]), 1.0));
        return it->second;
    };
    auto spaceAreaVector = [&](uint32_t f) {
        glm::dvec3 n(0.0);
        for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
            const std::span<const uint32_t> lp = mesh.loop(l);
            for (size_t k = 0; k < lp.size(); ++k) n += glm::cross(spacePoint(lp[k]), spacePoint(lp[(k + 1) % lp.size()]));
        }
        return 0.5 * n;
    };
    std::vector<std::vector<glm::dvec3>> capPositions(regions.size());
    for (size_t r = 0; r < regions.size(); ++r) {
        const Region& reg = regions[r];
        // Each region face moves its own points: local scale about its centre and the local
        // translate, in its frame (z its normal, x along its first edge). A point shared by several
        // region faces takes the average of their moves, as Maya's recorded bounds show: a corner
        // between two perpendicular sides moves half the distance along each, and a fan of
        // triangles scaled about their own centres spreads less than the local scale.
        std::unordered_map<uint32_t, std::pair<glm::dvec3, int>> move;
        for (uint32_t f : reg.faces) {
            const glm::dvec3 av = spaceAreaVector(f);
            const glm::dvec3 z = glm::length(av) > 0.0 ? glm::normalize(av) : glm::dvec3(0.0, 0.0, 1.0);
            const std::span<const uint32_t> outer = mesh.faceOuterLoop(f);
            glm::dvec3 centre(0.0);
            for (uint32_t p : outer) centre += spacePoint(p);
            centre /= double(outer.size());
            glm::dvec3 x = outer.size() >= 2 ? spacePoint(outer[1]) - spacePoint(outer[0]) : glm::dvec3(1, 0, 0);
            x -= z * glm::dot(x, z);
            if (!(glm::length(x) > 1e-300))
                x = std::abs(z.x) < 0.9 ? glm::cross(z, glm::dvec3(1, 0, 0)) : glm::cross(z, glm::dvec3(0, 1, 0));
            x = glm::normalize(x);
            const glm::dmat3 frame(x, glm::cross(z, x), z);
            const glm::dmat3 toLocal = glm::transpose(frame);
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l)
                for (uint32_t p : mesh.loop(l)) {
                    const glm::dvec3 pos = spacePoint(p);
                    const glm::dvec3 target = centre + frame * (params.localScale * (toLocal * (pos - centre))) +
                                              frame * params.localTranslate;
                    auto& [sum, count] = move[p];
                    sum += target - pos;
                    ++count;
                }
        }
        capPositions[r].reserve(reg.points.size());
        for (uint32_t p : reg.points) {
            const auto& [sum, count] = move[p];
            glm::dvec3 moved = spacePoint(p) + (count > 0 ? sum / double(count) : glm::dvec3(0.0));
            moved = glm::dvec3(objectFromSpace * (params.transform * glm::dvec4(moved, 1.0)));
            if (!isFinite(moved)) {
                if (error) *error = "the extruded faces' points are not finite";
                return false;
            }
            capPositions[r].push_back(moved);
        }
    }

    completeEdges(mesh, true);

    // New points: per region, intermediate rings of boundary points, then the cap.
    // ringIndex[r][k][i]: index of ring k (0 = the original points, divisions = cap) of
    // reg.points[i]; UINT32_MAX for an interior point on an intermediate ring.
    std::vector<std::vector<std::vector<uint32_t>>> ringIndex(regions.size());
    mesh.points.reserve(mesh.points.size() + newPoints);
    for (size_t r = 0; r < regions.size(); ++r) {
        const Region& reg = regions[r];
        auto& rings = ringIndex[r];
        rings.assign(size_t(divisions) + 1, std::vector<uint32_t>(reg.points.size(), UINT32_MAX));
        for (size_t i = 0; i < reg.points.size(); ++i) rings[0][i] = reg.points[i];
        for (int k = 1; k < divisions; ++k) {
            const double t = double(k) / double(divisions);
            for (uint32_t p : reg.boundaryPoints) {
                const size_t i = reg.slot.at(p);
                const glm::dvec3 pos = glm::mix(glm::dvec3(original[p]), capPositions[r][i], t);
                rings[size_t(k)][i] = uint32_t(mesh.points.size());
                mesh.points.emplace_back(pos);
            }
        }
        for (size_t i = 0; i < reg.points.size(); ++i) {
            rings[size_t(divisions)][i] = uint32_t(mesh.points.size());
            mesh.points.emplace_back(capPositions[r][i]);
        }
    }

    std::vector<bool> dropEdge(mesh.edges.size(), false);
    // The region faces move onto the cap; their stored normals no longer hold.
    std::vector<uint32_t> capOf(original.size(), UINT32_MAX);
    size_t sideFaces = 0;
    const size_t oldEdgeCount = mesh.edges.size();
    std::unordered_map<uint64_t, size_t> edgeIndexOf;
    edgeIndexOf.reserve(oldEdgeCount);
    for (size_t e = 0; e < oldEdgeCount; ++e) edgeIndexOf.emplace(edgeKey(mesh.edges[e].v0, mesh.edges[e].v1), e);
    for (size_t r = 0; r < regions.size(); ++r) {
        const Region& reg = regions[r];
        for (size_t i = 0; i < reg.points.size(); ++i) capOf[reg.points[i]] = ringIndex[r][size_t(divisions)][i];
        // Inner edges are made anew on the cap (below); the old ones go.
        for (const RegionEdge& e : reg.edges)
            if (!e.boundary)
                if (const auto it = edgeIndexOf.find(edgeKey(e.a, e.b)); it != edgeIndexOf.end()) dropEdge[it->second] = true;
        for (uint32_t f : reg.faces) {
            for (uint32_t fv = mesh.faceVertexBegin(f); fv < mesh.faceVertexEnd(f); ++fv) {
                mesh.faceVertices[fv] = capOf[mesh.faceVertices[fv]];
                if (!mesh.normals.empty()) mesh.normals[fv] = glm::vec3(0.0f);
            }
        }
        for (size_t i = 0; i < reg.points.size(); ++i) capOf[reg.points[i]] = UINT32_MAX;

        // Side faces and new edges, division by division.
        const auto& rings = ringIndex[r];
        for (int k = 1; k <= divisions; ++k) {
            std::vector<bool> verticalDone(reg.points.size(), false);
            auto vertical = [&](uint32_t p) {
                const size_t i = reg.slot.at(p);
                if (verticalDone[i]) return;
                verticalDone[i] = true;
                mesh.edges.push_back({rings[size_t(k - 1)][i], rings[size_t(k)][i], true});
            };
            auto along = [&](const RegionEdge& e) {
                mesh.edges.push_back({rings[size_t(k)][reg.slot.at(e.a)], rings[size_t(k)][reg.slot.at(e.b)], true});
            };
            // Per boundary edge: the edges up from its two points (those not made yet), then the
            // edge along it; then, on the cap, the region's inner edges. Maya's numbering, as the
            // split rings that later name these edges on real scenes show.
            for (const RegionEdge& e : reg.edges)
                if (e.boundary) {
                    vertical(e.a);
                    vertical(e.b);
                    along(e);
                }
            if (k == divisions)
                for (const RegionEdge& e : reg.edges)
                    if (!e.boundary) along(e);
        }
        for (const BoundaryEdge& be : reg.boundary) {
            const size_t ia = reg.slot.at(be.a), ib = reg.slot.at(be.b);
            for (int k = 1; k <= divisions; ++k) {
                const uint32_t quad[4] = {rings[size_t(k - 1)][ia], rings[size_t(k - 1)][ib], rings[size_t(k)][ib],
                                          rings[size_t(k)][ia]};
                const uint32_t f = mesh.addFace(quad);
                ++sideFaces;
                // Each wall takes the UVs of its base edge (the region face's UVs at a and b).
                const uint32_t fv0 = mesh.faceVertexBegin(f);
                for (UvSet& set : mesh.uvSets) {
                    if (set.faceVertexUvs.size() != mesh.faceVertices.size()) continue;
                    const int32_t ua = set.faceVertexUvs[be.fvA], ub = set.faceVertexUvs[be.fvB];
                    set.faceVertexUvs[fv0 + 0] = ua;
                    set.faceVertexUvs[fv0 + 1] = ub;
                    set.faceVertexUvs[fv0 + 2] = ub;
                    set.faceVertexUvs[fv0 + 3] = ua;
                }
            }
        }
    }

    // Soft or hard new edges, by the angle between the faces they join.
    {
        std::unordered_map<uint64_t, size_t> newEdge;
        newEdge.reserve(mesh.edges.size() - oldEdgeCount);
        for (size_t e = oldEdgeCount; e < mesh.edges.size(); ++e) newEdge[edgeKey(mesh.edges[e].v0, mesh.edges[e].v1)] = e;
        std::vector<glm::dvec3> firstNormal(mesh.edges.size() - oldEdgeCount, glm::dvec3(0.0));
        std::vector<uint8_t> seen(mesh.edges.size() - oldEdgeCount, 0);
        const double cosLimit = std::cos(std::clamp(params.smoothingAngle, 0.0, 3.141592653589793));
        auto visit = [&](size_t f) {
            const glm::dvec3 n = mesh.faceNormal(f);
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                const std::span<const uint32_t> lp = mesh.loop(l);
                for (size_t k = 0; k < lp.size(); ++k) {
                    const auto it = newEdge.find(edgeKey(lp[k], lp[(k + 1) % lp.size()]));
                    if (it == newEdge.end()) continue;
                    const size_t s = it->second - oldEdgeCount;
                    if (!seen[s]) {
                        seen[s] = 1;
                        firstNormal[s] = n;
                    } else {
                        mesh.edges[it->second].smooth = glm::dot(firstNormal[s], n) >= cosLimit - 1e-12;
                    }
                }
            }
        };
        for (uint32_t f : selected) visit(f);
        for (size_t f = faceCount; f < mesh.faceCount(); ++f) visit(f);
    }

    if (std::find(dropEdge.begin(), dropEdge.end(), true) != dropEdge.end()) {
        std::vector<MeshEdge> keptEdges;
        for (size_t e = 0; e < mesh.edges.size(); ++e)
            if (e >= dropEdge.size() || !dropEdge[e]) keptEdges.push_back(mesh.edges[e]);
        mesh.edges = std::move(keptEdges);
    }
    // Region points no face uses any more go, and the later points move down.
    std::vector<uint32_t> useCount(mesh.points.size(), 0);
    for (uint32_t p : mesh.faceVertices) ++useCount[p];
    std::vector<bool> drop(mesh.points.size(), false);
    size_t dropped = 0;
    for (const Region& reg : regions)
        for (uint32_t p : reg.points)
            if (useCount[p] == 0 && !drop[p]) {
                drop[p] = true;
                ++dropped;
            }
    if (dropped) {
        std::vector<uint32_t> remap(mesh.points.size(), UINT32_MAX);
        uint32_t next = 0;
        for (size_t p = 0; p < mesh.points.size(); ++p)
            if (!drop[p]) {
                remap[p] = next;
                mesh.points[next++] = mesh.points[p];
            }
        mesh.points.resize(next);
        for (uint32_t& p : mesh.faceVertices) p = remap[p];
        std::vector<MeshEdge> kept;
        kept.reserve(mesh.edges.size());
        for (MeshEdge e : mesh.edges)
            if (remap[e.v0] != UINT32_MAX && remap[e.v1] != UINT32_MAX) kept.push_back({remap[e.v0], remap[e.v1], e.smooth});
        mesh.edges = std::move(kept);
    }
    if (result) *result = {regions.size(), sideFaces, dropped};
    return true;
}

}  // namespace pushpin::geom
