// core/geom/poly_extrude.h: extruding polygon faces as Maya's polyExtrudeFace does.
// Thread safety: free functions on a caller-owned Mesh. Memory: grows the mesh by the new rings
// of points and the side faces; the caller bounds the request (see ExtrudeFacesParams::divisions).
//
// What an extrusion does to the mesh, and how the result is numbered:
//   - Regions: with keepFacesTogether, selected faces joined by an edge extrude as one region;
//     without it every face is its own region. Regions are taken in order of their lowest face.
//   - Every point of a region gets a copy on the cap; boundary points (those on an edge that only
//     one face of the region uses) also get one copy per intermediate division. New points are
//     appended region by region: the intermediate rings first (boundary points, first-use order),
//     then the cap (every region point, first-use order: faces ascending, loop order).
//   - The selected faces keep their indices and move onto the cap points. One side quad per
//     boundary edge and division is appended, (a, b, b', a') for a boundary edge a→b of a region
//     face, so the walls face outward when the region does.
//   - Points of a region that no face uses afterwards (a multi-face region's interior points) are
//     removed and the later points renumbered, so a region's cap points end up as the last ones.
//   - Edges inside a region are made anew on the cap and the old ones go (later edges move down).
//     New edges are appended per division: for each boundary edge in turn, the edges from its two
//     points up to their copies (those not made yet), then the edge along it; then the region's
//     inner edges. New edges are soft where the two faces they join are within smoothingAngle of
//     each other.
// The first-use order of the cap points, the drop of interior points and the edge order are pinned
// by Maya's own component numbers on real scenes: the face bounds Maya records on later
// extrusions, and the edge rings later polySplitRing nodes name (tests/core/scene/corpus_test.cpp);
// the side quads' first corner is not verified.
#pragma once

#include "core/geom/mesh.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace pushpin::geom {

// How an extrusion of faces or edges moves the copies it makes.
struct ExtrusionMove {
    bool keepFacesTogether = true;
    int divisions = 1;  // rings of side faces; values below 1 count as 1
    // The space the copies are moved in, from object space: worldFromObject when Maya's worldSpace
    // is on (distances and normals are then world-space ones), else the identity.
    glm::dmat4 space{1.0};
    // The copies' transform in that space (Maya's translate, rotate and scale about the pivot).
    glm::dmat4 transform{1.0};
    // In each region's frame, in that space: z along the normals (each point along the average
    // normal of its region faces), x and y in the region's plane. Local scale is about the
    // region's centre.
    glm::dvec3 localTranslate{0.0};
    glm::dvec3 localScale{1.0};
};

struct ExtrudeFacesParams : ExtrusionMove {
    std::vector<bool> faces;  // selected faces; a shorter mask leaves the rest unselected
    double smoothingAngle = 0.5235987755982988;  // radians (Maya's default, 30 degrees)
};

struct ExtrudeFacesResult {
    size_t regions = 0;
    size_t sideFaces = 0;
    size_t removedPoints = 0;
};

// The largest number of points an extrusion may leave (a request beyond it is refused).
inline constexpr size_t kMaxExtrudedPoints = size_t(1) << 27;

// Extrudes the selected faces of a valid mesh. Returns false, with `error` set, when the request
// would exceed kMaxExtrudedPoints or a transform gives a non-finite point; the mesh is then left
// as it was. No selected face is not an error: the mesh is unchanged.
bool extrudeFaces(Mesh& mesh, const ExtrudeFacesParams& params, ExtrudeFacesResult* result = nullptr,
                  std::string* error = nullptr);

}  // namespace pushpin::geom
