#include "core/scene/render_setup.h"

#include <algorithm>

namespace pushpin::scene {

namespace {

// "instObjGroups[2].objectGroups[1]" → (2, 1); "instObjGroups" → (0, -1). False if not an iog plug.
bool parseMemberPlug(const std::string& path, int& instance, int& objectGroup) {
    auto segs = parsePlugPath(path);
    if (!segs || segs->empty() || (*segs)[0].name != "instObjGroups") return false;
    instance = (*segs)[0].indexed() ? int((*segs)[0].first) : 0;
    objectGroup = -1;
    if (segs->size() >= 2) {
        if ((*segs)[1].name != "objectGroups") return false;
        objectGroup = (*segs)[1].indexed() ? int((*segs)[1].first) : 0;
    }
    return true;
}

NodeId sourceNode(const Graph& g, NodeId node, std::string_view plug) {
    auto src = g.source(node, plug);
    return src ? src->node : kNoNode;
}

// The node behind a relationship/linker plug: a light set, a light transform or shape, an object.
NodeId plugNode(const Plug& p) { return p.node; }

}  // namespace

RenderSetup extractRenderSetup(const Graph& g) {
    RenderSetup setup;
    setup.renderGlobals = g.find("defaultRenderGlobals");
    setup.renderQuality = g.find("defaultRenderQuality");
    setup.resolution = g.find("defaultResolution");

    // One bound for the instance paths of every camera and light together (see DagPathBudget).
    DagPathBudget pathBudget;
    auto pathsOf = [&](NodeId id) {
        const bool before = pathBudget.exhausted;
        auto paths = g.dagPaths(id, &pathBudget);
        if (pathBudget.exhausted && !before) setup.notes.push_back(dagPathBudgetMessage(g, id, pathBudget));
        return paths;
    };
    for (NodeId id : g.nodesOfType("camera")) {
        const Node& n = g.node(id);
        for (auto& path : pathsOf(id)) {
            CameraInfo c;
            c.shape = id;
            c.path = path;
            c.name = n.name;
            c.transformName = path.size() >= 2 ? g.node(path[path.size() - 2]).name : n.name;
            c.renderable = g.getBool(id, "renderable", true);
            c.orthographic = g.getBool(id, "orthographic", false);
            setup.cameras.push_back(std::move(c));
        }
    }

    const NodeSchema* lightSchema = findSchema("light");
    for (const Node& n : g.nodes()) {
        bool known = n.schema && lightSchema && n.schema->isA(lightSchema);
        // Plug-in lights (aiSkyDomeLight, aiAreaLight, …) are listed so users see them, flagged unsupported.
        bool plugin = !n.schema && n.isDag() && n.type.size() > 5 &&
                      n.type.compare(n.type.size() - 5, 5, "Light") == 0;
        if (!known && !plugin) continue;
        for (auto& path : pathsOf(n.id))
            setup.lights.push_back(LightInfo{n.id, path, n.name, n.type, known});
    }

    for (NodeId id : g.nodesOfType("shadingEngine")) {
        ShadingGroupInfo sg;
        sg.node = id;
        sg.name = g.node(id).name;
        sg.surfaceShader = sourceNode(g, id, "surfaceShader");
        sg.volumeShader = sourceNode(g, id, "volumeShader");
        sg.displacementShader = sourceNode(g, id, "displacementShader");
        for (const Connection* c : g.outputs(id))
            if (c->dst.node < g.size() && g.node(c->dst.node).name == "renderPartition" &&
                c->dst.path.rfind("sets", 0) == 0)
                sg.inRenderPartition = true;
        for (const Connection* c : g.inputs(id)) {
            if (c->dst.path.rfind("dagSetMembers", 0) != 0) continue;
            SetMember m;
            m.shape = c->src.node;
            if (!parseMemberPlug(c->src.path, m.instance, m.objectGroup)) continue;
            if (m.objectGroup >= 0) {
                std::string key = "instObjGroups[" + std::to_string(m.instance) + "].objectGroups[" +
                                  std::to_string(m.objectGroup) + "].objectGrpCompList";
                if (const Value* v = g.value(m.shape, key))
                    if (auto* cl = std::get_if<ComponentList>(v)) m.components = cl->items;
            }
            sg.members.push_back(std::move(m));
        }
        setup.shadingGroups.push_back(std::move(sg));
    }

    // Light linking, newer form: relationship "link" ":lightLinker1" "obj.message" "light.message".
    for (const Relationship& r : g.relationships()) {
        if (r.plugs.size() < 3) continue;
        setup.lightLinks.push_back(LightLink{r.type, plugNode(r.plugs[2]), plugNode(r.plugs[1])});
    }
    // Older form: lightLinker1.link[i].light / .object connections.
    for (NodeId linker : g.nodesOfType("lightLinker")) {
        struct Pair { NodeId light = kNoNode, object = kNoNode; };
        std::map<std::string, Pair> pairs;  // "link[3]" → pair
        for (const Connection* c : g.inputs(linker)) {
            auto segs = parsePlugPath(c->dst.path);
            if (!segs || segs->size() != 2 || !(*segs)[0].indexed()) continue;
            const std::string& parent = (*segs)[0].name;
            const std::string& child = (*segs)[1].name;
            std::string key = parent + "[" + std::to_string((*segs)[0].first) + "]";
            if (child == "light" || child == "lightIgnored" || child == "shadowLight" || child == "shadowLightIgnored")
                pairs[key].light = c->src.node;
            else if (child == "object" || child == "objectIgnored" || child == "shadowObject" || child == "shadowObjectIgnored")
                pairs[key].object = c->src.node;
        }
        for (auto& [key, p] : pairs) {
            std::string kind = key.rfind("link[", 0) == 0 ? "link"
                               : key.rfind("ignore[", 0) == 0 ? "ignore"
                               : key.rfind("shadowLink[", 0) == 0 ? "shadowLink"
                                                                   : "shadowIgnore";
            if (p.light != kNoNode && p.object != kNoNode) setup.lightLinks.push_back(LightLink{kind, p.light, p.object});
        }
    }
    return setup;
}

std::vector<const ShadingGroupInfo*> shadingGroupsOf(const RenderSetup& setup, NodeId shape, int instance) {
    std::vector<const ShadingGroupInfo*> out;
    for (const ShadingGroupInfo& sg : setup.shadingGroups)
        for (const SetMember& m : sg.members)
            if (m.shape == shape && m.instance == instance) {
                out.push_back(&sg);
                break;
            }
    return out;
}

}  // namespace pushpin::scene
