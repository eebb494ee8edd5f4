// core/scene/scene_info.h: the scene report behind `pushpin --info`: node-type counts, shapes
// (renderable or why not, world bounds, shading groups), cameras, lights, shading groups, the
// render globals in effect, unsupported node types and attributes, and warnings.
// Evaluates geometry at the requested frame to find bounds; builds no render data.
#pragma once

#include "core/geom/bounds.h"
#include "core/scene/graph.h"
#include "core/scene/not_rendered.h"
#include "core/util/json_writer.h"

#include <string>
#include <vector>

namespace pushpin::scene {

struct ShapeReport {
    std::string name;  // the shape node's name
    std::string path;  // DAG path of this instance
    std::string type;  // mesh, nurbsSurface
    NodeId shape = kNoNode;
    int instance = 0;
    bool renderable = false;
    std::string reason;          // why not renderable (empty when renderable)
    geom::Bounds3 worldBounds;   // empty when the geometry could not be evaluated
    std::vector<std::string> shadingGroups;
    size_t vertices = 0, faces = 0;  // polygon counts (meshes) or CV counts (NURBS: cvsU*cvsV, 0)
};

struct SceneReport {
    double frame = 1.0;
    std::vector<ShapeReport> shapes;
    std::vector<std::string> warnings;  // reader and evaluation warnings, one line each
    size_t renderableShapes = 0, skippedShapes = 0;
};

// The frame a scene opens at: time1.outTime when the file sets it, else renderGlobals.startFrame.
double sceneCurrentFrame(const Graph& graph);
// Evaluates every mesh and NURBS surface instance at `frame`. Never throws for bad geometry: a
// shape that cannot be built is reported with its reason.
SceneReport describeScene(const Graph& graph, double frame);
// One {feature, nodes, count} entry of "notRendered" (--info and --stats).
void writeNotRendered(util::JsonWriter& w, const NotRendered& n);
// The whole report as one JSON object (the `--info` output).
std::string sceneInfoJson(const Graph& graph, double frame);

}  // namespace pushpin::scene
