// core/render/camera_space.h: object space to camera space for the rasterizer and the shading
// points, and the near-plane clip (DESIGN.md step 6a). The camera looks down −z.
#pragma once

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace pushpin::render {

// The camera-space position of an object-space point, and the unit camera-space normal of an
// object-space normal (zero when it has no direction or its length is not finite), exactly as
// every stage computes them. Both stay in double precision: GCC may keep a double rounded to float
// at double precision (its excess precision), so a round trip through float would give whatever
// the optimizer chose, and images that differ from one build to the next.
// Inline: the rasterizer calls them for every vertex of every tile.
inline glm::dvec3 cameraPoint(const glm::dmat4& cameraFromObject, const glm::vec3& p) {
    return glm::dvec3(cameraFromObject * glm::dvec4(glm::dvec3(p), 1.0));
}
inline glm::dvec3 cameraNormal(const glm::dmat3& normalToCamera, const glm::vec3& n) {
    const glm::dvec3 c = normalToCamera * glm::dvec3(n);
    const double len = glm::length(c);
    return len > 0.0 && std::isfinite(len) ? c / len : glm::dvec3(0.0);
}

// Clips a camera-space triangle to the half-space z <= nearZ (nearZ = −near clip distance),
// keeping the triangle's winding, and returns how many vertices it wrote: 0 when the triangle lies
// wholly past the plane, 3 when it lies inside or two of its vertices are past it (a smaller
// triangle), 4 when one is past it (a quadrilateral). A vertex on the plane counts as inside.
int clipNear(const glm::dvec3 in[3], double nearZ, glm::dvec3 out[4]);

}  // namespace pushpin::render
