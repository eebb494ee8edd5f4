// core/geom/nurbs_ops.h: NURBS construction history as pure functions: the surface a `revolve` node
// builds from a profile curve, the surface a `loft` node skins through section curves, and the polygon
// mesh a `nurbsTessellate` node ("NURBS to Polygons") makes of a surface. Also the curve edits they are
// built on (knot insertion, clamping, degree elevation, reversal, affine transforms).
// Thread safety: pure functions of their arguments. Memory: results own their knots, CVs and arrays.
//
// What is verified against Maya and what is not:
// - revolve. U is the profile curve (its degree, knots and form are kept), V the sweep, as the
//   revolvedPrimitive surfaces Maya writes (makeNurbSphere: U pole to pole, V around). The sweep circle
//   is built exactly as nurbs_primitives.h builds the primitives' circles (checked against Maya's files):
//   degree 3 is a NON-rational cubic B-spline interpolating the circle at its s + 1 knots (periodic with
//   s + 3 CVs for a full turn, open with s + 3 CVs otherwise), degree 1 the inscribed polygon; the V
//   knots are uniform over [0, sections]. That the revolve node itself uses the same construction (and
//   not a rational circle) is assumed from the shared revolvedPrimitive code path, not checked on a
//   file written by a revolve node. The sweep turns the radial direction r towards r × axis (for axis
//   +Y: from +X towards +Z), the primitives' direction; for a profile running along +axis the normal
//   dP/du × dP/dv then points away from the axis.
// - loft. U is the loft direction and V the curves' direction (Maya's Loft documentation: "the first
//   profile curve corresponds to the isoparm on the surface at U[0], the second to U[1]");
//   reverseSurfaceNormals swaps U and V (loft command documentation). Uniform spacing puts section k
//   at u = k; chord-length spacing at the accumulated distance between the curves' start points
//   (documented). Unverified: the cubic interpolation's end conditions (natural: zero second
//   derivative at the first and last section, so N sections give N − 1 spans and N + 2 CVs) and how
//   Maya makes curves of different degree or knots compatible (here: exact degree elevation and knot
//   merging, all curves reparametrised to the first curve's domain).
// - tessellation. The grid follows the documented uType/uNumber meaning; the count of segments per span
//   (uNumber + 1: uNumber isoparms inside each span) matches the polyTweak/deleteComponent indices of
//   a Maya-tessellated loft in a real scene (13 vertices per row from uNumber 5 over 2 spans); the
//   other types, the refinement passes and formats 0 and 1 are documented approximations.
#pragma once

#include "core/geom/mesh.h"
#include "core/geom/nurbs.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace pushpin::geom {

// ---- revolve

// Attribute values of a revolve node (angles in radians, lengths in centimetres); defaults are the
// node's. `axis` need not be normalised but must not be zero.
struct RevolveParams {
    glm::dvec3 axis{1.0, 0.0, 0.0};
    glm::dvec3 pivot{0.0};
    double startSweep = 0.0;
    double endSweep = 2.0 * std::numbers::pi;  // |endSweep − startSweep| is clamped to 2π
    int degree = 3;                            // 1 linear or 3 cubic in the sweep direction
    int sections = 8;                          // spans in the sweep direction
    bool useTolerance = false;                 // choose the sections from `tolerance` instead
    double tolerance = 0.01;                   // largest distance of the sweep from the true circle
    bool autoCorrectNormal = false;            // reverse the axis if the normal would face the axis
};

// The surface of revolution of `profile`. Every point of the profile at parameter u, at distance ρ from
// the axis, sweeps a circle of radius ρ about it: exactly at the V knots, within the cubic's bulge
// (about 0.2% of ρ for 8 sections over 360°) in between. At startSweep = 0 the isoparm v = 0 is the
// profile. useTolerance picks the fewest sections (at most 1024) keeping the largest radial error of
// the sweep below `tolerance` for the profile CV farthest from the axis. Returns nullopt and sets
// *error (when not null) for non-finite values, a zero axis or sweep, an unsupported degree, too few
// sections (1 for an arc, 3 for a full turn), or a profile lying on the axis.
std::optional<NurbsSurface> revolveCurve(const NurbsCurve& profile, const RevolveParams& p, std::string* error);

// ---- loft

// Attribute values of a loft node; defaults are the node's.
struct LoftParams {
    bool uniform = false;                // true: section k at u = k; false: chord length between start points
    bool close = false;                  // periodic in the loft direction, back to the first curve
    int degree = 3;                      // 1 or 3 in the loft direction
    bool reverseSurfaceNormals = false;  // swap U and V
    bool autoReverse = true;             // reverse curves running against their predecessor
    int sectionSpans = 1;                // spans between consecutive sections (>= 1)
    std::vector<bool> reverse;           // per curve, used when autoReverse is false
};

