// core/geom/nurbs_primitives.h: NURBS surfaces and curves of Maya's primitive creator nodes
// (makeNurbSphere, makeNurbPlane, makeNurbCylinder, makeNurbCone, makeNurbTorus, makeNurbCube,
// makeNurbCircle) as pure functions of their attribute values, plus an exact rational sphere.
// Thread safety: pure functions. Memory: each result owns its CVs.
//
// How Maya builds its cubic primitives (checked against surfaces Maya wrote to .ma files: the default
// sphere, 7 × 11 CVs, and cylinders with 8 spans): every circle and arc is a NON-rational cubic
// B-spline that interpolates the exact circle at its knots — a full circle of s sections has its CVs on
// a regular s-gon of radius 3 / (2 + cos(2π/s)), CV 1 at angle 0; an open arc of n spans interpolates
// n + 1 points with end derivatives along the tangent whose length is the chord of one span. Hence a
// cubic Maya sphere is exactly round only at the knot grid and bulges by up to 0.24% of the radius
// between knots (sections 8, spans 4; measured by nurbs_primitives_test). The degree-2 sphere (`makeRationalSphere`, also chosen by
// makeNurbSphere for degree 2, which Maya itself does not offer) is exact everywhere.
// Parameter ranges: sphere/torus/circle directions run over [0, spans] and [0, sections]; cylinder and
// cone profiles over [0, length of the profile line]; planes over [0, patches].
// Orientation: for axis +Y (what Maya's UI writes) the layout matches Maya: the profile runs from −axis
// to +axis and the sweep starts at +X turning towards +Z. Other axes apply the shortest rotation from +X
// (the nodes' default axis) to `axis` to the layout Maya builds for axis +X (assumed, not verified).
#pragma once

#include "core/geom/nurbs.h"

#include <glm/vec3.hpp>

#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace pushpin::geom {

// Attribute values of the creator nodes; defaults are the node defaults (angles in radians,
// lengths in centimetres). `axis` need not be normalised but must not be zero.
struct NurbsSphereParams {
    double radius = 1.0;
    double startSweep = 0.0;
    double endSweep = 2.0 * std::numbers::pi;
    int degree = 3;  // 1 linear, 3 cubic (Maya's choices); 2 gives the exact rational sphere
    int sections = 8;
    int spans = 4;
    glm::dvec3 axis{1.0, 0.0, 0.0};
    glm::dvec3 pivot{0.0};
};

struct NurbsPlaneParams {
    double width = 1.0;
    double lengthRatio = 1.0;
    int patchesU = 1;
    int patchesV = 1;
    int degree = 3;  // 1, 2, 3, 5 or 7 in Maya; any degree up to kMaxNurbsDegree works
    glm::dvec3 axis{1.0, 0.0, 0.0};  // the plane's normal
    glm::dvec3 pivot{0.0};
};

struct NurbsCylinderParams {
    double radius = 1.0;
    double heightRatio = 2.0;  // height = radius × heightRatio
    double startSweep = 0.0;
    double endSweep = 2.0 * std::numbers::pi;
    int degree = 3;
    int sections = 8;
    int spans = 1;
    glm::dvec3 axis{1.0, 0.0, 0.0};
    glm::dvec3 pivot{0.0};
};
using NurbsConeParams = NurbsCylinderParams;  // the cone's base has `radius`, its apex is at +axis

struct NurbsTorusParams {
    double radius = 1.0;        // major radius
    double heightRatio = 0.5;   // minor radius = radius × heightRatio
    double minorSweep = 2.0 * std::numbers::pi;
    double startSweep = 0.0;
    double endSweep = 2.0 * std::numbers::pi;
    int degree = 3;
    int sections = 8;
    int spans = 4;
    glm::dvec3 axis{1.0, 0.0, 0.0};
    glm::dvec3 pivot{0.0};
};

struct NurbsCubeParams {
    double width = 1.0;
    double lengthRatio = 1.0;
    double heightRatio = 1.0;
    int patchesU = 1;
    int patchesV = 1;
    int degree = 3;
    glm::dvec3 axis{1.0, 0.0, 0.0};
    glm::dvec3 pivot{0.0};
};

struct NurbsCircleParams {
    double radius = 1.0;
    double sweep = 2.0 * std::numbers::pi;
    int degree = 3;
    int sections = 8;
    glm::dvec3 normal{0.0, 0.0, 1.0};
    glm::dvec3 center{0.0};
};

// Each returns nullopt and sets *error (when not null) for unusable values: non-finite numbers,
// radius/width <= 0, sections/spans/patches < 1 (sections < 3 for a full circle of degree 3),
// an unsupported degree, a zero axis.
std::optional<NurbsSurface> makeNurbSphere(const NurbsSphereParams& p, std::string* error);
// The exact sphere: rational biquadratic, circular arcs of at most 90° each (The NURBS Book A7.1);
// every point lies on the sphere up to rounding. Uses radius, sweeps, axis and pivot of `p`;
// at least `sections` arcs around and `spans` (min 2) arcs from pole to pole.
std::optional<NurbsSurface> makeRationalSphere(const NurbsSphereParams& p, std::string* error);
std::optional<NurbsSurface> makeNurbPlane(const NurbsPlaneParams& p, std::string* error);
std::optional<NurbsSurface> makeNurbCylinder(const NurbsCylinderParams& p, std::string* error);
std::optional<NurbsSurface> makeNurbCone(const NurbsConeParams& p, std::string* error);
std::optional<NurbsSurface> makeNurbTorus(const NurbsTorusParams& p, std::string* error);
// The six faces in Maya's output order: top, bottom, left, right, front, back (outputSurface,
// outputSurface1 … outputSurface5). Faces are planes; normals point out of the box.
std::optional<std::vector<NurbsSurface>> makeNurbCube(const NurbsCubeParams& p, std::string* error);
std::optional<NurbsCurve> makeNurbCircle(const NurbsCircleParams& p, std::string* error);

// ---- building blocks (exposed for tests)

// Unit-radius cubic B-spline points (x, y) interpolating the circle at angles start + k·Δ at knot k,
// k = 0..sections, Δ = sweep / sections. Full turn (|sweep| ≈ 2π): periodic, sections + 3 CVs with
// the 3 wrap-around CVs repeated. Otherwise open, sections + 3 CVs. See the header comment.
std::vector<glm::dvec2> cubicArcCvs(double start, double sweep, int sections, bool periodic);
// Knot vector (Maya form, without the two outermost knots) of a uniform curve with `spans` spans over
// [0, range]: clamped for open, extended by one span spacing per extra knot for periodic.
std::vector<double> uniformMayaKnots(int degree, int spans, double range, bool periodic);

}  // namespace pushpin::geom
