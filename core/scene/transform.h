// core/scene/transform.h: the local matrix of a Maya transform or joint from its attribute values
// (reference/nodes.md §1). Pure functions on plain structs; thread-safe; no allocation.
//
// Maya composes row-vector matrices (p' = p · M, the left factor applies first). These functions
// return the same matrices transposed, as GLM column-major matrices for column vectors
// (p' = M * p), so `parentFromLocal * vec4(p, 1)` gives the point in the parent's space.
// Angles are radians, lengths centimetres (the internal units of a scene::Graph).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace pushpin::scene {

// Maya's rotateOrder enum; the letters give the order in which the axis rotations are applied.
enum class RotateOrder : int { XYZ = 0, YZX = 1, ZXY = 2, XZY = 3, YXZ = 4, ZYX = 5 };

// The attributes of a `transform` node that shape its local matrix, with Maya's defaults.
struct TransformAttrs {
    glm::dvec3 translate{0.0};
    glm::dvec3 rotate{0.0};  // radians, applied in rotateOrder
    glm::dvec3 scale{1.0};
    glm::dvec3 shear{0.0};  // (shearXY, shearXZ, shearYZ)
    int rotateOrder = 0;    // RotateOrder; values outside 0..5 are treated as XYZ
    glm::dvec3 rotateAxis{0.0};  // radians, always XYZ order, applied before rotate
    glm::dvec3 rotatePivot{0.0};
    glm::dvec3 rotatePivotTranslate{0.0};
    glm::dvec3 scalePivot{0.0};
    glm::dvec3 scalePivotTranslate{0.0};
};

// The attributes of a `joint` node that shape its local matrix.
struct JointAttrs {
    glm::dvec3 translate{0.0};
    glm::dvec3 rotate{0.0};  // radians, applied in rotateOrder
    glm::dvec3 scale{1.0};
    int rotateOrder = 0;
    glm::dvec3 rotateAxis{0.0};    // the joint's "rotate axis" (orientation of its rotation), XYZ order
    glm::dvec3 jointOrient{0.0};   // radians, XYZ order
    glm::dvec3 inverseScale{1.0};  // normally the parent joint's scale (joint.inverseScale ← parent.scale)
    bool segmentScaleCompensate = true;
};

// Rotation by `radians` about x, y and z applied in `rotateOrder` (column-vector form).
glm::dmat4 rotationMatrix(const glm::dvec3& radians, int rotateOrder);

// parentFromLocal of a transform:
// Maya's M = SP⁻¹ · S · SH · SP · ST · RP⁻¹ · RA · R · RP · RT · T, returned transposed.
glm::dmat4 transformMatrix(const TransformAttrs& a);

// parentFromLocal of a joint: Maya's M = S · RA · R · JO · IS · T, returned transposed, where IS is the
// inverse of inverseScale when segmentScaleCompensate is on and the identity otherwise. A zero
// inverseScale component cannot be inverted and is treated as 1 so that no Inf reaches the matrix.
glm::dmat4 jointMatrix(const JointAttrs& a);

}  // namespace pushpin::scene
