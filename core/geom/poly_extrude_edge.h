// core/geom/poly_extrude_edge.h: extruding polygon edges as Maya's polyExtrudeEdge does: each
// selected edge gets a wall of quads standing on it, up to a copy of the edge that the transform
// moves.
// Thread safety: free functions on a caller-owned Mesh. Memory: grows the mesh by the new rings
// of points and the wall faces; the caller bounds the request (see ExtrudeEdgesParams::divisions).
//
// What an extrusion does, and how the result is numbered (the layout is this renderer's own: no
// real scene checks it yet):
//   - Regions: with keepFacesTogether, selected edges that share a point extrude as one chain and
//     share the copies of their points; without it every edge is its own region. Regions are
//     taken in order of their lowest edge.
//   - A region's points, in first-use order (its edges ascending, each edge's first point then
//     its second), get one copy per division, appended ring by ring, region by region.
//   - One quad per selected edge and division is appended, edges ascending: for an edge that runs
//     a→b in the first face using it, (b, a, a′, b′), so the wall continues that face's winding.
//   - New edges per division, per edge: from a and from b up to their copies (those not made
//     yet), then the copy of the edge, which keeps the edge's hard or soft flag; the others are
//     soft.
//   - The last ring is placed by the local translate and local scale in the region's frame
//     (z the average normal of the faces on its edges, x along its edges, y = z × x, which points
//     into the faces beside a border edge; scale about the region's centre), then by the
//     transform; the rings between are spaced evenly from the edge to it.
#pragma once

#include "core/geom/mesh.h"
#include "core/geom/poly_extrude.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace pushpin::geom {

// The move as in extrudeFaces; `divisions` counts rings of wall faces, and each region's frame is
// the one described above.
struct ExtrudeEdgesParams : ExtrusionMove {
    std::vector<bool> edges;  // selected edges (indices into mesh.edges after completeEdges)
};

struct ExtrudeEdgesResult {
    size_t regions = 0;
    size_t wallFaces = 0;
};

// The largest number of points an edge extrusion may leave (a request beyond it is refused).
inline constexpr size_t kMaxEdgeExtrudedPoints = size_t(1) << 27;

// Extrudes the selected edges. Returns false, with `error` set and the mesh unchanged, when the
// request would exceed kMaxEdgeExtrudedPoints, the space is not invertible, or a point would not
// be finite. No selected edge is not an error: the mesh is unchanged.
bool extrudeEdges(Mesh& mesh, const ExtrudeEdgesParams& params, ExtrudeEdgesResult* result = nullptr,
                  std::string* error = nullptr);

}  // namespace pushpin::geom
