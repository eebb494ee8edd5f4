// core/scene/nurbs_eval.h: the geometry of nurbsSurface and nurbsCurve shapes at one frame: decodes a
// shape's stored `cached` (`cc`) data, or evaluates the primitive creator node feeding its `create`
// (`cr`) plug (makeNurbSphere, makeNurbPlane, makeNurbCylinder, makeNurbCone, makeNurbTorus,
// makeNurbCube, makeNurbCircle) or the revolve / loft node feeding it (geom/nurbs_ops.h) with attribute
// values taken through the Evaluator (so animated attributes work); and the polygon mesh of a
// nurbsTessellate node. Other construction history is not evaluated.
// Input curves of revolve and loft come from a nurbsCurve shape's `local` plug (object space) or its
// `worldSpace[i]` plug (transformed by the world matrix of DAG instance i), or straight from a
// makeNurbCircle; the surface of a nurbsTessellate likewise from a shape's `local` / `worldSpace[i]`,
// a creator, revolve or loft node.
// Thread safety: as the Evaluator passed in (one per thread); the decode functions are pure.
// Memory: results own their knots and CVs.
//
// Rational `.cc` data: Maya writes 4 numbers per CV when `rational` is yes. No file Maya wrote with
// rational data was available to check which form xyz has; the default, RationalCvLayout::Cartesian,
// reads them as the CV's position with w as its weight (Maya's MPoint convention for CVs) and
// pre-multiplies internally. RationalCvLayout::PreMultiplied reads (x·w, y·w, z·w, w) instead.
#pragma once

#include "core/geom/mesh.h"
#include "core/geom/nurbs.h"
#include "core/scene/evaluator.h"
#include "core/scene/value.h"

#include <optional>
#include <string>
#include <vector>

namespace pushpin::scene {

enum class RationalCvLayout : unsigned char { Cartesian, PreMultiplied };

// Decodes `.cc` data of type nurbsSurface. Checks Maya's conventions: degrees >= 1, forms 0..2,
// knot count = CVs + degree − 1 per direction, cvCountU × cvCountV CVs of 3 (4 when rational) numbers,
// non-decreasing finite knots, finite CVs, positive weights. Returns nullopt and a message in *error
// (when not null) otherwise; never throws for bad data.
std::optional<geom::NurbsSurface> decodeNurbsSurface(const NurbsSurfaceData& data, std::string* error,
                                                     RationalCvLayout layout = RationalCvLayout::Cartesian);
// Decodes `.cc` data of type nurbsCurve (dimension 2 curves get z = 0). Same checks and contract.
std::optional<geom::NurbsCurve> decodeNurbsCurve(const NurbsCurveData& data, std::string* error,
                                                 RationalCvLayout layout = RationalCvLayout::Cartesian);

// The object-space surface of a nurbsSurface shape at the evaluator's frame:
// - with an incoming `create` connection from a supported creator node: that node's surface (for
//   makeNurbCube the face its outputSurface[i] / outputSurfaceN plug names);
// - from a revolve or loft node: its surface; when it cannot be evaluated, the stored `cc` data when
//   present (and *note says why), otherwise nullopt with the reason;
// - with any other incoming `create` connection: the shape's stored `cc` data when present (and
//   *note says so), otherwise nullopt with *skipReason = "history node <type> (<name>) is not evaluated";
// - without a `create` connection: the stored `cc` data.
// Returns nullopt with *skipReason (when not null) when there is nothing usable: no data, invalid data
// (the decode error, prefixed with the shape name), unusable creator attributes.
// Trim curves (`TRIM` data) are not applied; *note mentions it. Throws nothing for bad scene data.
std::optional<geom::NurbsSurface> evaluateNurbsSurface(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                       std::string* note = nullptr);
// The same for a nurbsCurve shape (`create` from makeNurbCircle, else `cc`).
std::optional<geom::NurbsCurve> evaluateNurbsCurve(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                   std::string* note = nullptr);

// The polygon mesh a nurbsTessellate node outputs at the Evaluator's frame, from the surface at its
// inputSurface. nullopt with *reason set when the surface or the settings cannot be evaluated.
std::optional<geom::Mesh> evaluateNurbsTessellate(Evaluator& ev, NodeId tessellateNode, std::string* reason,
                                                  std::vector<std::string>* notes);

}  // namespace pushpin::scene
