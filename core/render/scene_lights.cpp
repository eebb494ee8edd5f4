#include "core/render/scene_lights.h"

#include "core/geom/finite.h"
#include "core/render/camera.h"
#include "core/util/format.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace pushpin::render {

using scene::Graph;
using scene::kNoNode;
using scene::NodeId;

namespace {

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

}  // namespace

SceneLights readSceneLights(scene::Evaluator& ev, const scene::RenderSetup& setup, std::vector<std::string>& notes) {
    SceneLights out;
    const Graph& g = ev.graph();
    for (const scene::LightInfo& info : setup.lights) {
        const std::string label = g.dagPathName(info.path);
        shade::Light light;
        if (info.type == "ambientLight") light.type = shade::LightType::Ambient;
        else if (info.type == "directionalLight") light.type = shade::LightType::Directional;
        else if (info.type == "pointLight") light.type = shade::LightType::Point;
        else if (info.type == "spotLight") light.type = shade::LightType::Spot;
        else {
            notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (!info.supported) {
            notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (std::string why = ev.hiddenReason(info.path); !why.empty()) {
            notes.push_back(label + ": light " + why + "; not rendered");
            continue;
        }
        const glm::dmat4 world = ev.worldMatrix(info.path);
        if (std::string why = worldMatrixProblem(world); !why.empty()) {
            notes.push_back(label + ": " + why + "; light not rendered");
            continue;
        }
        const glm::dvec3 position(world * glm::dvec4(0, 0, 0, 1));
        const glm::dvec3 axis(world * glm::dvec4(0, 0, -1, 0));
        const double axisLength = glm::length(axis);
        if (!(axisLength > 0.0) || !std::isfinite(axisLength)) {
            notes.push_back(label + ": degenerate world matrix (scale 0 on the path); light not rendered");
            continue;
        }
        const NodeId n = info.shape;
        light.name = label;
        light.shape = n;
        light.position = position;
        light.direction = axis / axisLength;
        glm::dvec3 color = ev.getDouble3(n, "color", glm::dvec3(1.0));
        if (!geom::isFinite(color)) {
            notes.push_back(label + ": non-finite color replaced by 1 1 1");
            color = glm::dvec3(1.0);
        }
        const double intensity = finiteValue(ev, n, "intensity", 1.0, label, notes);
        const glm::dvec3 emitted = color * intensity;
        if (!(std::max({std::abs(emitted.x), std::abs(emitted.y), std::abs(emitted.z)}) <= kMaxLightValue)) {
            notes.push_back(label + ": color × intensity is beyond 1e30; light not rendered");
            continue;
        }
        light.color = glm::vec3(emitted);
        light.decayRate = ev.getInt(n, "decayRate", 0);
        if (light.decayRate < 0 || light.decayRate > 3) {
            notes.push_back(label + ": decayRate " + std::to_string(light.decayRate) + " out of range, 0 (none) used");
            light.decayRate = 0;
        }
        light.coneAngle = float(finiteValue(ev, n, "coneAngle", 40.0 * std::numbers::pi / 180.0, label, notes));
        light.penumbraAngle = float(finiteValue(ev, n, "penumbraAngle", 0.0, label, notes));
        light.dropoff = float(finiteValue(ev, n, "dropoff", 0.0, label, notes));
        light.ambientShade = float(finiteValue(ev, n, "ambientShade", 0.45, label, notes));
        light.emitDiffuse = ev.getBool(n, "emitDiffuse", true);
        light.emitSpecular = ev.getBool(n, "emitSpecular", true);
        out.lights.push_back(std::move(light));
        out.paths.push_back(info.path);
    }
    return out;
}

void linkLights(const Graph& g, const scene::RenderSetup& setup, const std::vector<std::vector<NodeId>>& lightPaths,
                const std::vector<std::vector<NodeId>>& objectPaths, FrameScene& scene) {
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
                out[k][l] = resolver.contains(list[k]->light, lightPaths[l], kNoNode) ? 1 : 0;
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
}

}  // namespace pushpin::render
