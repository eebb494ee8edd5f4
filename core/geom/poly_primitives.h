// core/geom/poly_primitives.h: the meshes of Maya's polygon creator nodes (polyCube, polySphere,
// polyPlane, polyCylinder, polyCone, polyTorus, polyPlatonicSolid), generated from their
// attribute values. Pure functions of their parameters; thread-safe; the returned Mesh is the
// caller's.
//
// Conventions shared by every generator:
// - Built around the origin with +Y as the primitive's up axis, then rotated by the smallest
//   rotation that takes +Y onto `axis` (Maya's `axis`/`ax` attribute). A zero or non-finite axis
//   keeps +Y; an axis opposite to +Y turns the primitive upside down about X.
// - Subdivision counts below Maya's minimums are raised to them (polySphere: 3 around, 2 high…);
//   negative sizes are treated as 0 (Maya's attribute minimum), which gives degenerate faces.
// - Non-finite sizes, and counts that would make more than kMaxPrimitiveFaces faces, are
//   rejected: the generator returns nullopt and fills `error`.
// - Faces wind counter-clockwise seen from outside, so Newell normals point outward.
// - With createUVs, UV set "map1" is filled with UVs inside [0,1]; the layouts follow Maya's where
//   noted and are documented per generator otherwise.
// - Edge flags: polyCube and polyPlatonicSolid edges are hard, the cap borders of cylinders and
//   cones are hard, every other edge is soft. Edge numbering is not Maya's.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace pushpin::geom {

constexpr size_t kMaxPrimitiveFaces = size_t(1) << 26;

struct PrimitiveAxis {
    glm::dvec3 axis{0.0, 1.0, 0.0};  // `ax`
    bool createUVs = true;           // `cuv` != 0
};

// polyCube: width (w) along X, height (h) along Y, depth (d) along Z; sw/sh/sd ≥ 1.
// Point order is Maya's: rows of sw+1 points along X walk a belt around the cube (front bottom
// to front top, over the top, down the back, under the bottom), then the interior points of the
// +X side, then those of the -X side. Faces: the belt (front, top, back, bottom), then +X, then
// -X. For 1×1×1 this is exactly Maya's 8-point, 6-face, 14-UV cube (reference/ma-format.md).
struct PolyCubeParams : PrimitiveAxis {
    double width = 1.0, height = 1.0, depth = 1.0;
    int subdivisionsWidth = 1, subdivisionsHeight = 1, subdivisionsDepth = 1;
};
std::optional<Mesh> makePolyCube(const PolyCubeParams& p, std::string* error = nullptr);

// polySphere: sa ≥ 3 points per ring, sh ≥ 2 bands. Points: sh−1 rings from the south (−Y) pole
// up, sa each, then the south pole, then the north pole (sa·(sh−1)+2 points, Maya's order). A
// ring's first point is one step (2π/sa) round from +X towards −Z, as in Maya's files.
// Faces: quads band by band, then the south triangle fan, then the north one (sa·sh faces).
// UVs: u = around/sa over sa+1 columns per ring, v = band/sh; each pole triangle has its own pole
// UV ((sa+1)·(sh−1) + 2·sa UVs, as Maya).
struct PolySphereParams : PrimitiveAxis {
    double radius = 1.0;
    int subdivisionsAxis = 20, subdivisionsHeight = 20;
};
std::optional<Mesh> makePolySphere(const PolySphereParams& p, std::string* error = nullptr);

// polyPlane: width (w) along X, height (h) along Z, facing +Y; (sw+1)·(sh+1) points, row by row
// from (−w/2, 0, h/2) with X varying fastest; UV (0,0) at the first point, (1,1) at the last.
struct PolyPlaneParams : PrimitiveAxis {
    double width = 1.0, height = 1.0;
    int subdivisionsWidth = 10, subdivisionsHeight = 10;
};
std::optional<Mesh> makePolyPlane(const PolyPlaneParams& p, std::string* error = nullptr);

