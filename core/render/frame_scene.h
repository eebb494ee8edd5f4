// core/render/frame_scene.h: the flat scene one frame renders (DESIGN.md step 2): render objects
// (one per visible shape instance: polygon meshes, and NURBS surfaces on a uniform per-span grid)
// with their world matrix, render stats and geometry handle; the lights in world space with the objects
// each lights (light linking); the shading groups with their compiled networks. Built once per
// frame from an evaluated Graph; immutable afterwards.
// Thread safety: building reads the Graph through the caller's Evaluator and, without a memory
// cap, evaluates the shapes that render on settings.numCpusToUse threads, each with its own
// Evaluator over the same Graph (under a cap, one at a time); a finished FrameScene is read by
// every tile thread at once.
// Numbers at the door: world matrices, world bounds, light positions and light values are checked
// here (kMaxSceneCoordinate, camera.h); what cannot be rendered without overflow is skipped with
// a note naming the node, so nothing past this point meets NaN, Inf or an overflowing number.
// Memory: each object refers to a geom::GeometryHandle, shared by the instances of a shape; no
// triangles are made here (the renderer tessellates what a tile needs). Under a memory cap
// (memoryCap(settings)) no evaluated mesh is kept either: a handle evaluates its shape again, on
// the tessellating thread, from the Graph, which must therefore outlive the FrameScene.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/geometry_handle.h"
#include "core/render/fragment.h"
#include "core/render/render_settings.h"
#include "core/scene/evaluator.h"
#include "core/scene/render_setup.h"
#include "core/shade/light.h"
#include "core/shade/shading_network.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <string>
#include <vector>

namespace pushpin::render {

// A shading group as one object uses it, with the lights linked to that pair.
struct MaterialSlot {
    uint32_t shadingGroup = 0;             // index into FrameScene::shadingGroups
    std::vector<uint32_t> lights;          // indices into FrameScene::lights that light this slot
};

struct RenderObject {
    std::string name;                      // DAG path of the shape instance
    scene::NodeId shape = scene::kNoNode;
    int instance = 0;
    glm::dmat4 worldFromObject{1.0};
    geom::Bounds3 worldBounds;
    // The shape's geometry (shared with the other instances that render the same faces with the
    // same materials): bounds and cost known, triangles made on first need. Never null.
    std::shared_ptr<const geom::GeometryHandle> geometry;
    std::vector<MaterialSlot> materials;
    // render stats (reference/nodes.md §1)
    bool primaryVisibility = true;
    bool doubleSided = true;
    bool opposite = false;
    bool castsShadows = true, receiveShadows = true;
    bool smoothShading = true;
    bool shadingSamplesOverride = false;
    int shadingSamples = 1, maxShadingSamples = 1;
};

struct RenderShadingGroup {
    std::string name;
    scene::NodeId node = scene::kNoNode;
    std::shared_ptr<const shade::ShadingNetwork> network;  // never null (black when no shader)
};

struct FrameScene {
    double frame = 1.0;
    std::vector<RenderObject> objects;
    std::vector<shade::Light> lights;      // world space; never holds Maya's default light:
    // usesDefaultLight = no light of the scene is rendered and enableDefaultLight is on; the
    // renderer then adds shade::defaultLight along its camera's view, lighting every slot.
    bool usesDefaultLight = false;
    std::vector<RenderShadingGroup> shadingGroups;
    // Shapes not rendered and why ("|pCube1|pCubeShape1: belongs to no shading group"), unsupported
    // nodes met in networks, replaced NaN/Inf values … one line each, for the log and --stats.
    std::vector<std::string> notes;
    size_t skippedShapes = 0;
};

// Builds the frame: every mesh and nurbsSurface instance that is visible (Evaluator::visible), not
// an intermediate object, with primaryVisibility on, and member of a shading group (an object in
// no shading group is not rendered, reference/algorithms.md §1); its geometry handle (one per shape
// and face-material assignment, shared by instances; degenerate faces dropped); its material per face from
// whole-object and per-face (iog[i].og[j]) set membership; lights (supported types, world space)
// with light linking from lightLinker connections and `relationship "link"/"ignore"` lines (a light
// lights an (object, shading group) slot when a "link" pairs a light side containing the light —
// itself, its transform or a set holding either — with an object side containing the object or
// the shading group, and no "ignore" does; without any "link" every light lights every slot not
// ignored); usesDefaultLight when no scene light is rendered and settings.enableDefaultLight is
// on. Shapes that cannot be evaluated are skipped with a note, and so are (each with a note naming
// the DAG path, counted in skippedShapes for shapes) instances whose world matrix is not finite
// or has an entry beyond kMaxSceneCoordinate, instances whose world-space bounds reach past
// kMaxSceneCoordinate (e.g. a vertex at 1e30 or a translate of 1e308), and meshes with NaN/Inf
// points. Lights are skipped with a note for the same matrix problems, a scale 0 on their path,
// or colour × intensity beyond 1e30; a light attribute that is not finite or beyond 1e30 is
// replaced by its default with a note. Never throws for bad scene content.
FrameScene buildFrameScene(scene::Evaluator& ev, const scene::RenderSetup& setup, const RenderSettings& settings);

// A face material entry for a face that is not rendered (it belongs to no shading group).
constexpr uint16_t kNoMaterial = geom::kNoFaceMaterial;

}  // namespace pushpin::render
