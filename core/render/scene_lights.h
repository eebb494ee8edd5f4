// core/render/scene_lights.h: a frame's lights (DESIGN.md step 2) and which objects each lights.
// Lights are read in world space with numbers at the door: a light that cannot be placed, or
// whose emitted colour would overflow a float, is skipped with a note naming it; a value that is
// not finite or beyond 1e30 is replaced by its default with a note. Light linking follows
// reference/nodes.md §5.
#pragma once

#include "core/render/frame_scene.h"
#include "core/scene/evaluator.h"
#include "core/scene/graph.h"
#include "core/scene/render_setup.h"
#include "core/shade/light.h"

#include <string>
#include <vector>

namespace pushpin::render {

// The lights that render, in the render setup's order, with the DAG path each was read at.
struct SceneLights {
    std::vector<shade::Light> lights;
    std::vector<std::vector<scene::NodeId>> paths;  // parallel to lights
};

// Reads every light of `setup` that renders: ambient, directional, point and spot lights that
// are visible, at the evaluator's frame. What is skipped or replaced gets a note in `notes`.
SceneLights readSceneLights(scene::Evaluator& ev, const scene::RenderSetup& setup, std::vector<std::string>& notes);

// Fills the `lights` of every material slot of scene.objects (scene.lights read at `lightPaths`,
// each object at objectPaths[o]): light L lights (object O, shading group S) when a "link" pairs
// a light side containing L with an object side containing O or S, and no "ignore" does; without
// any "link" in the scene every light lights everything not explicitly ignored. A side names a
// light or object directly, a DAG ancestor of it, a set containing it (sets nest, to a depth of
// 16) or, on the object side, its shading group.
void linkLights(const scene::Graph& g, const scene::RenderSetup& setup,
                const std::vector<std::vector<scene::NodeId>>& lightPaths,
                const std::vector<std::vector<scene::NodeId>>& objectPaths, FrameScene& scene);

}  // namespace pushpin::render
