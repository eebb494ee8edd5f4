// core/geom/poly_bevel.h: chamfering polygon edges, as Maya's polyBevel with one segment does.
// Thread safety: free functions on a caller-owned Mesh. Memory: one new mesh of about the input's
// size; work is linear in the mesh.
//
// What a bevel does (one segment, flat: Maya's chamfer), and how the result is laid out (the
// layout is this renderer's own; no real scene checks it yet):
//   - Every corner of a face at a point of a selected edge moves into the face: by `offset` along
//     each of its two edges that is selected (a corner between two selected edges goes in along
//     both), or along its unselected edge when only the other is selected; a corner with neither
//     edge selected is replaced by the points its neighbours slid along its edges (keeping the
//     point itself where an edge has none). A point no face uses afterwards goes.
//   - The faces keep their indices. Then one quad per selected edge (edges ascending) joins the
//     two faces' moved edges, and one polygon per point (points ascending) fills the gap the
//     moved corners leave round it, where they leave one.
//   - The offset of each point is at most half its shortest edge, so moved corners never cross.
//   - New corners take UVs moved with them along the face's edges; the new faces have none. Edges
//     that stay keep their hard or soft flag; new ones are soft where their faces meet at less
//     than `smoothingAngle`.
//   - Border edges and edges of more than two faces are not beveled (they are counted).
#pragma once

#include "core/geom/mesh.h"

#include <string>
#include <vector>

namespace pushpin::geom {

struct BevelParams {
    std::vector<bool> edges;       // selected edges (indices into mesh.edges after completeEdges)
    double offset = 0.2;           // distance along the edges, or a fraction (see below)
    bool offsetAsFraction = false; // offset × half the shortest edge at each point
    double smoothingAngle = 0.5235987755982988;  // radians
};

struct BevelResult {
    size_t bevelledEdges = 0;
    size_t skippedEdges = 0;  // border or non-manifold
    size_t newFaces = 0;
};

// Bevels the selected edges. Returns false with `error` set, leaving the mesh unchanged, when the
// offset is not finite or negative, or the mesh has faces with holes on a selected edge.
bool bevelEdges(Mesh& mesh, const BevelParams& params, BevelResult* result = nullptr, std::string* error = nullptr);

}  // namespace pushpin::geom
