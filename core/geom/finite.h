// core/geom/finite.h: whether vectors and matrices hold only finite numbers (no NaN, no Inf), the
// check every value from a scene passes before it reaches geometry.
// Thread safety: pure functions. Memory: none.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace pushpin::geom {

inline bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline bool isFinite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace pushpin::geom
