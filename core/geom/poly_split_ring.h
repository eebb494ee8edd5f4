// core/geom/poly_split_ring.h: inserting an edge loop across a ring of edges, as Maya's
// polySplitRing does.
// Thread safety: free functions on a caller-owned Mesh. Memory: one editable copy of the faces
// during the split; work is linear in the mesh per loop inserted.
//
// What a split does, and how the result is numbered (pinned by the edge numbers later splits and
// tweaks on real scenes refer to; see tests/core/geom/poly_split_ring_test.cpp):
//   - The ring is walked from the root edge, first through the face in which the root runs in its
//     own direction, from each quad to the edge opposite, while that edge is in the ring. A ring
//     that does not close is walked the other way from the root as well; the loop then runs from
//     that far end, through the root, to the first one.
//   - One new point per ring edge, in walk order. On the root it lies at `weight` from its first
//     point (from its second when `fromFirst` is off); on every other edge at the same fraction
//     from the end joined to that point through the faces crossed.
//   - Each ring edge a→b split at p keeps its index for a→p; p→b is appended. Faces using the edge
//     gain p. Then each crossed quad is cut by a new edge between its two new points: the part
//     from the earlier point forward to the later one is appended, the rest keeps the face. New
//     edges come in the order Maya's sequential split makes them: the root's second half, then per
//     following ring edge its second half and the edge across the face just crossed, and last the
//     edge closing a closed loop.
//   - New face-vertices take UVs interpolated along the edge in that face; normals are unset.
#pragma once

#include "core/geom/mesh.h"

#include <string>
#include <vector>

namespace pushpin::geom {

struct SplitRingParams {
    std::vector<bool> edges;  // the ring's edges (indices into mesh.edges after completeEdges)
    int64_t rootEdge = -1;    // where the walk and the weight start; -1: the lowest ring edge
    double weight = 0.5;      // fraction along the root edge, in [0, 1]
    bool fromFirst = true;    // weight measured from the root edge's first point (else its second)
};

struct SplitRingResult {
    size_t newPoints = 0;
    size_t newFaces = 0;
    bool closed = false;
    // Per ring edge split, the index of its half between the end the fraction was measured from
    // and the new point (the ring a further loop on that side splits); the root's is `rootEdge`.
    std::vector<bool> nearHalves;
};

// The largest number of points a split may leave.
inline constexpr size_t kMaxSplitPoints = size_t(1) << 27;

// Inserts the loop. Returns false with `error` set, leaving the mesh unchanged, when the root
// edge is not in the ring, the ring has no quad to cross, a weight is not finite, or the result
// would be too large.
bool splitRing(Mesh& mesh, const SplitRingParams& params, SplitRingResult* result = nullptr,
               std::string* error = nullptr);

}  // namespace pushpin::geom
