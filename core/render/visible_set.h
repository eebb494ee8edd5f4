// core/render/visible_set.h: the visible set of a frame (DESIGN.md step 4). Each object is placed
// before the camera from its object-space bounds alone, without its triangles: its matrices to and
// from camera space, whether it is culled (wholly past the far plane, wholly in front of the near
// plane or behind the eye, or off the screen), and its screen box in raster space with the range of
// depth keys (fragment.h) its bounds span, which the tile plan, the per-tile object lists and the
// occlusion test read. Triangles that cross the near plane are clipped later, per triangle.
// Pure functions: reentrant and thread-safe; no allocation.
#pragma once

#include "core/geom/bounds.h"
#include "core/render/camera.h"
#include "core/render/fragment.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

namespace pushpin::render {

struct ObjectPlacement {
    glm::dmat4 cameraFromObject{1.0};
    // The inverse of cameraFromObject; for a matrix without a usable inverse (a scale of 0, or an
    // inverse with an entry beyond kMaxSceneCoordinate) the projection onto the origin, so that
    // object-space shading positions stay finite.
    glm::dmat4 objectFromCamera{1.0};
    glm::dmat3 normalToCamera{1.0};  // inverse transpose of cameraFromObject's 3×3 part
    bool kept = false;               // some of the object may be seen
    bool culledFar = false;          // wholly past the far clip plane
    // The screen box of the bounds in raster space and the smallest and largest depth key of their
    // corners; for bounds that cross the near plane the box is the whole plane, nearKey −∞ and
    // farKey +∞. Zero when not kept.
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double nearKey = 0, farKey = 0;
};

// Places an object whose object-space `bounds` sit in the world by `worldFromObject` before
// `camera`. It is kept when its bounds are finite and not empty, reach past the near plane and
// not wholly past the far plane, and its screen box meets `reach` (the pixels rendered, widened by
// what tiles read around them); a box touching `reach` along an edge is kept.
ObjectPlacement placeObject(const geom::Bounds3& bounds, const glm::dmat4& worldFromObject, const RenderCamera& camera,
                            const PixelRect& reach);

}  // namespace pushpin::render
