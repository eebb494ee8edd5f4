// core/render/shading_points.h: where a shading sample lies on a visible triangle (DESIGN.md step 6,
// "shading points"). A sample is taken where the camera ray through its raster position meets the
// triangle's plane: that point, its barycentric weights, the interpolated shading normal and uv,
// the geometric normal facing the ray, and the surface's tangents along u and v, all in camera
// space. A shading point depends on the triangle and the ray alone, so a tile gets the same
// numbers whether it reads the triangle from a shape's tessellation or from its own copy.
// Thread safety: pure.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pushpin::render {

// A triangle as shading reads it, in camera space: corner positions, unit shading normals (zero
// where a vertex normal has no direction) and uvs (hasUvs false: every uv 0).
struct ShadingTriangle {
    glm::dvec3 p[3];
    glm::dvec3 n[3];
    glm::dvec2 uv[3];
    bool hasUvs = false;
    bool opposite = false;  // the shape's opposite flag: both normals point the other way
};

struct ShadingPoint {
    glm::dvec3 position;          // on the triangle
    double weight[3] = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};  // barycentric, of corners 0, 1, 2
    glm::dvec3 shadingNormal;     // unit, facing the ray's origin side (see flipped)
    glm::dvec3 geometricNormal;   // unit, facing against the ray
    glm::dvec2 uv{0.0};
    glm::dvec3 tangentU{0.0}, tangentV{0.0};  // dP/du and dP/dv (zero without uvs or when degenerate)
    bool flipped = false;         // the normals were turned to face the ray (a back face)
};

// The shading point where the ray origin + t·dir meets `t`'s plane. A hit a little outside the
// triangle (a sub-sample the triangle owns, up to rounding) is pulled back onto it; a triangle
// without area, or a ray along its plane, is shaded at its centroid with the geometric normal
// −dir. Normals are turned to face the ray (flipped) after the opposite flag.
ShadingPoint shadingPointOn(const ShadingTriangle& t, const glm::dvec3& origin, const glm::dvec3& dir);

}  // namespace pushpin::render
