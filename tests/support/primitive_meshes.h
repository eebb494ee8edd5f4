// tests/support/primitive_meshes.h: the unit cube and the subdivided unit plane the geometry
// tests start from, built by core/geom/poly_primitives.h with Maya's numbering.
#pragma once

#include "core/geom/poly_primitives.h"

namespace pushpin::test {

// polyCube 1 × 1 × depth.
inline geom::Mesh unitCube(double depth = 1.0) {
    geom::PolyCubeParams p;
    p.depth = depth;
    return *geom::makePolyCube(p);
}

// polyPlane 1 × 1 facing +Y with sw × sh faces.
inline geom::Mesh unitPlane(int sw, int sh) {
    geom::PolyPlaneParams p;
    p.subdivisionsWidth = sw;
    p.subdivisionsHeight = sh;
    return *geom::makePolyPlane(p);
}

}  // namespace pushpin::test
