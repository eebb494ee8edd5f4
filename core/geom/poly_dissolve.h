// core/geom/poly_dissolve.h: deleting edges and points the way Maya's deleteComponent does:
// an edge between two faces is dissolved (the faces merge), a point on only two edges is taken out
// of its faces. Thread safety: free functions on a caller-owned Mesh. Memory: one editable copy of
// the faces; work is linear in the mesh plus the edges dissolved.
//
// Numbering: a merged face keeps the lower of the two indices (its loop starts where that face
// started); the other face goes and later faces move down. Dissolved edges go and later edges move
// down; points no face uses any more go the same way. A corner left as a spike (a point visited
// and left along the same edge) is cut off.
#pragma once

#include "core/geom/mesh.h"

#include <vector>

namespace pushpin::geom {

struct DissolveResult {
    size_t dissolvedEdges = 0;
    size_t removedFaces = 0;    // border edges' faces (an edge on one face cannot be dissolved)
    size_t removedPoints = 0;
    size_t keptPoints = 0;      // selected points on more than two edges, which stay
};

// Dissolves the marked edges (indices into mesh.edges after completeEdges; a shorter mask leaves
// the rest). An edge on a single face removes that face; an edge with the same face on both sides
// stays. With `cleanPoints`, the dissolved edges' ends left on only two edges go as well (as
// removeWingedPoints takes them out).
DissolveResult dissolveEdges(Mesh& mesh, const std::vector<bool>& edges, bool cleanPoints = false);

// Closes each border loop made only of marked edges with a new face (Maya's polyCloseBorder),
// wound against the faces along it so that it faces the same way they do. New faces follow the
// existing ones, in the order of each loop's lowest edge. Returns the number of faces added.
size_t closeBorders(Mesh& mesh, const std::vector<bool>& edges);

// Takes the marked points that lie on exactly two edges out of every loop (the two edges become
// one); other marked points stay and are counted.
DissolveResult removeWingedPoints(Mesh& mesh, const std::vector<bool>& points);

}  // namespace pushpin::geom
