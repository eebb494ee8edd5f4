#include "core/render/frame_scene.h"

#include "core/geom/finite.h"
#include "core/render/camera.h"
#include "core/util/format.h"
#include "core/util/release.h"
#include "cache/error.h"
#include "core/geom/nurbs.h"
#include "core/geom/geometry_handle.h"
#include "core/scene/components.h"
#include "core/scene/mesh_eval.h"
#include "core/scene/nurbs_eval.h"

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

// Why a world matrix cannot place anything the renderer can project, or empty when it can: an
// entry that is not finite or beyond kMaxSceneCoordinate (camera.h says why that limit).
std::string matrixProblem(const glm::dmat4& m) {
    if (!geom::isFinite(m)) return "non-finite world matrix";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (std::abs(m[c][r]) > kMaxSceneCoordinate)
                return "world matrix entry " + util::formatNumber(m[c][r], 6) +
                       " is beyond 1e18 scene units (a translate or scale on the path is too large)";
    return {};
}

// Why world-space bounds are beyond what the renderer can project, or empty when they are not.
std::string boundsProblem(const geom::Bounds3& b) {
    for (int k = 0; k < 3; ++k) {
        for (double v : {b.lo[k], b.hi[k]})
            if (!std::isfinite(v) || std::abs(v) > kMaxSceneCoordinate)
                return "world-space bounds reach " + util::formatNumber(v, 6) + ", beyond 1e18 scene units";
    }
    return {};
}

