// core/geom/subdivide.h: Catmull-Clark subdivision of a polygon mesh (OpenSubdiv's Far layer), for
// polySmoothFace and a mesh's smooth preview.
// Thread safety: free function on a caller-owned Mesh. Memory: OpenSubdiv's refiner holds every
// level; the request is bounded by kMaxSubdividedFaces before any of it is built.
//
// Uniform refinement: every face of n sides becomes n quads at the first level, each quad four at
// the next. Faces of the result are grouped by the face they came from, in its order (faceOrigin
// maps each back). UV and colour sets are refined as face-varying data; stored normals are dropped
// (they no longer fit the surface); hard edges become sharp creases when asked.
#pragma once

#include "core/geom/mesh.h"

#include <string>
#include <vector>

namespace pushpin::geom {

struct SubdivideParams {
    int levels = 1;              // 0 leaves the mesh as it is
    bool keepBorder = true;      // border corners stay sharp (else only border edges are kept)
    bool keepHardEdges = false;  // hard edges are infinitely sharp creases
    bool smoothUvs = true;       // UVs are smoothed with the surface (else interpolated linearly)
    double continuity = 1.0;     // 1 smooth, 0 the linear subdivision, between: a blend of the two
};

inline constexpr size_t kMaxSubdividedFaces = size_t(1) << 22;

// The number of faces `levels` of uniform refinement make of `mesh` (n quads per n-gon, then four
// per quad per level), as a double so that any request can be compared with the bound.
double subdividedFaceCount(const Mesh& mesh, int levels);

// Subdivides a valid mesh in place. `faceOrigin` (when given) receives, per new face, the index of
// the face it came from. Returns false with `error` set, leaving the mesh unchanged, for a face
// with holes (OpenSubdiv has no holes in faces), a result beyond kMaxSubdividedFaces, or a
// topology OpenSubdiv refuses.
bool subdivideMesh(Mesh& mesh, const SubdivideParams& params, std::vector<uint32_t>* faceOrigin = nullptr,
                   std::string* error = nullptr);

}  // namespace pushpin::geom
