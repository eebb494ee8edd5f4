#include "core/render/frame_scene.h"

#include "core/geom/finite.h"
#include "core/geom/geometry_handle.h"
#include "core/geom/nurbs.h"
#include "core/render/camera.h"
#include "core/render/scene_lights.h"
#include "core/render/shape_geometry.h"
#include "core/scene/components.h"
#include "core/scene/mesh_eval.h"
#include "core/util/format.h"
#include "core/util/release.h"

#include "cache/error.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <memory>
#include <cmath>
#include <new>
#include <numbers>
#include <numeric>
#include <optional>
#include <unordered_map>

namespace pushpin::render {

using scene::Graph;
using scene::NodeId;
using scene::kNoNode;

namespace {

// Why world-space bounds are beyond what the renderer can project, or empty when they are not.
std::string boundsProblem(const geom::Bounds3& b) {
    for (int k = 0; k < 3; ++k) {
        for (double v : {b.lo[k], b.hi[k]})
            if (!std::isfinite(v) || std::abs(v) > kMaxSceneCoordinate)
                return "world-space bounds reach " + util::formatNumber(v, 6) + ", beyond 1e18 scene units";
    }
    return {};
}

// One shading-group membership of a shape instance.
struct Membership {
    const scene::ShadingGroupInfo* group = nullptr;
    const scene::SetMember* member = nullptr;
};

// Every shading-group membership by member shape, in the order of the sets in the scene.
std::unordered_map<NodeId, std::vector<Membership>> membershipsByShape(const scene::RenderSetup& setup) {
    std::unordered_map<NodeId, std::vector<Membership>> out;
    for (const scene::ShadingGroupInfo& sg : setup.shadingGroups) {
        if (!sg.inRenderPartition) continue;  // outside the render partition nothing renders
        for (const scene::SetMember& m : sg.members) out[m.shape].push_back({&sg, &m});
    }
    return out;
}

// The groupId node wired to shape.instObjGroups[instance].objectGroups[group].objectGroupId.
NodeId objectGroupIdNode(const Graph& g, NodeId shape, int instance, int group) {
    for (const scene::Connection* c : g.inputs(shape)) {
        auto segs = scene::parsePlugPath(c->dst.path);
        if (!segs || segs->size() != 3) continue;
        const auto& s = *segs;
        if (s[0].name != "instObjGroups" || s[1].name != "objectGroups" || s[2].name != "objectGroupId") continue;
        if ((s[0].indexed() ? s[0].first : 0) != instance || (s[1].indexed() ? s[1].first : 0) != group) continue;
        return c->src.node;
    }
    return kNoNode;
}

// Face components of a per-face membership: the member's own objectGrpCompList, or, when that is
// empty, the groupParts component list of the mesh history tied to the same groupId node.
scene::ComponentList memberComponents(scene::Evaluator& ev, const scene::SetMember& m,
                                      const scene::MeshEvaluation& evaluation) {
    if (!m.components.empty()) return scene::ComponentList{m.components};
    const Graph& g = ev.graph();
    const NodeId groupId = objectGroupIdNode(g, m.shape, m.instance, m.objectGroup);
    if (groupId == kNoNode) return {};
    for (const scene::MeshComponentGroup& group : evaluation.groups) {
        const NodeId parts = g.find(group.groupParts);
        if (parts == kNoNode) continue;
        if (auto src = g.source(parts, "groupId"); src && src->node == groupId) return group.components;
    }
    // Both sides may store the numeric id instead of a connection.
    const int id = ev.getInt(groupId, "groupId", -1);
    if (id >= 0)
        for (const scene::MeshComponentGroup& group : evaluation.groups)
            if (group.groupId == id) return group.components;
    return {};
}

// Numbers at the door for objects: a world matrix with an entry beyond kMaxSceneCoordinate, or
// world bounds that reach past it (finite entries can still carry float geometry out of range),
// cannot be projected without overflow, so the object is skipped with a note instead of being
// culled without a word later. `paths` runs parallel to scene.objects and is compacted with it.
void dropUnplaceableObjects(FrameScene& scene, std::vector<std::vector<NodeId>>& paths) {
    size_t kept = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        RenderObject& o = scene.objects[i];
        std::string why = worldMatrixProblem(o.worldFromObject);
        if (why.empty()) why = boundsProblem(o.worldBounds);
        if (!why.empty()) {
            scene.notes.push_back(o.name + ": " + why + "; not rendered");
            ++scene.skippedShapes;
            continue;
        }
        if (kept != i) {
            scene.objects[kept] = std::move(o);
            paths[kept] = std::move(paths[i]);
        }
        ++kept;
    }
    scene.objects.resize(kept);
    paths.resize(kept);
}

}  // namespace

namespace {

FrameScene buildFrameSceneHere(scene::Evaluator& ev, const scene::RenderSetup& setup, const RenderSettings& settings);

}  // namespace

