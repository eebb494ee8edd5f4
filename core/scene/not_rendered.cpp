#include "core/scene/not_rendered.h"

#include "core/util/format.h"

#include <algorithm>
#include <set>
#include <string_view>

namespace pushpin::scene {

namespace {

class Collector {
public:
    explicit Collector(const Graph& g) : m_g(g) {}
    void add(std::string_view feature, NodeId node) {
        NotRendered* entry = nullptr;
        for (NotRendered& n : m_out)
            if (n.feature == feature) entry = &n;
        if (!entry) entry = &m_out.emplace_back(NotRendered{std::string(feature), {}, 0});
        if (!m_seen.insert({entry->feature, node}).second) return;
        ++entry->count;
        if (entry->nodes.size() < kMaxNotRenderedNodes) entry->nodes.push_back(m_g.node(node).name);
    }
    std::vector<NotRendered> take() { return std::move(m_out); }

private:
    const Graph& m_g;
    std::vector<NotRendered> m_out;
    std::set<std::pair<std::string, NodeId>> m_seen;
};

}  // namespace

std::vector<NotRendered> notRenderedFeatures(Evaluator& ev, const RenderSetup& setup) {
    const Graph& g = ev.graph();
    Collector out(g);
    const bool raytracing = setup.renderQuality != kNoNode && ev.getBool(setup.renderQuality, "enableRaytracing", false);

    const bool depthMaps = setup.renderGlobals == kNoNode || ev.getBool(setup.renderGlobals, "enableDepthMaps", true);

    // Shadows, by light: depth maps unless the render globals turn them all off; ray-traced
    // shadows only where ray tracing is on.
    for (const LightInfo& l : setup.lights) {
        if (!l.supported) continue;
        const Node& n = g.node(l.shape);
        if (depthMaps && n.findAttr("useDepthMapShadows") && ev.getBool(l.shape, "useDepthMapShadows", false))
            out.add("depth-map shadows", l.shape);
        if (raytracing && ev.getBool(l.shape, "useRayTraceShadows", false)) out.add("ray-traced shadows", l.shape);
    }
    if (raytracing) out.add("ray tracing", setup.renderQuality);

    // Materials of the shading groups that have members.
    std::vector<NodeId> materials;
    for (const ShadingGroupInfo& sg : setup.shadingGroups) {
        if (sg.members.empty()) continue;
        if (sg.surfaceShader != kNoNode &&
            std::find(materials.begin(), materials.end(), sg.surfaceShader) == materials.end())
            materials.push_back(sg.surfaceShader);
        if (sg.volumeShader != kNoNode) out.add("fog and volume shaders", sg.volumeShader);
        if (sg.displacementShader != kNoNode) out.add("displacement", sg.displacementShader);
    }
    for (NodeId m : materials) {
        const Node& n = g.node(m);
        if (!n.schema) {
            out.add("plug-in or unmodelled materials", m);
            continue;
        }
        if (raytracing && n.findAttr("reflectivity") && ev.getDouble(m, "reflectivity", 0.0) > 0.0)
            out.add("ray-traced reflections", m);
        if (raytracing && n.findAttr("refractions") && ev.getBool(m, "refractions", false))
            out.add("ray-traced refractions", m);
        if (n.findAttr("glowIntensity") && ev.getDouble(m, "glowIntensity", 0.0) > 0.0) out.add("glow and optical effects", m);
    }
    if (setup.renderGlobals != kNoNode && ev.getBool(setup.renderGlobals, "motionBlur", false))
        out.add("motion blur", setup.renderGlobals);
    for (const LightInfo& l : setup.lights)
        if (!l.supported) out.add("plug-in lights", l.shape);

    // Node types that stand for a feature wherever they are.
    for (const Node& n : g.nodes()) {
        const std::string_view t = n.type;  // compared by length first, not with strlen and memcmp
        // (Maya's default shaderGlow1 is in every scene: glow counts where a material glows.)
        if (t == "opticalFX") {
            out.add("glow and optical effects", n.id);
        } else if (t == "envFog" || t == "lightFog" || t == "volumeFog" || t == "fluidShape") {
            out.add("fog and volume shaders", n.id);
        } else if (t == "particle" || t == "nParticle" || t == "stroke" || t == "pfxHair" || t == "hairSystem" ||
                   t == "pfxToon") {
            out.add("particles and strokes", n.id);
        } else if (t == "nCloth" || t == "nRigid" || t == "nucleus") {
            out.add("cloth simulation (the cloth's input mesh is rendered)", n.id);
        } else if (t == "imagePlane") {
            out.add("image planes", n.id);
        } else if (t == "renderLayer" && n.name != "defaultRenderLayer" && n.name.find(":defaultRenderLayer") == std::string::npos &&
                   ev.getBool(n.id, "renderable", true)) {
            out.add("render layers other than the default", n.id);
        }
    }
    return out.take();
}

std::string describeNotRendered(const NotRendered& n) {
    std::string s = n.feature + " (";
    for (size_t i = 0; i < n.nodes.size() && i < 5; ++i) s += (i ? ", " : "") + util::excerpt(n.nodes[i]);
    if (n.count > 5) s += ", and " + std::to_string(n.count - 5) + " more";
    return s + ")";
}

}  // namespace pushpin::scene
