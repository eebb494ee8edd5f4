// core/scene/mesh_eval.h: turns a Maya mesh shape into a geom::Mesh at one frame: the shape's own
// stored data (.vt/.ed/.fc/.uvst/.n/.pt, reference/ma-format.md "Mesh shape"), or the construction
// history feeding its inMesh: creator nodes (polyCube, polySphere, polyPlane, polyCylinder,
// polyCone, polyTorus, polyPlatonicSolid) and the common cheap history nodes (polyTweak,
// polyTweakUV, groupParts, transformGeometry, deleteComponent, polySoftEdge, polyNormal,
// createColorSet, polyTriangulate, the UV-only and normal-only nodes passed through, another mesh's
// outMesh/worldMesh), the deformers of deformer_eval.h (tweak, cluster, nonLinear, skinCluster,
// given their input in object space), nurbsTessellate of a NURBS surface (nurbs_eval.h) and nCloth,
// which is not simulated: its input mesh is used. deleteComponent deletes the listed faces and
// every face using a listed vertex or edge, then drops unused points (Maya merges the faces
// around a deleted edge or vertex instead; that merge is not modelled). polyNormal passes the
// mesh through unchanged (noted). groupParts component lists are recorded as written, relative
// to the mesh at that point of the history. Other history nodes are not evaluated: the shape is skipped with a
// reason, unless it caches its final geometry in .vt/.fc, which is then used.
// Thread safety: uses the given Evaluator, which is single-threaded; use one Evaluator per thread.
// Memory: the returned mesh belongs to the caller.
#pragma once

#include "core/geom/mesh.h"
#include "core/geom/mesh_pieces.h"
#include "core/geom/poly_primitives.h"
#include "core/scene/evaluator.h"
#include "core/scene/graph.h"
#include "core/scene/value.h"

#include <optional>
#include <string>
#include <vector>

namespace pushpin::scene {

// A component group a groupParts node defines on the way to the shape (`inputComponents`),
// e.g. the faces of a per-face shading assignment. `groupId` is the id of the groupId node
// feeding groupParts.groupId, -1 when none is connected or set.
struct MeshComponentGroup {
    std::string groupParts;  // node name
    int groupId = -1;
    ComponentList components;
};

struct MeshEvaluation {
    std::optional<geom::Mesh> mesh;        // nullopt: skipped, see skipReason
    std::string skipReason;                // "history node polySplit (polySplit1) is not evaluated", …
    std::vector<std::string> notes;        // approximations and recoveries worth reporting
    std::vector<std::string> history;      // "type name" of each node evaluated, nearest the shape first
    std::vector<MeshComponentGroup> groups;
    bool usedCachedData = false;           // history was not evaluable; the shape's stored data was used
    // When the shape renders its smooth mesh preview: per face of `mesh`, the face of the
    // unsmoothed mesh it comes from (the faces shading assignments name), and how many there were.
    std::vector<uint32_t> faceOrigin;
    size_t sourceFaceCount = 0;
    // The degenerate faces of `mesh` (geom::MeshValidation::degenerateFaces) when the evaluation
    // validated the mesh it returns; nullopt when the mesh changed after that check.
    std::optional<std::vector<uint32_t>> degenerateFaces;
};

// Evaluates mesh shape `meshShape` at the Evaluator's frame. Never throws for bad scene content:
// malformed data, unknown history and non-finite creator attributes give a skip reason.
// Shape tweaks (.pt) are added to the result whether it comes from stored data or history. A
// shape showing its smooth mesh preview (displaySmoothMesh on) renders it, as Maya Software does:
// Catmull-Clark at smoothLevel (renderSmoothLevel when useSmoothPreviewForRender is off).
MeshEvaluation evaluateMeshShape(Evaluator& ev, NodeId meshShape);

// What evaluateMeshShape would give for a shape whose mesh comes straight from a polySphere,
// polyPlane, polyCube, polyCylinder (flat caps), polyCone or polyTorus (its inMesh connected to
// the creator, no point tweaks, no smooth mesh preview), known without making it: the mesh's counts and object-space bounds, so that making it
// can wait until it is needed. nullopt for every other shape, and where the primitive's counts do
// not vouch for a mesh without degenerate faces (geom::polySphereCounts and the like).
std::optional<geom::PrimitiveCounts> primitiveShapeCounts(Evaluator& ev, NodeId meshShape);

// The same, reduced to the mesh; on a skip, `skipReason` (if given) receives the reason.
std::optional<geom::Mesh> evaluateMesh(Evaluator& ev, NodeId meshShape, std::string* skipReason);

// Evaluates the mesh a history node's output plug carries (polyExtrudeFace1.output, a shape's
// worldMesh[0], …), as a shape's history is evaluated: the mesh, a skip reason and notes.
MeshEvaluation evaluateMeshPlug(Evaluator& ev, const Plug& output);

// Decodes the shape's own stored data, without tweaks and without looking at history.
// Returns nullopt with `error` set when the data is missing or inconsistent (an edge index out of
// range, a face whose edges do not meet, …); recoverable oddities go to `notes`.
std::optional<geom::Mesh> decodeStoredMesh(const Graph& graph, NodeId meshShape, std::string* error,
                                           std::vector<std::string>* notes = nullptr);

// True when the shape stores its own geometry (.vt and .fc).
bool hasStoredMesh(const Graph& graph, NodeId meshShape);

// Whether evaluateMeshShape gives the shape's stored mesh as decodeStoredMesh decodes it (no
// history, no point tweaks, no smooth mesh preview), from face records that follow one another
// from face 0 and uvs in uvSet[k].uvSetPoints: then decodeStoredMeshWindow can make any part of it.
bool storedMeshMakesWindows(Evaluator& ev, NodeId meshShape);

// The window of piece `piece` of `pieces` (split from the whole decoded mesh, which has
// `faceVertexCount` face-vertices) decoded from the stored data alone: geom::cutMeshWindow of the
// whole mesh, without making the rest. nullopt when the stored data does not hold it.
std::optional<geom::MeshWindow> decodeStoredMeshWindow(const Graph& graph, NodeId meshShape,
                                                       const geom::MeshPieces& pieces, size_t piece,
                                                       uint64_t faceVertexCount);

}  // namespace pushpin::scene
