// core/scene/deformer_eval.h: Maya's common mesh deformers evaluated at one frame: tweak, cluster,
// nonLinear (with a deformBend, deformFlare, deformSine, deformSquash, deformTwist or deformWave
// handle) and skinCluster. Each moves the points of the geometry arriving at one of its inputs the
// way the deformer's outputGeometry carries them; topology, UVs and colours pass through.
// Attribute values and matrices are read through the Evaluator, so animated parameters, handles
// and joints work. Matrices follow Maya's row-vector convention in the file and are used here as
// column-vector GLM matrices (core/scene/evaluator.h).
//
// Spaces. Points are in the object space of the geometry. A deformer that works in world space
// (cluster, skinCluster) or in its handle's space (nonLinear) goes there through the geometry's
// world matrix: geomMatrix[geometryIndex] (`gm`) where it is stored or connected; for nonLinear
// without one, the world matrix of the shape whose worldMesh starts the chain of history feeding
// the deformer (Maya hands deformers that matrix with the geometry; outMesh data carries none).
//
// Thread safety: uses the given Evaluator, which is single-threaded; use one Evaluator per thread.
// Memory: edits the caller's mesh in place; temporary arrays are the size of its point list.
#pragma once

#include "core/geom/mesh.h"
#include "core/scene/evaluator.h"
#include "core/scene/graph.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::scene {

// True for the deformer node types applyDeformer evaluates: tweak, cluster, nonLinear, skinCluster.
bool isEvaluatedDeformer(std::string_view type);

// Deforms `mesh`, the geometry arriving at input[geometryIndex].inputGeometry of deformer node
// `deformer`, into what its outputGeometry[geometryIndex] carries at the Evaluator's frame.
// `members` (may be null = every point) marks the points of the deformer's set (from the groupParts
// feeding it); points past its end are not members. Returns an empty string on success, else the
// reason the shape cannot be rendered; on failure `mesh` is left as it was. Notes about
// approximations go to `notes`. Never throws for bad scene content: non-finite parameters,
// matrices or results give a reason and never reach the mesh.
//
// What each type honours (the formulas are in deformer_eval.cpp):
// - every type: envelope (`en`, default 1); points outside `members` stay where they are.
// - tweak: plist[g].controlPoints (double3) and vlist[g].vertex (float3) offsets, added together;
//   relativeTweak (`rtw`) off makes the listed entries absolute positions.
// - cluster: weightList[g].weights (default 1); absolute mode moves world-space points by
//   matrix · bindPreMatrix (`ma`, `pm`); relative mode (`rel`) by the handle's local matrix taken
//   in its parent's space (from the transform driving `ma`, else the stored
//   postMatrix · weightedMatrix · preMatrix). A weight w moves a point by w of the full motion.
// - nonLinear: weightList[g].weights (default 1); parameters from the node's own (addAttr'd)
//   attributes, else from the handle shape feeding its deformerData (`dd`); handle space is
//   inverse(matrix) · geomMatrix.
// - skinCluster: weightList[i].weights[j] (default 0), matrix[j], bindPreMatrix[j], geomMatrix,
//   normalizeWeights (2 = post: weights divided by their sum), skinningMethod 0 linear,
//   1 dual quaternion, 2 blended by blendWeights[i]. Points whose weights sum to 0 stay put.
std::string applyDeformer(Evaluator& ev, NodeId deformer, uint32_t geometryIndex, const std::vector<bool>* members,
                          geom::Mesh& mesh, std::vector<std::string>& notes);

}  // namespace pushpin::scene
