// core/geom/poly_merge.h: merging polygon points as Maya's polyMergeVert does.
// Thread safety: free functions on a caller-owned Mesh. Memory: linear in the mesh; the search for
// near points uses a hash grid, so the work stays near linear for any distance.
//
// What a merge does, and how the result is numbered:
//   - Groups: with a target point, every selected point joins the target, at the target's
//     position. Otherwise selected points closer than `distance` (in the move space) form groups
//     (joined transitively), each at the average of its points; with alwaysMergeTwo and exactly
//     two points selected, those two merge whatever their distance.
//   - A group keeps its lowest point index; the other points are removed and the later points
//     move down, as Maya's later component numbers on real scenes show.
//   - A loop that now visits the same point twice in a row loses the repeat; a face whose outer
//     loop falls below three points is removed (holes below three points are dropped). Edges
//     follow their points; an edge that collapsed or now repeats another goes.
#pragma once

#include "core/geom/mesh.h"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace pushpin::geom {

struct MergeVerticesParams {
    std::vector<bool> points;         // selected points; a shorter mask leaves the rest out
    double distance = 0.0;            // in the move space; points this close or closer merge
    glm::dmat4 space{1.0};            // object → move space (world space when Maya's worldSpace is on)
    bool alwaysMergeTwo = false;      // two selected points merge whatever their distance
    std::optional<uint32_t> target;   // merge every selected point into this one
};

struct MergeVerticesResult {
    size_t removedPoints = 0;
    size_t removedFaces = 0;
};

// Merges the selected points of a valid mesh. Returns false with `error` set when the target does
// not exist or the distance is not finite; the mesh is then unchanged.
bool mergeVertices(Mesh& mesh, const MergeVerticesParams& params, MergeVerticesResult* result = nullptr,
                   std::string* error = nullptr);

}  // namespace pushpin::geom
