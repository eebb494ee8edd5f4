// core/geom/bounds.h: axis-aligned bounding boxes. Plain value type; thread-safe.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <limits>

namespace pushpin::geom {

struct Bounds3 {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};

    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(const glm::dvec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3& b) {
        if (b.empty()) return;
        extend(b.lo);
        extend(b.hi);
    }
    glm::dvec3 size() const { return empty() ? glm::dvec3(0.0) : hi - lo; }
    glm::dvec3 center() const { return (lo + hi) * 0.5; }

    // Bounds of this box after an affine transform (column-vector convention): all 8 corners.
    Bounds3 transformed(const glm::dmat4& m) const {
        Bounds3 out;
        if (empty()) return out;
        for (int i = 0; i < 8; ++i) {
            glm::dvec3 c((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            out.extend(glm::dvec3(m * glm::dvec4(c, 1.0)));
        }
        return out;
    }
};

}  // namespace pushpin::geom