// The skinned surface through `curves` (at least 2, at most 512): S(u_k, v) = curve k at v, for the
// section parameters u_k, in the domain of the first curve (the others are reparametrised linearly
// onto it). Curves whose degrees or knots differ are made compatible exactly (degree elevation, knot
// merging); the V direction is then clamped (Closed when every curve is closed) instead of keeping a
// periodic form. Rational curves are interpolated in homogeneous space, so sections stay exact.
// Chord-length spacing falls back to uniform when two consecutive start points coincide. A closed loft
// with sectionSpans > 1 is clamped at the seam (form Closed). Returns nullopt with *error for unusable
// input (fewer than 2 curves, unsupported degree, sectionSpans < 1, a singular interpolation).
std::optional<NurbsSurface> loftCurves(const std::vector<NurbsCurve>& curves, const LoftParams& p, std::string* error);

// ---- extrude

// Maya's extrude: distance (the profile moved along a direction by a length; exact), flat (the
// profile translated along a path curve; exact for non-rational curves) or tube (the profile
// carried along the path in a rotation-minimising frame: sections every quarter span of the path,
// at least 8, lofted cubically, an approximation). U runs along the length or path, V along the
// profile. The path starts at its end nearer the profile; with fixedPath the profile's bounding-box
// centre rides on the path (the surface lies along the path), else the path's start is moved onto
// the profile.
enum class ExtrudeType { Distance, Flat, Tube };  // Maya's extrudeType 0, 1, 2
struct ExtrudeParams {
    ExtrudeType type = ExtrudeType::Tube;
    glm::dvec3 direction{0.0, 1.0, 0.0};
    double length = 1.0;
    int degreeAlongLength = 1;
    bool fixedPath = false;
};
std::optional<NurbsSurface> extrudeCurve(const NurbsCurve& profile, const NurbsCurve* path, const ExtrudeParams& p,
                                         std::string* error);

// ---- tessellation (nurbsTessellate)

// Maya's `format` values.
enum class TessellationFormat : int { TriangleCount = 0, StandardFit = 1, General = 2, ControlPoints = 3 };
// Maya's `uType`/`vType` values (MTesselationParams isoparm types, in enum order).
enum class IsoparmType : int { Surface3DDistance = 0, Surface3DEquiSpaced = 1, SurfaceEquiSpaced = 2, SpanEquiSpaced = 3 };

// Attribute values of a nurbsTessellate node; defaults are the node's (parentTessellate docs).
struct TessellateParams {
    int format = 1;        // TessellationFormat
    int polygonType = 0;   // 0 triangles, 1 quads
    int polygonCount = 200;
    int uType = 3;         // IsoparmType
    int vType = 3;
    int uNumber = 3;
    int vNumber = 3;
    bool useChordHeight = false;
    double chordHeight = 0.1;  // object-space distance
    bool useChordHeightRatio = true;
    double chordHeightRatio = 0.983;
    double delta = 0.1;  // Standard Fit's 3D delta
    bool matchNormalDir = false;
};

// The polygon mesh of `surface` (object space), with one UV set "map1" of normalised parameters
// ((u − uMin)/(uMax − uMin), (v − vMin)/(vMax − vMin)), no stored normals and no edge list (all soft).
//
// Grid: parameters u_0 < … < u_{m−1} and v_0 < … < v_{n−1} spanning the whole domain.
// - General (2): per direction by its type: SpanEquiSpaced, number + 1 equal segments in every span;
//   SurfaceEquiSpaced, number + 1 equal segments over the domain; Surface3DEquiSpaced, number + 1
//   segments of equal length along the middle isoparm; Surface3DDistance is taken as
//   Surface3DEquiSpaced (noted). Then, when useChordHeight / useChordHeightRatio are on, every grid
//   interval whose midpoint deviates from its chord by more than chordHeight or (1 − ratio) × chord
//   length on some grid line is halved (whole grid lines, so the mesh stays a grid), at most 10 times.
//   Maya refines adaptively per polygon; counts then differ from Maya's (noted when it happens).
// - StandardFit (1): General with one segment per span, refined by chordHeightRatio and by chord
//   height `delta` (approximation, noted).
// - TriangleCount (0): an equal-parameter grid sized so that its polygon count is near polygonCount,
//   split between U and V by the surface's average isoparm lengths (approximation, noted).
// - ControlPoints (3): the CVs themselves (Cartesian), the `degree` wrap-around CVs of periodic
//   directions joined to the first ones; UVs are the CV indices normalised to [0, 1].
//   matchNormalDir is not modelled: faces always wind as below (noted when it is on).
// Order: grid points are visited with u fastest (index j·m + i for u_i, v_j), and faces likewise
// (row j, column i: corners (i, j), (i+1, j), (i+1, j+1), (i, j+1), winding so that the face normal
// follows dP/du × dP/dv). Points that coincide along a seam of the grid (last column with the first,
// last row with the first) or along a collapsed row or column (a pole) are one vertex; vertices are
// numbered in order of first visit. A face that loses a corner this way becomes a triangle, one that
// keeps fewer than 3 corners is dropped. Triangles (polygonType 0) split each quad along the
// (i, j)–(i+1, j+1) diagonal into (c0, c1, c2) and (c0, c2, c3), in place of the quad.
// UV values are one per grid point (seams keep u = 0 and u = 1 apart), index j·m + i.
// Returns nullopt and sets *error (when not null) for unusable settings (numbers < 1 or not finite,
// unknown format/type, a grid above 4M points) or a surface that evaluates to NaN/Inf. `notes` (when
// not null) receives what is approximated.
std::optional<Mesh> tessellateSurface(const NurbsSurface& surface, const TessellateParams& p, std::string* error,
                                      std::vector<std::string>* notes = nullptr);

