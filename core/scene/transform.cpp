#include "core/scene/transform.h"

#include <cmath>

namespace pushpin::scene {

namespace {

// GLM matrices are indexed m[column][row]. Each elementary factor below is the column-vector form
// (the transpose) of Maya's row-vector matrix of the same name in reference/nodes.md §1.

glm::dmat4 translation(const glm::dvec3& t) {
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

glm::dmat4 scaling(const glm::dvec3& s) {
    glm::dmat4 m(1.0);
    m[0][0] = s.x;
    m[1][1] = s.y;
    m[2][2] = s.z;
    return m;
}

// Maya's SH has rows (1 0 0)(shxy 1 0)(shxz shyz 1): p·SH = (x + shxy·y + shxz·z, y + shyz·z, z).
glm::dmat4 shearing(const glm::dvec3& sh) {
    glm::dmat4 m(1.0);
    m[1][0] = sh.x;  // x' += shearXY · y
    m[2][0] = sh.y;  // x' += shearXZ · z
    m[2][1] = sh.z;  // y' += shearYZ · z
    return m;
}

// Right-handed rotations (counter-clockwise looking down the axis towards the origin).
glm::dmat4 rotateX(double a) {
    const double c = std::cos(a), s = std::sin(a);
    glm::dmat4 m(1.0);
    m[1][1] = c;
    m[1][2] = s;
    m[2][1] = -s;
    m[2][2] = c;
    return m;
}

glm::dmat4 rotateY(double a) {
    const double c = std::cos(a), s = std::sin(a);
    glm::dmat4 m(1.0);
    m[0][0] = c;
    m[0][2] = -s;
    m[2][0] = s;
    m[2][2] = c;
    return m;
}

glm::dmat4 rotateZ(double a) {
    const double c = std::cos(a), s = std::sin(a);
    glm::dmat4 m(1.0);
    m[0][0] = c;
    m[0][1] = s;
    m[1][0] = -s;
    m[1][1] = c;
    return m;
}

glm::dvec3 safeInverse(const glm::dvec3& s) {
    auto inv = [](double v) { return (std::abs(v) > 1e-12 && std::isfinite(v)) ? 1.0 / v : 1.0; };
    return {inv(s.x), inv(s.y), inv(s.z)};
}

}  // namespace

glm::dmat4 rotationMatrix(const glm::dvec3& r, int rotateOrder) {
    const glm::dmat4 x = rotateX(r.x), y = rotateY(r.y), z = rotateZ(r.z);
    // Column-vector composition: the rotation applied first is the right-most factor.
    switch (static_cast<RotateOrder>(rotateOrder)) {
        case RotateOrder::YZX: return x * z * y;
        case RotateOrder::ZXY: return y * x * z;
        case RotateOrder::XZY: return y * z * x;
        case RotateOrder::YXZ: return z * x * y;
        case RotateOrder::ZYX: return x * y * z;
        case RotateOrder::XYZ:
        default: return z * y * x;
    }
}

glm::dmat4 transformMatrix(const TransformAttrs& a) {
    // Maya (row vectors): SP⁻¹ · S · SH · SP · ST · RP⁻¹ · RA · R · RP · RT · T.
    // Column vectors: the same factors in reverse order.
    const glm::dmat4 scalePart = translation(a.scalePivotTranslate) * translation(a.scalePivot) *
                                 shearing(a.shear) * scaling(a.scale) * translation(-a.scalePivot);
    const glm::dmat4 rotatePart = translation(a.rotatePivotTranslate) * translation(a.rotatePivot) *
                                  rotationMatrix(a.rotate, a.rotateOrder) *
                                  rotationMatrix(a.rotateAxis, int(RotateOrder::XYZ)) *
                                  translation(-a.rotatePivot);
    return translation(a.translate) * rotatePart * scalePart;
}

glm::dmat4 jointMatrix(const JointAttrs& a) {
    // Maya (row vectors): S · RA · R · JO · IS · T.
    const glm::dmat4 inverseScale =
        a.segmentScaleCompensate ? scaling(safeInverse(a.inverseScale)) : glm::dmat4(1.0);
    return translation(a.translate) * inverseScale * rotationMatrix(a.jointOrient, int(RotateOrder::XYZ)) *
           rotationMatrix(a.rotate, a.rotateOrder) * rotationMatrix(a.rotateAxis, int(RotateOrder::XYZ)) *
           scaling(a.scale);
}

}  // namespace pushpin::scene
