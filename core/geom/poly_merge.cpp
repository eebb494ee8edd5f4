// core/geom/poly_merge.cpp: polyMergeVert on a geom::Mesh.
#include "core/geom/poly_merge.h"

#include "core/geom/union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace pushpin::geom {

bool mergeVertices(Mesh& mesh, const MergeVerticesParams& params, MergeVerticesResult* result, std::string* error) {
    if (result) *result = {};
    const size_t n = mesh.points.size();
    std::vector<uint32_t> selected;
    for (size_t p = 0; p < std::min(n, params.points.size()); ++p)
        if (params.points[p]) selected.push_back(uint32_t(p));
    if (params.target && *params.target >= n) {
        if (error) *error = "the point to merge to (vtx[" + std::to_string(*params.target) + "]) does not exist";
        return false;
    }
    if (!std::isfinite(params.distance)) {
        if (error) *error = "the merge distance is not finite";
        return false;
    }
    LowestRootSets groups(n);  // a group's root is its lowest index: the point that stays
    std::vector<glm::dvec3> position(n);
    for (size_t p = 0; p < n; ++p) position[p] = glm::dvec3(mesh.points[p]);
    bool atTarget = false;
    if (params.target) {
        if (selected.empty()) return true;
        for (uint32_t p : selected) groups.join(p, *params.target);
        atTarget = true;
    } else if (params.alwaysMergeTwo && selected.size() == 2) {
        groups.join(selected[0], selected[1]);
    } else if (selected.size() >= 2) {
        // Hash grid of cell size `distance` in the move space: near points are in adjacent cells.
        const double d = std::max(params.distance, 0.0);
        std::vector<glm::dvec3> at(selected.size());
        for (size_t i = 0; i < selected.size(); ++i)
            at[i] = glm::dvec3(params.space * glm::dvec4(position[selected[i]], 1.0));
        const double cell = d > 0.0 ? d : 1.0;
        auto cellOf = [&](const glm::dvec3& p) {
            return glm::dvec3(std::floor(p.x / cell), std::floor(p.y / cell), std::floor(p.z / cell));
        };
        auto key = [](const glm::dvec3& c) {
            const auto h = [](double v) { return uint64_t(int64_t(std::clamp(v, -1e15, 1e15))); };
            return h(c.x) * 0x9E3779B97F4A7C15ull ^ h(c.y) * 0xC2B2AE3D27D4EB4Full ^ h(c.z) * 0x165667B19E3779F9ull;
        };
        std::unordered_multimap<uint64_t, size_t> grid;
        grid.reserve(selected.size());
        for (size_t i = 0; i < selected.size(); ++i) grid.emplace(key(cellOf(at[i])), i);
        for (size_t i = 0; i < selected.size(); ++i) {
            if (!std::isfinite(at[i].x) || !std::isfinite(at[i].y) || !std::isfinite(at[i].z)) continue;
            const glm::dvec3 c = cellOf(at[i]);
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz) {
                        const auto range = grid.equal_range(key(c + glm::dvec3(dx, dy, dz)));
                        for (auto it = range.first; it != range.second; ++it) {
                            const size_t j = it->second;
                            if (j <= i) continue;
                            if (glm::length(at[j] - at[i]) <= d) groups.join(selected[i], selected[j]);
                        }
                    }
        }
    }

    // Survivors and their positions.
    std::vector<uint32_t> remap(n);
    std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
    std::vector<uint32_t> count(n, 0);
    uint32_t next = 0;
    for (size_t p = 0; p < n; ++p) {
        const uint32_t root = groups.find(uint32_t(p));
        sum[root] += position[p];
        ++count[root];
        if (root == p) remap[p] = next++;
    }
    if (next == n) return true;
    for (size_t p = 0; p < n; ++p) remap[p] = remap[groups.find(uint32_t(p))];
    std::vector<glm::vec3> points(next);
    for (size_t p = 0; p < n; ++p)
        if (groups.find(uint32_t(p)) == p)
            points[remap[p]] = glm::vec3(atTarget && count[p] > 1 ? position[*params.target] : sum[p] / double(count[p]));

    // Faces without repeated corners; per-face-vertex data follows the corners kept.
    Mesh out = facelessCopy(mesh, std::move(points));
    size_t removedFaces = 0;
    std::vector<uint32_t> kept;
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        const size_t loopsBefore = out.loopCount();
        for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
            const uint32_t begin = mesh.loopStarts[l], end = mesh.loopStarts[l + 1];
            kept.clear();
            for (uint32_t fv = begin; fv < end; ++fv) {
                const uint32_t p = remap[mesh.faceVertices[fv]];
                if (!kept.empty() && remap[mesh.faceVertices[kept.back()]] == p) continue;
                kept.push_back(fv);
            }
            while (kept.size() > 1 && remap[mesh.faceVertices[kept.back()]] == remap[mesh.faceVertices[kept.front()]])
                kept.pop_back();
            if (kept.size() < 3) {
                if (l == mesh.faceLoopStarts[f]) break;  // the outer loop collapsed: the face goes
                continue;
            }
            for (uint32_t fv : kept) copyFaceVertex(out, mesh, fv, remap[mesh.faceVertices[fv]]);
            out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        }
        if (out.loopCount() == loopsBefore) {
            ++removedFaces;
            continue;
        }
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    // A face whose outer loop collapsed after a hole was kept cannot happen: the outer loop is
    // first. Edges follow their points, once each, in their order.
    std::unordered_map<uint64_t, bool> seen;
    for (const MeshEdge& e : mesh.edges) {
        if (e.v0 >= n || e.v1 >= n) continue;
        const uint32_t a = remap[e.v0], b = remap[e.v1];
        if (a == b || !seen.emplace(edgeKey(a, b), true).second) continue;
        out.edges.push_back({a, b, e.smooth});
    }
    const size_t removedPoints = n - next;
    mesh = std::move(out);
    if (result) *result = {removedPoints, removedFaces};
    return true;
}

}  // namespace pushpin::geom