// Per-span divisions for one direction: ceil(number · factor), at least 1 (reference/algorithms.md
// §8: numberU/V isoparms per span, u/vDivisionsFactor). Capped so a wild value cannot exhaust memory.
int spanDivisions(scene::Evaluator& ev, NodeId shape, const char* numberAttr, const char* factorAttr,
                  const std::string& label, std::vector<std::string>& notes) {
    constexpr int kMaxDivisions = 256;
    double number = ev.getDouble(shape, numberAttr, 3.0);
    double factor = ev.getDouble(shape, factorAttr, 1.5);
    if (!std::isfinite(number) || !std::isfinite(factor)) {
        notes.push_back(label + ": non-finite " + numberAttr + " or " + factorAttr + " replaced by the defaults");
        number = 3.0;
        factor = 1.5;
    }
    const double divisions = std::ceil(number * factor - 1e-9);
    if (divisions > kMaxDivisions) {
        notes.push_back(label + ": " + numberAttr + " × " + factorAttr + " capped at " + std::to_string(kMaxDivisions) +
                        " divisions per span");
        return kMaxDivisions;
    }
    return std::max(1, int(divisions));
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

// Light linking (reference/nodes.md §5): a link side names a light or object directly, a DAG
// ancestor of it, a set containing it (sets nest), or, on the object side, its shading group.
class LinkResolver {
public:
    explicit LinkResolver(const Graph& g) : m_graph(g) {}

    bool contains(NodeId side, const std::vector<NodeId>& path, NodeId shadingGroup, int depth = 0) {
        if (side == kNoNode) return false;
        if (side == shadingGroup) return true;
        if (std::find(path.begin(), path.end(), side) != path.end()) return true;
        if (depth > 16) return false;  // sets nested deeper than this are a cycle
        for (NodeId m : members(side))
            if (contains(m, path, shadingGroup, depth + 1)) return true;
        return false;
    }

private:
    const std::vector<NodeId>& members(NodeId set) {
        auto it = m_members.find(set);
        if (it != m_members.end()) return it->second;
        std::vector<NodeId> out;
        for (const scene::Connection* c : m_graph.inputs(set))
            if (c->dst.path.rfind("dagSetMembers", 0) == 0 || c->dst.path.rfind("dnSetMembers", 0) == 0)
                out.push_back(c->src.node);
        return m_members.emplace(set, std::move(out)).first->second;
    }

    const Graph& m_graph;
    std::unordered_map<NodeId, std::vector<NodeId>> m_members;
};

// The largest light value (intensity, angles, dropoff, colour × intensity) kept: shading holds
// them in float, and sums and products of a few such values must stay within float's 3.4e38.
constexpr double kMaxLightValue = 1e30;

// A number read through the evaluator, `fallback` (with a note) when it is not finite or its
// magnitude exceeds kMaxLightValue.
double finiteValue(scene::Evaluator& ev, NodeId node, const char* attr, double fallback, const std::string& label,
                   std::vector<std::string>& notes) {
    const double v = ev.getDouble(node, attr, fallback);
    if (std::isfinite(v) && std::abs(v) <= kMaxLightValue) return v;
    notes.push_back(label + ": " + (std::isfinite(v) ? attr + std::string(" ") + util::formatNumber(v, 10) + " is beyond 1e30"
                                                     : "non-finite " + std::string(attr)) +
                    "; replaced by " + util::formatNumber(fallback, 6));
    return fallback;
}

struct LightRecord {
    std::vector<NodeId> path;
};

void readLights(scene::Evaluator& ev, const scene::RenderSetup& setup, FrameScene& out,
                std::vector<LightRecord>& records) {
    const Graph& g = ev.graph();
    for (const scene::LightInfo& info : setup.lights) {
        const std::string label = g.dagPathName(info.path);
        shade::Light light;
        if (info.type == "ambientLight") light.type = shade::LightType::Ambient;
        else if (info.type == "directionalLight") light.type = shade::LightType::Directional;
        else if (info.type == "pointLight") light.type = shade::LightType::Point;
        else if (info.type == "spotLight") light.type = shade::LightType::Spot;
        else {
            out.notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (!info.supported) {
            out.notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (std::string why = ev.hiddenReason(info.path); !why.empty()) {
            out.notes.push_back(label + ": light " + why + "; not rendered");
            continue;
        }
        const glm::dmat4 world = ev.worldMatrix(info.path);
        if (std::string why = matrixProblem(world); !why.empty()) {
            out.notes.push_back(label + ": " + why + "; light not rendered");
            continue;
        }
        const glm::dvec3 position(world * glm::dvec4(0, 0, 0, 1));
        const glm::dvec3 axis(world * glm::dvec4(0, 0, -1, 0));
        const double axisLength = glm::length(axis);
        if (!(axisLength > 0.0) || !std::isfinite(axisLength)) {
            out.notes.push_back(label + ": degenerate world matrix (scale 0 on the path); light not rendered");
            continue;
        }
        const NodeId n = info.shape;
        light.name = label;
        light.shape = n;
        light.position = position;
        light.direction = axis / axisLength;
        glm::dvec3 color = ev.getDouble3(n, "color", glm::dvec3(1.0));
        if (!geom::isFinite(color)) {
            out.notes.push_back(label + ": non-finite color replaced by 1 1 1");
            color = glm::dvec3(1.0);
        }
        const double intensity = finiteValue(ev, n, "intensity", 1.0, label, out.notes);
        const glm::dvec3 emitted = color * intensity;
        if (!(std::max({std::abs(emitted.x), std::abs(emitted.y), std::abs(emitted.z)}) <= kMaxLightValue)) {
            out.notes.push_back(label + ": color × intensity is beyond 1e30; light not rendered");
            continue;
        }
        light.color = glm::vec3(emitted);
        light.decayRate = ev.getInt(n, "decayRate", 0);
        if (light.decayRate < 0 || light.decayRate > 3) {
            out.notes.push_back(label + ": decayRate " + std::to_string(light.decayRate) + " out of range, 0 (none) used");
            light.decayRate = 0;
        }
        light.coneAngle = float(finiteValue(ev, n, "coneAngle", 40.0 * std::numbers::pi / 180.0, label, out.notes));
        light.penumbraAngle = float(finiteValue(ev, n, "penumbraAngle", 0.0, label, out.notes));
        light.dropoff = float(finiteValue(ev, n, "dropoff", 0.0, label, out.notes));
        light.ambientShade = float(finiteValue(ev, n, "ambientShade", 0.45, label, out.notes));
        light.emitDiffuse = ev.getBool(n, "emitDiffuse", true);
        light.emitSpecular = ev.getBool(n, "emitSpecular", true);
        out.lights.push_back(std::move(light));
        records.push_back({info.path});
    }
}

// One Evaluator per thread over the scene at the frame, for meshes evaluated again when a tile
// needs their triangles (an Evaluator is not thread-safe; the Graph is only read).
class EvaluatorPool {
public:
    EvaluatorPool(const Graph& graph, double frame) : m_graph(graph), m_frame(frame) {}
    scene::Evaluator& local() {
        std::unique_ptr<scene::Evaluator>& ev = m_evaluators.local();
        if (!ev) ev = std::make_unique<scene::Evaluator>(m_graph, m_frame);
        return *ev;
    }

private:
    const Graph& m_graph;
    double m_frame;
    tbb::enumerable_thread_specific<std::unique_ptr<scene::Evaluator>> m_evaluators;
};

// A mesh shape evaluated again, on the calling thread's Evaluator, each time it is asked for.
// A shape that is its stored mesh (scene::storedMeshMakesWindows) makes each piece's window from
// the stored data alone.
class EvaluatedMesh final : public geom::MeshSource {
public:
    EvaluatedMesh(std::shared_ptr<EvaluatorPool> pool, NodeId shape)
        : m_pool(std::move(pool)), m_shape(shape), m_windows(scene::storedMeshMakesWindows(m_pool->local(), shape)) {}
    std::shared_ptr<const geom::Mesh> mesh() const override {
        scene::MeshEvaluation e = scene::evaluateMeshShape(m_pool->local(), m_shape);
        return std::make_shared<const geom::Mesh>(e.mesh ? std::move(*e.mesh) : geom::Mesh{});
    }
    bool keepsMesh() const override { return false; }
    bool makesWindows() const override { return m_windows; }
    std::optional<geom::MeshWindow> window(const geom::MeshPieces& pieces, size_t piece,
                                           uint64_t faceVertexCount) const override {
        if (!m_windows) return std::nullopt;
        return scene::decodeStoredMeshWindow(m_pool->local().graph(), m_shape, pieces, piece, faceVertexCount);
    }

private:
    std::shared_ptr<EvaluatorPool> m_pool;
    NodeId m_shape;
    bool m_windows;
};

// Geometry of one shape, evaluated once whatever its number of instances.
struct ShapeGeometry {
    bool failed = false;
    std::string skipReason;
    scene::MeshEvaluation evaluation;                    // meshes: groups, face origins (mesh moved out)
    std::shared_ptr<const geom::Mesh> mesh;              // meshes, validated
    std::shared_ptr<const geom::MeshSource> source;      // meshes: where the handles get them again
    std::shared_ptr<const std::vector<bool>> degenerate;  // meshes: faces to drop
    std::shared_ptr<const geom::NurbsSurface> surface;   // NURBS surfaces (one material)
    int divU = 1, divV = 1;
    // The handle made for the last instance, reused by the next with the same face materials and
    // smoothShading: instances share one tessellation.
    std::shared_ptr<const geom::GeometryHandle> lastHandle;
    std::vector<uint16_t> lastMaterials;
    bool lastSmooth = true;
    // Meshes straight from a primitive: its counts and bounds, so that an instance in one shading
    // group as a whole gets a handle that makes the mesh only when a tile first needs it.
    std::optional<geom::PrimitiveCounts> counts;
    std::shared_ptr<const geom::GeometryHandle> deferredHandle;
    bool deferredSmooth = true;
};

void evaluateShape(scene::Evaluator& ev, NodeId shape, const std::string& label, ShapeGeometry& out,
                   std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    try {
        if (g.node(shape).type == "mesh") {
            out.evaluation = scene::evaluateMeshShape(ev, shape);
            for (const std::string& note : out.evaluation.notes) notes.push_back(label + ": " + note);
            if (!out.evaluation.mesh) {
                out.failed = true;
                out.skipReason =
                    out.evaluation.skipReason.empty() ? "the mesh could not be evaluated" : out.evaluation.skipReason;
                return;
            }
            // The evaluation has validated the mesh when nothing changed it afterwards.
            geom::MeshValidation validation;
            if (out.evaluation.degenerateFaces) validation.degenerateFaces = std::move(*out.evaluation.degenerateFaces);
            else validation = out.evaluation.mesh->validate();
            out.evaluation.degenerateFaces.reset();
            auto mesh = std::make_shared<const geom::Mesh>(std::move(*out.evaluation.mesh));
            out.evaluation.mesh.reset();
            if (!validation.ok()) {
                out.failed = true;
                out.skipReason = "invalid mesh: " + validation.errors.front();
                return;
            }
            if (mesh->empty()) {
                out.failed = true;
                out.skipReason = "mesh has no faces";
                return;
            }
            if (!validation.degenerateFaces.empty()) {
                auto degenerate = std::make_shared<std::vector<bool>>(mesh->faceCount(), false);
                for (uint32_t f : validation.degenerateFaces) (*degenerate)[f] = true;
                out.degenerate = std::move(degenerate);
                notes.push_back(label + ": " + std::to_string(validation.degenerateFaces.size()) +
                                " degenerate face(s) not rendered");
            }
            out.mesh = std::move(mesh);
            return;
        }
        std::string reason, note;
        auto surface = scene::evaluateNurbsSurface(ev, shape, &reason, &note);
        if (!note.empty()) notes.push_back(label + ": " + note);
        if (!surface) {
            out.failed = true;
            out.skipReason = reason.empty() ? "the surface could not be evaluated" : reason;
            return;
        }
        out.divU = spanDivisions(ev, shape, "numberU", "uDivisionsFactor", label, notes);
        out.divV = spanDivisions(ev, shape, "numberV", "vDivisionsFactor", label, notes);
        out.surface = std::make_shared<const geom::NurbsSurface>(std::move(*surface));
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        out.failed = true;
        out.skipReason = e.what();
    }
}

// Numbers at the door for objects: a world matrix with an entry beyond kMaxSceneCoordinate, or
// world bounds that reach past it (finite entries can still carry float geometry out of range),
// cannot be projected without overflow, so the object is skipped with a note instead of being
// culled without a word later. `paths` runs parallel to scene.objects and is compacted with it.
void dropUnplaceableObjects(FrameScene& scene, std::vector<std::vector<NodeId>>& paths) {
    size_t kept = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        RenderObject& o = scene.objects[i];
        std::string why = matrixProblem(o.worldFromObject);
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
                if (!shape.lastHandle) shape.lastHandle = geom::GeometryHandle::fromNurbs(shape.surface, shape.divU, shape.divV);
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

    std::vector<LightRecord> lightRecords;
    readLights(ev, setup, scene, lightRecords);
    scene.usesDefaultLight = scene.lights.empty() && settings.enableDefaultLight;

    // Light linking: light L lights (object O, shading group S) when a "link" pairs a light side
    // containing L with an object side containing O or S, and no "ignore" does. Without any
    // "link" in the scene every light lights everything that is not explicitly ignored.
    LinkResolver resolver(g);
    std::vector<const scene::LightLink*> links, ignores;
    for (const scene::LightLink& l : setup.lightLinks) {
        if (l.kind == "link") links.push_back(&l);
        else if (l.kind == "ignore") ignores.push_back(&l);
    }
    const bool linkedScene = !links.empty();
    auto lightSides = [&](const std::vector<const scene::LightLink*>& list) {
        std::vector<std::vector<char>> out(list.size(), std::vector<char>(scene.lights.size(), 0));
        for (size_t k = 0; k < list.size(); ++k)
            for (size_t l = 0; l < scene.lights.size(); ++l)
                out[k][l] = resolver.contains(list[k]->light, lightRecords[l].path, kNoNode) ? 1 : 0;
        return out;
    };
    const auto linkLights = lightSides(links), ignoreLights = lightSides(ignores);
    for (size_t o = 0; o < scene.objects.size(); ++o) {
        for (MaterialSlot& slot : scene.objects[o].materials) {
            const NodeId sgNode = scene.shadingGroups[slot.shadingGroup].node;
            std::vector<char> lit(scene.lights.size(), linkedScene ? 0 : 1);
            for (size_t k = 0; k < links.size(); ++k) {
                if (std::find(linkLights[k].begin(), linkLights[k].end(), 1) == linkLights[k].end()) continue;
                if (!resolver.contains(links[k]->object, objectPaths[o], sgNode)) continue;
                for (size_t l = 0; l < lit.size(); ++l) lit[l] |= linkLights[k][l];
            }
            for (size_t k = 0; k < ignores.size(); ++k) {
                if (std::find(ignoreLights[k].begin(), ignoreLights[k].end(), 1) == ignoreLights[k].end()) continue;
                if (!resolver.contains(ignores[k]->object, objectPaths[o], sgNode)) continue;
                for (size_t l = 0; l < lit.size(); ++l)
                    if (ignoreLights[k][l]) lit[l] = 0;
            }
            for (size_t l = 0; l < lit.size(); ++l)
                if (lit[l]) slot.lights.push_back(uint32_t(l));
        }
    }
    return scene;
}

}  // namespace

}  // namespace pushpin::render
