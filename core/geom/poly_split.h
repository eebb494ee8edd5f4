// core/geom/poly_split.h: cutting faces along a path of points, as Maya's polySplit does.
// Thread safety: free functions on a caller-owned Mesh. Memory: one editable copy of the faces
// the path touches; work is linear in the mesh plus the path.
//
// The path is a sequence of points, each on an edge of the input mesh (at a fraction from the
// edge's first point; 0 and 1 are its end points) or free inside a face. Between two consecutive
// edge points, with the free points met in between, the face holding both is cut in two. How the
// result is numbered (pinned by the face bounds Maya records on the extrusions that follow splits
// in real scenes; see Corpus.ExtrudedFacesHaveTheBoundsMayaRecorded):
//   - New points: each edge point strictly inside its edge, in path order; a cut's free points are
//     made once the cut is made, after its far end B, from B's side back to A. Several points on
//     one input edge split it in order of their fractions.
//   - An edge a→b split at p keeps its index for a→p; p→b is appended. Every loop along the edge
//     gains p, with UVs interpolated along the edge.
//   - A cut between edge points A and B appends its new edges in path order (A to the first free
//     point … to B), after B's edge split. Of the two parts of the face, the one holding more of
//     the input mesh's corners keeps the face's index and the other is appended; on a tie, the
//     part from A forward to B (then back along the cut) is appended.
//   - Free points take UVs interpolated over the face (mean value weights in its plane).
#pragma once

#include "core/geom/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace pushpin::geom {

struct SplitPoint {
    enum class Kind : unsigned char { Edge, Face };
    Kind kind = Kind::Edge;
    // Edge: the input edge (index into mesh.edges after completeEdges). Face: the input face the
    // free point lies in, or -1 when not known (the face holding both ends of its cut is used).
    int64_t index = 0;
    double fraction = 0.0;     // Edge: from the edge's first point, clamped to [0, 1]
    glm::dvec3 position{0.0};  // Face: object-space position
};

struct SplitParams {
    std::vector<SplitPoint> points;
    int subdivisions = 1;         // sections per new edge between two edge points (not via free points)
    double smoothingAngle = 0.0;  // radians: a new edge is soft when its faces meet at less than this
    bool dropFreePoints = false;  // Maya's clean2Verts: the cut runs straight past free points
};

struct SplitResult {
    size_t newPoints = 0;
    size_t newFaces = 0;
    size_t newEdges = 0;
    // Cuts not made: no face holds both ends, an end lies only on a hole, the ends are one point,
    // or free points lead nowhere (before the first or after the last edge point).
    size_t skippedCuts = 0;
};

// The largest number of points a split may leave, of points on its path and of sections per new
// edge. (Maya's split tools make paths of a few hundred points at most; the cap keeps the work of
// a hostile path, whose points may all crowd into one face, small.)
inline constexpr size_t kMaxSplitResultPoints = size_t(1) << 27;
inline constexpr size_t kMaxSplitPathPoints = 16384;
inline constexpr int kMaxSplitSubdivisions = 1024;

// Cuts the faces. Returns false with `error` set, leaving the mesh unchanged, when a point names
// an edge or face the mesh does not have, a value is not finite, `subdivisions` is outside 1 to
// kMaxSplitSubdivisions, the path has more than kMaxSplitPathPoints points (sections included),
// or the result would be too large.
bool splitFaces(Mesh& mesh, const SplitParams& params, SplitResult* result = nullptr, std::string* error = nullptr);

}  // namespace pushpin::geom
