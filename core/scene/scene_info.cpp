#include "core/scene/scene_info.h"

#include "core/scene/not_rendered.h"

#include "core/scene/evaluator.h"
#include "core/scene/mesh_eval.h"
#include "core/scene/nurbs_eval.h"
#include "core/scene/render_setup.h"
#include "core/util/format.h"
#include "core/util/json_writer.h"

#include "cache/error.h"

#include <map>

namespace pushpin::scene {

namespace {

std::string diagnosticLine(const Diagnostic& d) {
    std::string s = d.file;
    if (d.line) s += ":" + std::to_string(d.line) + ":" + std::to_string(d.column);
    s += ": ";
    if (!d.node.empty()) s += "'" + util::excerpt(d.node) + "': ";
    return s + d.message;
}

// Object-space bounds of a shape's geometry at the evaluator's frame, or nullopt with a reason.
std::optional<geom::Bounds3> objectBounds(Evaluator& ev, NodeId shape, size_t& vertices, size_t& faces,
                                          std::string& reason) {
    const Graph& g = ev.graph();
    const std::string& type = g.node(shape).type;
    try {
        if (type == "mesh") {
            auto mesh = evaluateMesh(ev, shape, &reason);
            if (!mesh) return std::nullopt;
            vertices = mesh->points.size();
            faces = mesh->faceCount();
            if (faces == 0) {
                reason = "mesh has no faces";
                return std::nullopt;
            }
            return mesh->bounds();
        }
        if (type == "nurbsSurface") {
            auto surface = evaluateNurbsSurface(ev, shape, &reason);
            if (!surface) return std::nullopt;
            vertices = size_t(surface->cvCountU()) * size_t(surface->cvCountV());
            return surface->bounds();
        }
    } catch (const Error& e) {
        reason = e.what();
        return std::nullopt;
    }
    reason = "shape type " + type + " is not rendered";
    return std::nullopt;
}

void writeRenderGlobals(util::JsonWriter& w, const Graph& g, const char* nodeName) {
    NodeId id = g.find(nodeName);
    w.key(nodeName).beginObject();
    if (id != kNoNode && g.node(id).schema) {
        for (const AttrSpec& a : g.node(id).schema->ownAttributes()) {
            if (a.type == AttrType::Message || a.type == AttrType::Compound) continue;
            if (a.type == AttrType::String) {
                w.field(a.longName, g.getString(id, a.longName));
                continue;
            }
            std::vector<double> v;
            if (!g.numbers(id, a.longName, v) || v.empty()) continue;
            if (a.type == AttrType::Bool)
                w.field(a.longName, v[0] != 0.0);
            else
                w.field(a.longName, v[0]);
        }
    }
    w.endObject();
}

void writeBounds(util::JsonWriter& w, const geom::Bounds3& b) {
    if (b.empty()) {
        w.key("bounds").null();
        return;
    }
    w.key("bounds").beginObject();
    w.key("min").beginArray().value(b.lo.x).value(b.lo.y).value(b.lo.z).endArray();
    w.key("max").beginArray().value(b.hi.x).value(b.hi.y).value(b.hi.z).endArray();
    w.endObject();
}

}  // namespace

double sceneCurrentFrame(const Graph& g) {
    NodeId time = g.find("time1");
    if (time != kNoNode && g.value(time, "outTime")) return g.getDouble(time, "outTime", 1.0);
    NodeId globals = g.find("defaultRenderGlobals");
    return globals != kNoNode ? g.getDouble(globals, "startFrame", 1.0) : 1.0;
}

namespace {

SceneReport describeScene(const Graph& g, const RenderSetup& setup, double frame) {
    SceneReport report;
    report.frame = frame;
    for (const Diagnostic& d : g.warnings()) report.warnings.push_back(diagnosticLine(d));
    for (const std::string& note : setup.notes) report.warnings.push_back(g.sourceFile + ": " + note);
    Evaluator ev(g, frame);
    DagPathBudget pathBudget;  // one bound for every shape's instance paths together
    std::map<NodeId, std::tuple<std::optional<geom::Bounds3>, size_t, size_t, std::string>> geometry;

    for (const Node& n : g.nodes()) {
        if (n.type != "mesh" && n.type != "nurbsSurface") continue;
        const bool cutBefore = pathBudget.exhausted;
        auto paths = g.dagPaths(n.id, &pathBudget);
        if (pathBudget.exhausted && !cutBefore)
            report.warnings.push_back(g.sourceFile + ": " + dagPathBudgetMessage(g, n.id, pathBudget));
        for (size_t instance = 0; instance < paths.size(); ++instance) {
            const auto& path = paths[instance];
            ShapeReport s;
            s.name = n.name;
            s.path = g.dagPathName(path);
            s.type = n.type;
            s.shape = n.id;
            s.instance = int(instance);
            bool inPartition = false;
            for (const ShadingGroupInfo* sg : shadingGroupsOf(setup, n.id, int(instance))) {
                s.shadingGroups.push_back(sg->name);
                inPartition |= sg->inRenderPartition;
            }

            if (ev.getBool(n.id, "intermediateObject", false)) {
                s.reason = "intermediate object";
            } else if (std::string why = ev.hiddenReason(path); !why.empty()) {
                s.reason = why;
            } else if (s.shadingGroups.empty()) {
                s.reason = "belongs to no shading group";
            } else if (!inPartition) {
                s.reason = "its shading groups are not in the renderPartition";
            }
            // Geometry is evaluated once per shape, whatever the number of instances.
            auto it = geometry.find(n.id);
            if (it == geometry.end()) {
                size_t vertices = 0, faces = 0;
                std::string reason;
                auto bounds = objectBounds(ev, n.id, vertices, faces, reason);
                it = geometry.emplace(n.id, std::make_tuple(bounds, vertices, faces, reason)).first;
                if (!bounds && s.reason.empty())
                    report.warnings.push_back(g.sourceFile + ": '" + util::excerpt(n.name) + "': skipped: " + reason);
            }
            auto& [bounds, vertices, faces, reason] = it->second;
            s.vertices = vertices;
            s.faces = faces;
            if (bounds) s.worldBounds = bounds->transformed(ev.worldMatrix(path));
            else if (s.reason.empty()) s.reason = reason;
            s.renderable = s.reason.empty();
            (s.renderable ? report.renderableShapes : report.skippedShapes)++;
            report.shapes.push_back(std::move(s));
        }
    }
    return report;
}

}  // namespace

SceneReport describeScene(const Graph& g, double frame) { return describeScene(g, extractRenderSetup(g), frame); }

void writeNotRendered(util::JsonWriter& w, const NotRendered& n) {
    w.beginObject();
    w.field("feature", n.feature);
    w.key("nodes").beginArray();
    for (const std::string& node : n.nodes) w.value(node);
    w.endArray();
    w.field("count", uint64_t(n.count));
    w.endObject();
}

std::string sceneInfoJson(const Graph& g, double frame) {
    const RenderSetup setup = extractRenderSetup(g);
    SceneReport report = describeScene(g, setup, frame);
    util::JsonWriter w;
    w.beginObject();
    w.field("file", g.sourceFile);
    w.field("frame", frame);
    w.key("units").beginObject();
    w.field("cmPerLinearUnit", g.units.cmPerLinearUnit);
    w.field("radiansPerAngleUnit", g.units.radiansPerAngleUnit);
    w.field("framesPerSecond", g.units.framesPerSecond);
    w.endObject();

    std::map<std::string, int> types;
    for (const Node& n : g.nodes())
        if (n.line > 0) ++types[n.type];
    w.key("nodeTypes").beginObject();
    for (auto& [type, count] : types) w.field(type, count);
    w.endObject();

    w.key("shapes").beginArray();
    for (const ShapeReport& s : report.shapes) {
        w.beginObject();
        w.field("name", s.name).field("path", s.path).field("type", s.type).field("renderable", s.renderable);
        if (!s.renderable) w.field("reason", s.reason);
        writeBounds(w, s.worldBounds);
        if (s.type == "mesh") {
            w.field("vertices", uint64_t(s.vertices)).field("faces", uint64_t(s.faces));
        } else {
            w.field("controlVertices", uint64_t(s.vertices));
        }
        w.key("shadingGroups").beginArray();
        for (const std::string& sg : s.shadingGroups) w.value(sg);
        w.endArray();
        w.endObject();
    }
    w.endArray();
    w.key("shapeCounts").beginObject();
    w.field("renderable", uint64_t(report.renderableShapes)).field("skipped", uint64_t(report.skippedShapes));
    w.endObject();

    w.key("cameras").beginArray();
    for (const CameraInfo& c : setup.cameras) {
        w.beginObject();
        w.field("name", c.name).field("transform", c.transformName).field("path", g.dagPathName(c.path));
        w.field("renderable", c.renderable).field("orthographic", c.orthographic);
        w.endObject();
    }
    w.endArray();

    w.key("lights").beginArray();
    for (const LightInfo& l : setup.lights) {
        w.beginObject();
        w.field("name", l.name).field("type", l.type).field("path", g.dagPathName(l.path)).field("supported", l.supported);
        w.endObject();
    }
    w.endArray();

    w.key("shadingGroups").beginArray();
    for (const ShadingGroupInfo& sg : setup.shadingGroups) {
        w.beginObject();
        w.field("name", sg.name);
        auto port = [&](const char* k, NodeId id) {
            if (id == kNoNode) w.key(k).null();
            else w.field(k, g.node(id).type);
        };
        port("surfaceShader", sg.surfaceShader);
        if (sg.surfaceShader != kNoNode) w.field("surfaceShaderNode", g.node(sg.surfaceShader).name);
        port("volumeShader", sg.volumeShader);
        port("displacementShader", sg.displacementShader);
        w.field("members", uint64_t(sg.members.size()));
        w.endObject();
    }
    w.endArray();

    w.key("lightLinks").beginArray();
    for (const LightLink& l : setup.lightLinks) {
        w.beginObject();
        w.field("kind", l.kind);
        w.field("light", l.light != kNoNode ? g.node(l.light).name : std::string());
        w.field("object", l.object != kNoNode ? g.node(l.object).name : std::string());
        w.endObject();
    }
    w.endArray();

    w.key("renderGlobals").beginObject();
    writeRenderGlobals(w, g, "defaultRenderGlobals");
    writeRenderGlobals(w, g, "defaultRenderQuality");
    writeRenderGlobals(w, g, "defaultResolution");
    w.endObject();

    w.key("notRendered").beginArray();
    {
        Evaluator ev(g, frame);
        for (const NotRendered& n : notRenderedFeatures(ev, setup)) writeNotRendered(w, n);
    }
    w.endArray();

    w.key("unsupported").beginObject();
    w.key("nodeTypes").beginObject();
    for (auto& [type, count] : g.unsupportedTypes()) w.field(type, count);
    w.endObject();
    w.key("attributes").beginObject();
    for (auto& [attr, count] : g.unsupportedAttributes()) w.field(attr, count);
    w.endObject();
    w.endObject();

    w.key("references").beginArray();
    for (const std::string& r : g.references) w.value(r);
    w.endArray();

    w.key("warnings").beginArray();
    for (const std::string& s : report.warnings) w.value(s);
    w.endArray();
    w.endObject();
    return w.str() + "\n";
}

}  // namespace pushpin::scene