// ---- curve and surface edits (exposed for tests)

// The curve with CVs mapped by the affine transform `m` (column vectors); weights kept.
std::optional<NurbsCurve> transformCurve(const NurbsCurve& c, const glm::dmat4& m, std::string* error);
std::optional<NurbsSurface> transformSurface(const NurbsSurface& s, const glm::dmat4& m, std::string* error);
// The same curve run backwards over the same domain: C'(t) = C(tMin + tMax − t).
// These four return nullopt only when the result is not a valid curve (non-finite input).
std::optional<NurbsCurve> reverseCurve(const NurbsCurve& c);
// The same curve with knot t (inside the domain, else nullopt) inserted once (Boehm; The NURBS Book A5.1).
std::optional<NurbsCurve> insertKnot(const NurbsCurve& c, double t);
// The same curve with end knots of multiplicity degree + 1 (periodic curves unrolled); form Closed when
// its ends meet, else Open.
std::optional<NurbsCurve> clampCurve(const NurbsCurve& c);
// The same curve clamped and raised to `degree` (>= its own, else nullopt), exactly, through its
// Bézier segments (interior knots end with multiplicity `degree`).
std::optional<NurbsCurve> elevateCurveDegree(const NurbsCurve& c, int degree);

// The most cuts a detach, or knot values an insertion, takes (each costs a pass over the CVs).
inline constexpr size_t kMaxSurfaceEdits = 4096;

// detachSurface: the pieces of `s` cut across U (directionU) or V at each parameter strictly
// inside the domain, in order (a surface with no such parameter comes back whole, clamped). Each
// cut is raised to full multiplicity by knot insertion, so every piece is exactly the part of the
// surface over its range, with the same parameters. A periodic direction is refused (nullopt with
// `error`): opening it is not evaluated.
std::optional<std::vector<NurbsSurface>> detachSurface(const NurbsSurface& s, bool directionU, std::vector<double> params,
                                                       std::string* error);

// insertKnotSurface: each (parameter, count) inserted `count` times across U (directionU) or V, up
// to full multiplicity; parameters outside the domain insert nothing. The surface is unchanged as a
// shape. A periodic direction is refused.
std::optional<NurbsSurface> insertSurfaceKnots(const NurbsSurface& s, bool directionU,
                                               const std::vector<std::pair<double, int>>& inserts, std::string* error);

// rebuildSurface with Maya's uniform rebuild type: in each direction asked for, a surface of the
// given degree and spans with uniform knots (clamped ends; periodic stays periodic) over the new
// range, interpolating the input at the new knots' Greville abscissae (mapped linearly onto the
// input's range). With keepControlPoints the CVs stay and only the range changes. The fit is this
// renderer's own: Maya's CVs for the same request may differ.
enum class RebuildRange { ZeroToOne, Original, ZeroToSpans };  // Maya's keepRange 0, 1, 2
struct RebuildParams {
    bool rebuildU = true, rebuildV = true;
    int spansU = 4, spansV = 4;
    int degreeU = 3, degreeV = 3;
    RebuildRange range = RebuildRange::Original;
    bool keepControlPoints = false;
};
inline constexpr int kMaxRebuildSpans = 1024;
std::optional<NurbsSurface> rebuildSurface(const NurbsSurface& s, const RebuildParams& params, std::string* error);

}  // namespace pushpin::geom