FrameScene buildFrameScene(scene::Evaluator& ev, const scene::RenderSetup& setup, const RenderSettings& settings) {
    // Everything the build runs in parallel (shape evaluation, a large mesh's checks and piece
    // table) uses the threads -n allows.
    tbb::task_arena arena(settings.numCpusToUse > 0 ? settings.numCpusToUse : tbb::task_arena::automatic);
    FrameScene out;
    arena.execute([&] { out = buildFrameSceneHere(ev, setup, settings); });
    return out;
}

namespace {

FrameScene buildFrameSceneHere(scene::Evaluator& ev, const scene::RenderSetup& setup, const RenderSettings& settings) {
    const Graph& g = ev.graph();
    FrameScene scene;
    scene.frame = ev.frame();

    // Shading groups: compiled once each, the first time an object uses one.
    std::unordered_map<NodeId, uint32_t> groupIndex;
    auto useGroup = [&](const scene::ShadingGroupInfo& sg) {
        auto it = groupIndex.find(sg.node);
        if (it != groupIndex.end()) return it->second;
        RenderShadingGroup group;
        group.name = sg.name;
        group.node = sg.node;
        try {
            group.network = shade::ShadingNetwork::compile(ev, sg.surfaceShader, scene.notes);
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            scene.notes.push_back(sg.name + ": shading network not compiled (" + e.what() + "); rendered black");
        }
        if (!group.network) group.network = shade::ShadingNetwork::compile(ev, kNoNode, scene.notes);
        const uint32_t index = uint32_t(scene.shadingGroups.size());
        scene.shadingGroups.push_back(std::move(group));
        groupIndex.emplace(sg.node, index);
        return index;
    };

    const auto memberships = membershipsByShape(setup);
    // Under a memory cap no evaluated mesh stays resident: the handles evaluate their shape again
    // when a tile needs its triangles. Without one, each shape keeps the mesh evaluated here.
    const bool keepMeshes = memoryCapBytes(settings) == 0;
    const uint32_t pieceTriangles = geom::GeometryHandle::pieceTrianglesFor(memoryCapBytes(settings));
    const auto evaluators = std::make_shared<EvaluatorPool>(g, ev.frame());
    std::vector<std::vector<NodeId>> objectPaths;

    // Why one instance of a shape is not rendered (empty when it is), and its shading groups.
    auto instanceProblem = [&](const scene::Node& node, const std::vector<NodeId>& path, size_t instance,
                               std::vector<Membership>& groups) -> std::string {
        if (ev.getBool(node.id, "intermediateObject", false)) return "intermediate object";
        if (std::string why = ev.hiddenReason(path); !why.empty()) return why;
        if (!ev.getBool(node.id, "primaryVisibility", true)) return "primaryVisibility is off";
        groups.clear();
        if (auto it = memberships.find(node.id); it != memberships.end())
            for (const Membership& m : it->second)
                if (m.member->instance == int(instance)) groups.push_back(m);
        if (groups.empty()) {
            return scene::shadingGroupsOf(setup, node.id, int(instance)).empty()
                       ? "belongs to no shading group"
                       : "its shading groups are not in the renderPartition";
        }
        return {};
    };

    // Shapes straight from a primitive: their counts and bounds, read once.
    std::unordered_map<NodeId, geom::PrimitiveCounts> primitiveCounts;
    for (const scene::Node& node : g.nodes())
        if (node.type == "mesh")
            if (std::optional<geom::PrimitiveCounts> c = scene::primitiveShapeCounts(ev, node.id))
                primitiveCounts.emplace(node.id, *c);

    // Without a cap every shape's geometry stays resident anyway, so the shapes that render are
    // evaluated up front on all threads (each on its thread's Evaluator); under a cap they are
    // evaluated one at a time below, so that only one is resident at once.
    std::vector<ShapeGeometry> early;
    std::vector<std::vector<std::string>> earlyNotes;
    std::unordered_map<NodeId, size_t> earlyIndex;
    if (keepMeshes) {
        std::vector<std::pair<NodeId, std::string>> wanted;  // shape, its first rendered instance's name
        scene::DagPathBudget budget;
        std::vector<Membership> groups;
        for (const scene::Node& node : g.nodes()) {
            if (node.type != "mesh" && node.type != "nurbsSurface") continue;
            // A primitive's mesh waits for its first tile (an instance with per-face shading
            // groups evaluates it below).
            if (primitiveCounts.count(node.id)) continue;
            const auto paths = g.dagPaths(node.id, &budget);
            for (size_t instance = 0; instance < paths.size(); ++instance) {
                if (!instanceProblem(node, paths[instance], instance, groups).empty()) continue;
                earlyIndex.emplace(node.id, wanted.size());
                wanted.emplace_back(node.id, g.dagPathName(paths[instance]));
                break;
            }
        }
        early.resize(wanted.size());
        earlyNotes.resize(wanted.size());
        tbb::parallel_for(size_t(0), wanted.size(), [&](size_t i) {
            evaluateShape(evaluators->local(), wanted[i].first, wanted[i].second, early[i], earlyNotes[i]);
        });
    }

    scene::DagPathBudget pathBudget;  // one bound for every shape's instance paths together
    for (const scene::Node& node : g.nodes()) {
        if (node.type != "mesh" && node.type != "nurbsSurface") continue;
        const bool pathsCutBefore = pathBudget.exhausted;
        const auto paths = g.dagPaths(node.id, &pathBudget);
        if (pathBudget.exhausted && !pathsCutBefore) scene.notes.push_back(dagPathBudgetMessage(g, node.id, pathBudget));
        // Geometry is evaluated once per shape, on its first renderable instance that needs it.
        ShapeGeometry shape;
        if (auto it = primitiveCounts.find(node.id); it != primitiveCounts.end()) shape.counts = it->second;
        bool evaluated = false;
        for (size_t instance = 0; instance < paths.size(); ++instance) {
            const std::vector<NodeId>& path = paths[instance];
            const std::string label = g.dagPathName(path);
            auto skip = [&](const std::string& why) {
                scene.notes.push_back(label + ": " + why);
                ++scene.skippedShapes;
            };
            std::vector<Membership> groups;
            if (std::string why = instanceProblem(node, path, instance, groups); !why.empty()) {
                skip(why);
                continue;
            }

            const bool wholeOnly = std::all_of(groups.begin(), groups.end(),
                                               [](const Membership& m) { return m.member->objectGroup < 0; });
            const bool deferred = shape.counts && wholeOnly;
            if (!deferred && !evaluated) {
                if (auto it = earlyIndex.find(node.id); it != earlyIndex.end()) {
                    shape = std::move(early[it->second]);
                    for (std::string& note : earlyNotes[it->second]) scene.notes.push_back(std::move(note));
                } else {
                    evaluateShape(ev, node.id, label, shape, scene.notes);
                }
                evaluated = true;
            }
            if (!deferred && shape.failed) {
                skip(shape.skipReason);
                continue;
            }

            RenderObject object;
            std::vector<const scene::ShadingGroupInfo*> slotGroups;  // per material slot
            object.name = label;
            object.shape = node.id;
            object.instance = int(instance);
            object.worldFromObject = ev.worldMatrix(path);
            if (!geom::isFinite(object.worldFromObject)) {
                skip("non-finite world matrix");
                continue;
            }
            object.primaryVisibility = true;
            object.doubleSided = ev.getBool(node.id, "doubleSided", true);
            object.opposite = ev.getBool(node.id, "opposite", false);
            object.castsShadows = ev.getBool(node.id, "castsShadows", true);
            object.receiveShadows = ev.getBool(node.id, "receiveShadows", true);
            object.smoothShading = ev.getBool(node.id, "smoothShading", true);
            object.shadingSamplesOverride = ev.getBool(node.id, "shadingSamplesOverride", false);
            object.shadingSamples = std::max(1, ev.getInt(node.id, "shadingSamples", 1));
            object.maxShadingSamples = std::max(object.shadingSamples, ev.getInt(node.id, "maxShadingSamples", 1));

            // Shading groups per face: the whole-object group, overridden by per-face groups.
            std::vector<const scene::ShadingGroupInfo*> candidates;  // index = provisional material
            const scene::ShadingGroupInfo* whole = nullptr;
            for (const Membership& m : groups)
                if (m.member->objectGroup < 0 && !whole) whole = m.group;

            if (deferred) {
                // One shading group for the whole mesh: slot 0 on every face.
                slotGroups.push_back(whole);
                if (!shape.deferredHandle || shape.deferredSmooth != object.smoothShading) {
                    shape.deferredHandle = geom::GeometryHandle::fromMeshCounts(
                        std::make_shared<EvaluatedMesh>(evaluators, node.id), *shape.counts, object.smoothShading);
                    shape.deferredSmooth = object.smoothShading;
                }
                object.geometry = shape.deferredHandle;
            } else if (shape.surface) {
                const scene::ShadingGroupInfo* sg = whole ? whole : groups.front().group;
                if (!whole)
                    scene.notes.push_back(label + ": component shading assignment on a NURBS surface; " + sg->name +
                                          " used for the whole surface");
                if (!shape.lastHandle)
                    shape.lastHandle = geom::GeometryHandle::fromNurbs(shape.surface, shape.divU, shape.divV, pieceTriangles);
                object.geometry = shape.lastHandle;
                slotGroups.push_back(sg);
            } else {
                const geom::Mesh& mesh = *shape.mesh;
                const size_t faces = mesh.faceCount();
                // Shading assignments name the faces of the unsmoothed mesh when the shape renders
                // its smooth preview; each smoothed face takes the group of the face it comes from.
                const std::vector<uint32_t>& origin = shape.evaluation.faceOrigin;
                const size_t sourceFaces = origin.size() == faces ? shape.evaluation.sourceFaceCount : faces;
                std::vector<int32_t> sourceGroup(sourceFaces, -1);
                if (whole) {
                    candidates.push_back(whole);
                    std::fill(sourceGroup.begin(), sourceGroup.end(), 0);
                }
                for (const Membership& m : groups) {
                    if (m.member->objectGroup < 0) continue;
                    const scene::ComponentList list = memberComponents(ev, *m.member, shape.evaluation);
                    if (list.items.empty()) {
                        scene.notes.push_back(label + ": objectGroups[" + std::to_string(m.member->objectGroup) +
                                              "] in " + m.group->name + " lists no components");
                        continue;
                    }
                    std::string error;
                    const std::vector<bool> mask = scene::faceMask(list, sourceFaces, &error);
                    if (!error.empty()) scene.notes.push_back(label + ": " + m.group->name + ": " + error);
                    const int32_t index = int32_t(candidates.size());
                    candidates.push_back(m.group);
                    for (size_t f = 0; f < sourceFaces; ++f)
                        if (mask[f]) sourceGroup[f] = index;
                }
                std::vector<int32_t> faceGroup(faces, -1);
                for (size_t f = 0; f < faces; ++f) {
                    const size_t from = origin.size() == faces ? origin[f] : f;
                    faceGroup[f] = from < sourceFaces ? sourceGroup[from] : -1;
                }
                util::release(sourceGroup);
                // Slots for the groups that kept at least one face, in first-use order.
                std::vector<int32_t> slotOf(candidates.size(), -1);
                std::vector<uint16_t> faceMaterial(faces, kNoMaterial);
                size_t dropped = 0;
                for (size_t f = 0; f < faces; ++f) {
                    const int32_t c = faceGroup[f];
                    if (c < 0) {
                        ++dropped;
                        continue;
                    }
                    if (slotOf[size_t(c)] < 0) {
                        if (slotGroups.size() >= kNoMaterial) {
                            ++dropped;
                            continue;
                        }
                        slotOf[size_t(c)] = int32_t(slotGroups.size());
                        slotGroups.push_back(candidates[size_t(c)]);
                    }
                    faceMaterial[f] = uint16_t(slotOf[size_t(c)]);
                }
                // The handle below measures and splits a large mesh: what it works with is all that
                // stays.
                util::release(faceGroup);
                if (dropped == faces) {
                    skip("no face belongs to a shading group");
                    continue;
                }
                if (dropped > 0)
                    scene.notes.push_back(label + ": " + std::to_string(dropped) +
                                          " face(s) in no shading group not rendered");
                // One material on every face is kept as none listed (2 bytes a face less).
                if (std::all_of(faceMaterial.begin(), faceMaterial.end(), [](uint16_t m) { return m == 0; }))
                    util::release(faceMaterial);
                if (!shape.lastHandle || shape.lastMaterials != faceMaterial ||
                    shape.lastSmooth != object.smoothShading) {
                    if (!shape.source)
                        shape.source = keepMeshes ? std::shared_ptr<const geom::MeshSource>()
                                                  : std::make_shared<EvaluatedMesh>(evaluators, node.id);
                    shape.lastHandle = shape.source ? geom::GeometryHandle::fromMeshSource(shape.source, mesh, faceMaterial,
                                                                                           shape.degenerate,
                                                                                           object.smoothShading,
                                                                                           pieceTriangles)
                                                    : geom::GeometryHandle::fromMesh(shape.mesh, faceMaterial,
                                                                                     shape.degenerate, object.smoothShading);
                    shape.lastMaterials = std::move(faceMaterial);
                    shape.lastSmooth = object.smoothShading;
                }
                object.geometry = shape.lastHandle;
            }
            if (object.geometry->triangleCount() == 0) {
                skip("no renderable triangles (every face degenerate or unassigned)");
                continue;
            }
            object.worldBounds = object.geometry->bounds().transformed(object.worldFromObject);
            for (const scene::ShadingGroupInfo* sg : slotGroups) object.materials.push_back({useGroup(*sg), {}});
            scene.objects.push_back(std::move(object));
            objectPaths.push_back(path);
        }
    }

    dropUnplaceableObjects(scene, objectPaths);

    SceneLights lights = readSceneLights(ev, setup, scene.notes);
    scene.lights = std::move(lights.lights);
    scene.usesDefaultLight = scene.lights.empty() && settings.enableDefaultLight;
    linkLights(g, setup, lights.paths, objectPaths, scene);
    return scene;
}

}  // namespace

}  // namespace pushpin::render