// polyCylinder: radius r, height h centred on the origin, sa ≥ 3 around, sh ≥ 1 bands, sc ≥ 0 cap
// rings; each ring starts one step (2π/sa) round from +X towards −Z, as in Maya's files. Points: sh+1 side rings bottom to top, then the bottom cap's inner rings (outside in) and
// centre, then the top cap's (for sc = 1: bottom centre, then top centre, as Maya). sc = 0 closes each end with
// one n-gon. Faces: side quads band by band, then the bottom cap, then the top cap.
// Counts: sa·(sh+1) + 2·sa·(sc−1) + 2 points and sa·sh + 2·sa·sc faces for sc ≥ 1.
// UVs: side band u ∈ [0,1], v ∈ [0.3125, 0.6875]; caps are discs of radius 0.15625 centred at
// (0.5, 0.15625) (bottom) and (0.5, 0.84375) (top). `roundCap` is not modelled (flat caps).
struct PolyCylinderParams : PrimitiveAxis {
    double radius = 1.0, height = 2.0;
    int subdivisionsAxis = 20, subdivisionsHeight = 1, subdivisionsCaps = 1;
    bool roundCap = false;
};
std::optional<Mesh> makePolyCylinder(const PolyCylinderParams& p, std::string* error = nullptr);

// polyCone: base radius r at y = −h/2, apex at +h/2; sa ≥ 3, sh ≥ 1, sc ≥ 0 (0: the base is one
// n-gon). Points: sh rings bottom up (sa each), then the apex, then inner base rings and the base
// centre (sc ≥ 1). Faces: side quads, the apex triangles, then the base. UVs: side band as the
// cylinder's with one apex UV per apex triangle, base disc as the cylinder's bottom cap.
struct PolyConeParams : PrimitiveAxis {
    double radius = 1.0, height = 2.0;
    int subdivisionsAxis = 20, subdivisionsHeight = 1, subdivisionsCap = 0;
};
std::optional<Mesh> makePolyCone(const PolyConeParams& p, std::string* error = nullptr);

// polyTorus: ring radius r in the XZ plane, tube radius sr, twist (radians) rotating every
// section, sa ≥ 3 sections around Y, sh ≥ 3 points per section. sa·sh points (section by
// section), sa·sh quads, (sa+1)·(sh+1) UVs.
struct PolyTorusParams : PrimitiveAxis {
    double radius = 1.0, sectionRadius = 0.5, twistRadians = 0.0;
    int subdivisionsAxis = 20, subdivisionsHeight = 20;
};
std::optional<Mesh> makePolyTorus(const PolyTorusParams& p, std::string* error = nullptr);

// polyPlatonicSolid: solidType 0 dodecahedron, 1 icosahedron, 2 octahedron, 3 tetrahedron, with
// circumradius `radius`, in the textbook orientation (coordinates from ±1 and the golden ratio;
// the octahedron has a vertex on +Y). UVs: each face gets its own cell of a grid
// in [0,1]² (Maya's unfolded layouts are not reproduced).
struct PolyPlatonicParams : PrimitiveAxis {
    double radius = 1.0;
    int solidType = 0;
};
std::optional<Mesh> makePolyPlatonicSolid(const PolyPlatonicParams& p, std::string* error = nullptr);

// Column-vector rotation taking +Y onto `axis` (identity for +Y, zero or non-finite axes).
glm::dmat3 axisRotation(const glm::dvec3& axis);

// What a generator's mesh will hold, known without making it: exact counts of points, faces,
// face-vertices, edges and triangles (each face fanned), at most `uvs` UVs, and object-space
// bounds that hold every point (float rounding included: the box of the primitive's corners or
// sphere, widened by a millionth of its reach).
struct PrimitiveCounts {
    uint64_t points = 0, faces = 0, faceVertices = 0, edges = 0, uvs = 0, triangles = 0;
    Bounds3 bounds;
};

// The counts of makePolySphere, makePolyPlane, makePolyCube, makePolyCylinder, makePolyCone and
// makePolyTorus for the same parameters, when the
// generator makes a mesh without degenerate faces: nullopt when it would fail, when a size is not
// positive, or when its cells would be so thin or small that float points could make faces
// degenerate (the generator and Mesh::validate then decide).
std::optional<PrimitiveCounts> polySphereCounts(const PolySphereParams& p);
std::optional<PrimitiveCounts> polyPlaneCounts(const PolyPlaneParams& p);
std::optional<PrimitiveCounts> polyCubeCounts(const PolyCubeParams& p);
std::optional<PrimitiveCounts> polyCylinderCounts(const PolyCylinderParams& p);
std::optional<PrimitiveCounts> polyConeCounts(const PolyConeParams& p);
// A torus whose section radius is not below its ring radius meets itself at the axis: nullopt.
std::optional<PrimitiveCounts> polyTorusCounts(const PolyTorusParams& p);

}  // namespace pushpin::geom
