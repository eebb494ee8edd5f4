#include "core/render/visible_set.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pushpin::render {

ObjectPlacement placeObject(const geom::Bounds3& bounds, const glm::dmat4& worldFromObject, const RenderCamera& camera,
                            const PixelRect& reach) {
    ObjectPlacement v;
    v.cameraFromObject = camera.cameraFromWorld * worldFromObject;
    v.objectFromCamera = glm::inverse(v.cameraFromObject);
    // An object flattened by a scale of 0 still renders (Maya shows it flat) but has no inverse;
    // its object-space shading positions are then the origin rather than NaN or overflowing
    // floats. The same goes for a scale so small that the inverse leaves the scene range.
    bool invertible = true;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            invertible = invertible && std::isfinite(v.objectFromCamera[c][r]) &&
                         std::abs(v.objectFromCamera[c][r]) <= kMaxSceneCoordinate;
    if (!invertible) {
        v.objectFromCamera = glm::dmat4(0.0);
        v.objectFromCamera[3][3] = 1.0;
    }
    v.normalToCamera = glm::transpose(glm::inverse(glm::dmat3(v.cameraFromObject)));

    // Far-plane culling per object, and objects wholly behind the near plane.
    auto finite = [](const geom::Bounds3& b) {
        return std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.lo.z) && std::isfinite(b.hi.x) &&
               std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
    };
    if (bounds.empty() || !finite(bounds)) return v;
    const geom::Bounds3 cb = bounds.transformed(v.cameraFromObject);
    if (cb.empty() || !finite(cb)) return v;
    if (-cb.hi.z > camera.farClipPlane) {  // wholly past the far plane
        v.culledFar = true;
        return v;
    }
    if (-cb.lo.z < camera.nearClipPlane) return v;  // wholly between the eye and the near plane, or behind
    // Frustum culling by screen-space bounds: exact for boxes wholly past the near plane; a box that
    // crosses it is kept and reaches everywhere.
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (-cb.hi.z >= camera.nearClipPlane) {
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300, z0 = 1e300, z1 = -1e300;
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p((c & 1) ? cb.hi.x : cb.lo.x, (c & 2) ? cb.hi.y : cb.lo.y, (c & 4) ? cb.hi.z : cb.lo.z);
            const glm::dvec2 r = camera.rasterFromCamera(p);
            x0 = std::min(x0, r.x), x1 = std::max(x1, r.x), y0 = std::min(y0, r.y), y1 = std::max(y1, r.y);
            z0 = std::min(z0, camera.depthKey(p));
            z1 = std::max(z1, camera.depthKey(p));
        }
        if (x1 < reach.x0 || x0 > reach.x1 || y1 < reach.y0 || y0 > reach.y1) return v;
        v.x0 = x0, v.y0 = y0, v.x1 = x1, v.y1 = y1, v.nearKey = z0, v.farKey = z1;
    } else {
        v.x0 = v.y0 = v.nearKey = -inf;
        v.x1 = v.y1 = v.farKey = inf;
    }
    v.kept = true;
    return v;
}

}  // namespace pushpin::render
