// core/scene/mesh_eval.cpp: mesh shapes and their construction history → geom::Mesh.
#include "core/scene/mesh_eval.h"

#include "core/geom/finite.h"
#include "core/geom/poly_bevel.h"
#include "core/geom/poly_dissolve.h"
#include "core/geom/poly_extrude.h"
#include "core/geom/poly_extrude_edge.h"
#include "core/geom/poly_merge.h"
#include "core/geom/poly_split.h"
#include "core/geom/poly_split_ring.h"
#include "core/geom/subdivide.h"
#include "core/geom/poly_primitives.h"
#include "core/scene/components.h"
#include "core/scene/deformer_eval.h"
#include "core/scene/detail/multi_elements.h"
#include "core/scene/nurbs_eval.h"
#include "core/util/parallel_runs.h"
#include "core/util/release.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>


#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <map>
#include <unordered_map>

namespace pushpin::scene {

namespace {

using detail::forEachNumeric;
using detail::forEachNumericIn;
using detail::kMaxElements;
using detail::nodeLabel;
using detail::vectorElements;

constexpr int kMaxHistoryDepth = 256;
// Maya writes this for per-face-vertex normals that are "not set, compute".
constexpr double kUnsetNormal = 1e19;

// The key the Graph stores a top-level attribute under, given by short or long name.
std::string keyOf(const Graph& g, NodeId n, std::string_view name) {
    std::optional<std::vector<PlugSegment>> segs = parsePlugPath(name);
    return segs ? g.canonicalPath(n, *segs) : std::string(name);
}

const AttrData* attrOf(const Graph& g, NodeId n, std::string_view name) { return g.findAttr(n, keyOf(g, n, name)); }

// Incoming connection into any of `names` (long names as canonical paths, or as written for
// node types outside the schema). The connection's last index is ignored (`inputGeometry[0]`).
std::optional<Plug> inputPlug(const Graph& g, NodeId n, std::initializer_list<std::string_view> names) {
    for (const Connection* c : g.inputs(n)) {
        std::string_view path = c->dst.path;
        if (const size_t bracket = path.find('['); bracket != std::string_view::npos && path.back() == ']' &&
                                                   path.find('.') == std::string_view::npos)
            path = path.substr(0, bracket);
        for (std::string_view want : names) {
            if (path == want) return c->src;
            std::optional<std::vector<PlugSegment>> segs = parsePlugPath(want);
            if (segs && path == g.canonicalPath(n, *segs)) return c->src;
        }
    }
    return std::nullopt;
}

const ComponentList* componentListOf(const Graph& g, NodeId n, std::string_view name) {
    const Value* v = g.value(n, name);
    return v ? std::get_if<ComponentList>(v) : nullptr;
}

// Index inside "uvSet[3].uvSetName" style keys.
std::optional<uint32_t> leadingIndex(const std::string& key, std::string_view prefix) {
    if (key.rfind(prefix, 0) != 0) return std::nullopt;
    const size_t close = key.find(']', prefix.size());
    if (close == std::string::npos || close == prefix.size() || close - prefix.size() > 9) return std::nullopt;
    uint32_t v = 0;
    for (size_t i = prefix.size(); i < close; ++i) {
        if (key[i] < '0' || key[i] > '9') return std::nullopt;
        v = v * 10 + uint32_t(key[i] - '0');
    }
    return v;
}

struct Context {
    Evaluator& ev;
    const Graph& g;
    MeshEvaluation& out;
    std::vector<NodeId> visiting;
};

std::optional<geom::Mesh> evaluateShape(Context& c, NodeId shape, std::string& reason);

// ------------------------------------------------------------------------------ creator nodes
geom::PrimitiveAxis primitiveAxis(Evaluator& ev, NodeId n) {
    geom::PrimitiveAxis common;
    common.axis = ev.getDouble3(n, "ax", glm::dvec3(0.0, 1.0, 0.0));
    common.createUVs = ev.getInt(n, "cuv", 1) != 0;
    return common;
}

geom::PolyCubeParams polyCubeParams(Evaluator& ev, NodeId n) {
    geom::PolyCubeParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.width = ev.getDouble(n, "w", 1.0);
    p.height = ev.getDouble(n, "h", 1.0);
    p.depth = ev.getDouble(n, "d", 1.0);
    p.subdivisionsWidth = ev.getInt(n, "sw", 1);
    p.subdivisionsHeight = ev.getInt(n, "sh", 1);
    p.subdivisionsDepth = ev.getInt(n, "sd", 1);
    return p;
}

geom::PolySphereParams polySphereParams(Evaluator& ev, NodeId n) {
    geom::PolySphereParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.radius = ev.getDouble(n, "r", 1.0);
    p.subdivisionsAxis = ev.getInt(n, "sa", 20);
    p.subdivisionsHeight = ev.getInt(n, "sh", 20);
    return p;
}

geom::PolyPlaneParams polyPlaneParams(Evaluator& ev, NodeId n) {
    geom::PolyPlaneParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.width = ev.getDouble(n, "w", 1.0);
    p.height = ev.getDouble(n, "h", 1.0);
    p.subdivisionsWidth = ev.getInt(n, "sw", 10);
    p.subdivisionsHeight = ev.getInt(n, "sh", 10);
    return p;
}

geom::PolyCylinderParams polyCylinderParams(Evaluator& ev, NodeId n) {
    geom::PolyCylinderParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.radius = ev.getDouble(n, "r", 1.0);
    p.height = ev.getDouble(n, "h", 2.0);
    p.subdivisionsAxis = ev.getInt(n, "sa", 20);
    p.subdivisionsHeight = ev.getInt(n, "sh", 1);
    p.subdivisionsCaps = ev.getInt(n, "sc", 1);
    p.roundCap = ev.getBool(n, "rcp", false);
    return p;
}

geom::PolyConeParams polyConeParams(Evaluator& ev, NodeId n) {
    geom::PolyConeParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.radius = ev.getDouble(n, "r", 1.0);
    p.height = ev.getDouble(n, "h", 2.0);
    p.subdivisionsAxis = ev.getInt(n, "sa", 20);
    p.subdivisionsHeight = ev.getInt(n, "sh", 1);
    p.subdivisionsCap = ev.getInt(n, "sc", 0);
    return p;
}

geom::PolyTorusParams polyTorusParams(Evaluator& ev, NodeId n) {
    geom::PolyTorusParams p;
    static_cast<geom::PrimitiveAxis&>(p) = primitiveAxis(ev, n);
    p.radius = ev.getDouble(n, "r", 1.0);
    p.sectionRadius = ev.getDouble(n, "sr", 0.5);
    p.twistRadians = ev.getDouble(n, "tw", 0.0);
    p.subdivisionsAxis = ev.getInt(n, "sa", 20);
    p.subdivisionsHeight = ev.getInt(n, "sh", 20);
    return p;
}

std::optional<geom::Mesh> evaluateCreator(Context& c, NodeId n, std::string& reason) {
    Evaluator& ev = c.ev;
    const Node& node = c.g.node(n);
    const std::string& type = node.type;
    const geom::PrimitiveAxis common = primitiveAxis(ev, n);
    std::string error;
    std::optional<geom::Mesh> mesh;
    if (type == "polyCube") {
        mesh = geom::makePolyCube(polyCubeParams(ev, n), &error);
    } else if (type == "polySphere") {
        mesh = geom::makePolySphere(polySphereParams(ev, n), &error);
    } else if (type == "polyPlane") {
        mesh = geom::makePolyPlane(polyPlaneParams(ev, n), &error);
    } else if (type == "polyCylinder") {
        const geom::PolyCylinderParams p = polyCylinderParams(ev, n);
        if (p.roundCap) c.out.notes.push_back(nodeLabel(node) + ": roundCap is not modelled; caps are flat");
        mesh = geom::makePolyCylinder(p, &error);
    } else if (type == "polyCone") {
        mesh = geom::makePolyCone(polyConeParams(ev, n), &error);
    } else if (type == "polyTorus") {
        mesh = geom::makePolyTorus(polyTorusParams(ev, n), &error);
    } else if (type == "polyPlatonicSolid") {
        geom::PolyPlatonicParams p;
        static_cast<geom::PrimitiveAxis&>(p) = common;
        p.radius = ev.getDouble(n, "r", 1.0);
        p.solidType = ev.getInt(n, "st", 0);
        mesh = geom::makePolyPlatonicSolid(p, &error);
    } else {
        reason = "history node " + nodeLabel(node) + " is not evaluated";
        return std::nullopt;
    }
    if (!mesh) reason = error + " (" + node.name + ")";
    return mesh;
}

// ------------------------------------------------------------------------------ history nodes
// History nodes that edit UVs and leave points and faces as they are.
bool isUvOnlyHistory(std::string_view type) {
    static constexpr std::string_view kTypes[] = {
        "polyAutoProj", "polyPlanarProj", "polyCylProj", "polySphProj", "polyProjection", "polyMapCut",
        "polyMapSew", "polyMapSewMove", "polyMapDel", "polyNormalizeUV", "polyLayoutUV", "polyFlipUV",
        "polyMoveUV", "polyCopyUV", "polyUVRectangle", "polyOptUvs", "polyMergeUV", "createUVSet",
        "Unfold3DUnfold", "Unfold3DOptimize"};
    return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

std::optional<geom::Mesh> evaluatePlug(Context& c, const Plug& src, std::string& reason);

std::optional<geom::Mesh> evaluateInput(Context& c, NodeId n, std::initializer_list<std::string_view> names,
                                        std::string& reason) {
    std::optional<Plug> in = inputPlug(c.g, n, names);
    if (!in) {
        reason = nodeLabel(c.g.node(n)) + " has no input geometry";
        return std::nullopt;
    }
    return evaluatePlug(c, *in, reason);
}

void applyPointTweaks(const std::map<uint32_t, glm::dvec3>& tweaks, geom::Mesh& mesh, const Node& node,
                      std::vector<std::string>& notes) {
    size_t ignored = 0;
    for (const auto& [index, t] : tweaks) {
        if (index >= mesh.points.size()) {
            ++ignored;
            continue;
        }
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            ++ignored;
            continue;
        }
        mesh.points[index] = glm::vec3(glm::dvec3(mesh.points[index]) + t);
    }
    if (ignored)
        notes.push_back(nodeLabel(node) + ": " + std::to_string(ignored) +
                        " tweaks ignored (non-finite or past the last of " + std::to_string(mesh.points.size()) +
                        " points)");
}

// deleteComponent as Maya does it: listed edges dissolve (their two faces merge; a border edge
// takes its face with it), listed points on only two edges leave their faces, listed faces go.
void deleteComponents(geom::Mesh& mesh, const ComponentList& list, const Node& node, std::vector<std::string>& notes) {
    const ParsedComponents parsed = parseComponents(list);
    for (const std::string& e : parsed.errors) notes.push_back(nodeLabel(node) + ": " + e);
    std::string clip;
    auto mask = [&](ComponentKind kind, size_t count) {
        std::vector<bool> m = componentMask(parsed.ranges, kind, count, &clip);
        if (!clip.empty()) notes.push_back(nodeLabel(node) + ": " + clip);
        clip.clear();
        return m;
    };
    auto any = [](const std::vector<bool>& m) { return std::find(m.begin(), m.end(), true) != m.end(); };
    // Masks against the input's numbering. One kind per node is what Maya writes; a mix applies
    // the faces and says what it left.
    geom::completeEdges(mesh, true);
    const std::vector<bool> faces = mask(ComponentKind::Face, mesh.faceCount());
    const std::vector<bool> edges = mask(ComponentKind::Edge, mesh.edges.size());
    const std::vector<bool> points = mask(ComponentKind::Vertex, mesh.points.size());
    if (any(faces)) {
        geom::deleteFaces(mesh, faces);
        if (any(edges) || any(points))
            notes.push_back(nodeLabel(node) + ": edges and points listed with faces are not deleted");
        return;
    }
    if (any(edges)) {
        geom::dissolveEdges(mesh, edges);
        if (any(points)) notes.push_back(nodeLabel(node) + ": points listed with edges are not deleted");
        return;
    }
    if (any(points)) {
        const geom::DissolveResult r = geom::removeWingedPoints(mesh, points);
        if (r.keptPoints)
            notes.push_back(nodeLabel(node) + ": " + std::to_string(r.keptPoints) +
                            " points on more than two edges stay (Maya deletes only points on two edges)");
    }
}

// polySoftEdge: selected edges (all when none are listed) become soft where the faces meeting
// there are within `angleRadians` of each other, hard elsewhere.
void softenEdges(geom::Mesh& mesh, const ComponentList* list, double angleRadians) {
    geom::completeEdges(mesh, true);
    std::vector<bool> selected(mesh.edges.size(), true);
    if (list && !list->items.empty())
        selected = componentMask(parseComponents(*list).ranges, ComponentKind::Edge, mesh.edges.size());
    std::unordered_map<uint64_t, size_t> edgeIndex;
    for (size_t e = 0; e < mesh.edges.size(); ++e) edgeIndex[geom::edgeKey(mesh.edges[e].v0, mesh.edges[e].v1)] = e;
    std::vector<glm::dvec3> firstNormal(mesh.edges.size(), glm::dvec3(0.0));
    std::vector<double> maxAngle(mesh.edges.size(), 0.0);
    std::vector<int> faceCount(mesh.edges.size(), 0);
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        const glm::dvec3 n = mesh.faceNormal(f);
        for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
            const std::span<const uint32_t> lp = mesh.loop(l);
            for (size_t i = 0; i < lp.size(); ++i) {
                const auto it = edgeIndex.find(geom::edgeKey(lp[i], lp[(i + 1) % lp.size()]));
                if (it == edgeIndex.end()) continue;
                const size_t e = it->second;
                if (faceCount[e]++ == 0) firstNormal[e] = n;
                else maxAngle[e] = std::max(maxAngle[e], std::acos(std::clamp(glm::dot(firstNormal[e], n), -1.0, 1.0)));
            }
        }
    }
    for (size_t e = 0; e < mesh.edges.size(); ++e)
        if (e < selected.size() && selected[e]) mesh.edges[e].smooth = maxAngle[e] <= angleRadians + 1e-9;
}

// The selection of a component list as a mask of one kind, with what did not parse or fit as notes.
std::vector<bool> componentSelection(const ComponentList& list, ComponentKind kind, size_t count, const Node& node,
                                     std::vector<std::string>& notes) {
    const ParsedComponents parsed = parseComponents(list);
    for (const std::string& e : parsed.errors) notes.push_back(nodeLabel(node) + ": " + e);
    std::string clip;
    std::vector<bool> mask = componentMask(parsed.ranges, kind, count, &clip);
    if (!clip.empty()) notes.push_back(nodeLabel(node) + ": " + clip);
    return mask;
}

// The space polyMoveVertex and its descendants move points in: world space through inputMatrix
// when worldSpace is on (worldFromObject), else object space (the identity).
glm::dmat4 moveSpace(Evaluator& ev, NodeId n) {
    std::vector<double> v;
    if (ev.getBool(n, "ws", false) && ev.numbers(n, "ix", v) && v.size() == 16) {
        const glm::dmat4 worldFromObject = glm::make_mat4(v.data());
        if (geom::isFinite(worldFromObject) && geom::isFinite(glm::inverse(worldFromObject))) return worldFromObject;
    }
    return glm::dmat4(1.0);
}

// Maya's polyMoveVertex transform in its move space: translate, rotate (XYZ order) and scale
// about the pivot; nullopt when it is not finite.
std::optional<glm::dmat4> moveTransform(Evaluator& ev, NodeId n) {
    const glm::dvec3 t = ev.getDouble3(n, "t"), r = ev.getDouble3(n, "r");
    const glm::dvec3 s = ev.getDouble3(n, "s", glm::dvec3(1.0)), pivot = ev.getDouble3(n, "pvt");
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), pivot + t);
    m = glm::rotate(m, r.z, glm::dvec3(0, 0, 1));
    m = glm::rotate(m, r.y, glm::dvec3(0, 1, 0));
    m = glm::rotate(m, r.x, glm::dvec3(1, 0, 0));
    m = glm::scale(m, s);
    m = glm::translate(m, -pivot);
    if (!geom::isFinite(m)) return std::nullopt;
    return m;
}

// How an extrusion (of faces or edges) moves what it makes; false, with `error`, when a value
// is not finite.
bool readExtrusionMove(Context& c, NodeId n, geom::ExtrusionMove& m, std::string& error) {
    Evaluator& ev = c.ev;
    const std::optional<glm::dmat4> transform = moveTransform(ev, n);
    if (!transform) {
        error = "its translate, rotate, scale or pivot is not finite";
        return false;
    }
    m.transform = *transform;
    m.space = moveSpace(ev, n);
    m.localTranslate = ev.getDouble3(n, "lt");
    m.localScale = ev.getDouble3(n, "ls", glm::dvec3(1.0));
    if (!geom::isFinite(m.localTranslate) || !geom::isFinite(m.localScale)) {
        error = "its local translate or local scale is not finite";
        return false;
    }
    m.keepFacesTogether = ev.getBool(n, "kft", true);
    m.divisions = ev.getInt(n, "dv", 1);
    return true;
}

// What an extrusion (of faces or edges) does not apply yet, said rather than dropped.
void noteMovesNotApplied(Context& c, NodeId n) {
    Evaluator& ev = c.ev;
    std::vector<std::string> ignored;
    if (ev.getDouble3(n, "lr") != glm::dvec3(0.0)) ignored.push_back("localRotate");
    if (ev.getDouble(n, "off") != 0.0) ignored.push_back("offset");
    if (ev.getDouble(n, "tk") != 0.0) ignored.push_back("thickness");
    if (ev.getDouble(n, "twt") != 0.0) ignored.push_back("twist");
    if (ev.getDouble(n, "tp", 1.0) != 1.0) ignored.push_back("taper");
    if (ev.getDouble(n, "ran") != 0.0) ignored.push_back("random");
    if (ev.getDouble(n, "att") != 0.0 || ev.getDouble(n, "w") != 0.0) ignored.push_back("attraction and weight");
    if (ev.getBool(n, "raf", false)) ignored.push_back("reverseAllFaces");
    for (const auto& [index, point] : vectorElements(ev, n, keyOf(c.g, n, "c"), 3))
        if (point.y != 1.0) {
            ignored.push_back("taperCurve");
            break;
        }
    if (!ignored.empty()) {
        std::string names;
        for (const std::string& a : ignored) names += (names.empty() ? "" : ", ") + a;
        c.out.notes.push_back(nodeLabel(c.g.node(n)) + ": " + names + " not applied");
    }
}

// The common shape of a component edit (polyExtrudeFace, polyExtrudeEdge, polyBevel; not
// polyMergeVert, whose own tweaks apply even without components): the node's input mesh, then,
// when its component list names something, `edit` on the mesh with that list. An edit returns
// false with `error` set; the reason then names the node. Without components the input passes
// through unchanged.
template <class Edit>
std::optional<geom::Mesh> evaluateComponentEdit(Context& c, NodeId n, std::string& reason, Edit&& edit) {
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    const ComponentList* list = componentListOf(c.g, n, "ics");
    if (!list || list->items.empty()) return m;
    std::string error;
    if (!edit(*m, *list, error)) {
        reason = nodeLabel(c.g.node(n)) + ": " + error;
        return std::nullopt;
    }
    return m;
}

std::optional<geom::Mesh> evaluateExtrudeFace(Context& c, NodeId n, std::string& reason) {
    return evaluateComponentEdit(c, n, reason, [&](geom::Mesh& m, const ComponentList& list, std::string& error) {
        const Node& node = c.g.node(n);
        geom::ExtrudeFacesParams p;
        p.faces = componentSelection(list, ComponentKind::Face, m.faceCount(), node, c.out.notes);
        if (!readExtrusionMove(c, n, p, error)) return false;
        p.smoothingAngle = c.ev.getDouble(n, "sma", p.smoothingAngle);
        if (!std::isfinite(p.smoothingAngle)) {
            error = "its smoothing angle is not finite";
            return false;
        }
        noteMovesNotApplied(c, n);
        return geom::extrudeFaces(m, p, nullptr, &error);
    });
}

// polyExtrudeEdge: walls on the selected edges, moved as polyExtrudeFace moves its faces.
std::optional<geom::Mesh> evaluateExtrudeEdge(Context& c, NodeId n, std::string& reason) {
    return evaluateComponentEdit(c, n, reason, [&](geom::Mesh& m, const ComponentList& list, std::string& error) {
        geom::completeEdges(m, true);
        geom::ExtrudeEdgesParams p;
        p.edges = componentSelection(list, ComponentKind::Edge, m.edges.size(), c.g.node(n), c.out.notes);
        if (!readExtrusionMove(c, n, p, error)) return false;
        noteMovesNotApplied(c, n);
        return geom::extrudeEdges(m, p, nullptr, &error);
    });
}

// polyBevel and polyBevel3 with one segment: a chamfer of the selected edges.
std::optional<geom::Mesh> evaluateBevel(Context& c, NodeId n, std::string& reason) {
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    const bool third = node.type == "polyBevel3";
    if (const int segments = ev.getInt(n, "sg", 1); segments != 1) {
        reason = nodeLabel(node) + ": " + std::to_string(segments) + " segments are not evaluated (one is)";
        return std::nullopt;
    }
    return evaluateComponentEdit(c, n, reason, [&](geom::Mesh& m, const ComponentList& list, std::string& error) {
        geom::completeEdges(m, true);
        geom::BevelParams p;
        p.edges = componentSelection(list, ComponentKind::Edge, m.edges.size(), node, c.out.notes);
        p.offsetAsFraction = ev.getBool(n, "oaf", third);
        p.offset = third && p.offsetAsFraction ? ev.getDouble(n, "f", 0.5) : ev.getDouble(n, "o", 0.2);
        p.smoothingAngle = ev.getDouble(n, "sa", p.smoothingAngle);
        if (ev.getBool(n, "ws", false) && moveSpace(ev, n) != glm::dmat4(1.0))
            c.out.notes.push_back(nodeLabel(node) + ": the offset is measured in object space, not world space");
        geom::BevelResult r;
        if (!geom::bevelEdges(m, p, &r, &error)) return false;
        if (r.skippedEdges > 0)
            c.out.notes.push_back(nodeLabel(node) + ": " + std::to_string(r.skippedEdges) +
                                  " border or non-manifold edges are not bevelled");
        c.out.notes.push_back(nodeLabel(node) +
                              ": bevelled as a flat chamfer; the layout of its new components is pushpin's own");
        return true;
    });
}

// polyMergeVert: its own tweaks first (as Maya stores them on the node), then the merge.
std::optional<geom::Mesh> evaluateMergeVert(Context& c, NodeId n, std::string& reason) {
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    applyPointTweaks(vectorElements(ev, n, keyOf(g, n, "tk"), 3), *m, node, c.out.notes);
    const ComponentList* list = componentListOf(g, n, "ics");
    if (!list || list->items.empty()) return m;
    geom::MergeVerticesParams p;
    p.points = componentSelection(*list, ComponentKind::Vertex, m->points.size(), node, c.out.notes);
    if (const ComponentList* to = componentListOf(g, n, "mtc"); to && !to->items.empty()) {
        const std::vector<bool> target =
            componentMask(parseComponents(*to).ranges, ComponentKind::Vertex, m->points.size());
        for (size_t i = 0; i < target.size() && !p.target; ++i)
            if (target[i]) p.target = uint32_t(i);
        if (!p.target) {
            reason = nodeLabel(node) + ": the point to merge to is not on the mesh";
            return std::nullopt;
        }
    }
    p.distance = ev.getDouble(n, "d", 0.0);
    p.alwaysMergeTwo = ev.getBool(n, "am", false);
    p.space = moveSpace(ev, n);
    std::string error;
    if (!geom::mergeVertices(*m, p, nullptr, &error)) {
        reason = nodeLabel(node) + ": " + error;
        return std::nullopt;
    }
    return m;
}

// polySplitRing: its own tweaks first, then one edge loop across the ring at the weight.
std::optional<geom::Mesh> evaluateSplitRing(Context& c, NodeId n, std::string& reason) {
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    // Files from before splitType existed split at the weight; 2 puts `divisions` loops evenly
    // along the ring; 1 (an absolute distance) is not evaluated yet.
    const int splitType = g.value(n, "stp") ? ev.getInt(n, "stp", 0) : 0;
    if (splitType != 0 && splitType != 2) {
        reason = nodeLabel(node) + ": splitType " + std::to_string(splitType) + " (absolute distance) is not evaluated";
        return std::nullopt;
    }
    const int loops = splitType == 2 ? ev.getInt(n, "div", 2) : 1;
    if (loops < 1 || loops > 1024) {
        reason = nodeLabel(node) + ": " + std::to_string(loops) + " loops is outside 1 to 1024";
        return std::nullopt;
    }
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    applyPointTweaks(vectorElements(ev, n, keyOf(g, n, "tk"), 3), *m, node, c.out.notes);
    const ComponentList* list = componentListOf(g, n, "ics");
    if (!list || list->items.empty()) return m;
    geom::completeEdges(*m, true);
    geom::SplitRingParams p;
    p.edges = componentSelection(*list, ComponentKind::Edge, m->edges.size(), node, c.out.notes);
    p.rootEdge = ev.getInt(n, "re", -1);
    p.weight = ev.getDouble(n, "wt", 0.5);
    // The weight runs from the root edge's first point whatever `direction` says: Maya's recorded
    // extrusion bounds after splits on real scenes (direction on and off) agree only so.
    p.fromFirst = true;
    if (ev.getBool(n, "iwe", false)) c.out.notes.push_back(nodeLabel(node) + ": insertWithEdgeFlow not applied");
    std::string error;
    if (loops == 1) {
        if (!geom::splitRing(*m, p, nullptr, &error)) {
            reason = nodeLabel(node) + ": " + error;
            return std::nullopt;
        }
        return m;
    }
    // Several loops at k/(loops+1), the farthest from the root's first point first; each next
    // one splits the halves on the near side at its share of what is left.
    // (Maya's recorded extrusion bounds after such splits on real scenes match this order, not
    // the nearest loop first.)
    for (int k = loops; k >= 1; --k) {
        p.weight = k == loops ? double(k) / double(loops + 1) : double(k) / double(k + 1);
        geom::SplitRingResult r;
        if (!geom::splitRing(*m, p, &r, &error)) {
            reason = nodeLabel(node) + ": " + error;
            return std::nullopt;
        }
        p.edges = std::move(r.nearHalves);
    }
    c.out.notes.push_back(nodeLabel(node) + ": " + std::to_string(loops) +
                          " loops inserted evenly; their numbering is not Maya's own");
    return m;
}

// polySplit: a path of edge points and free points (desc/edge/vertices), cutting faces between.
std::optional<geom::Mesh> evaluateSplit(Context& c, NodeId n, std::string& reason) {
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    for (const auto& [key, data] : node.attrs)
        if (key.rfind("sps[", 0) == 0 || key.rfind("splitPoints[", 0) == 0) {
            reason = nodeLabel(node) + ": split points given by face triangles (splitPoints) are not evaluated";
            return std::nullopt;
        }
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    std::map<uint64_t, double> fractions, descriptors;
    if (const AttrData* e = attrOf(g, n, "e"))
        forEachNumeric(*e, [&](uint64_t i, const double* v, int) { fractions[i] = v[0]; });
    if (const AttrData* d = attrOf(g, n, "d"))
        forEachNumeric(*d, [&](uint64_t i, const double* v, int) { descriptors[i] = v[0]; });
    const std::map<uint32_t, glm::dvec3> freePoints = vectorElements(ev, n, keyOf(g, n, "v"), 3);
    // Maya 2015's files keep the face of a free point in `edge` and its place in `vertices` in
    // `desc`; earlier ones put the face in `desc` and take free points in order.
    const bool maya2015 = ev.getBool(n, "m2015", false);
    geom::SplitParams p;
    uint32_t nextFree = 0;
    for (const auto& [i, value] : descriptors) {
        if (!std::isfinite(value) || value < -2147483648.0 || value > 4294967295.0) {
            reason = nodeLabel(node) + ": desc[" + std::to_string(i) + "] is not a split descriptor";
            return std::nullopt;
        }
        const uint32_t bits = uint32_t(int64_t(value));
        geom::SplitPoint sp;
        if (bits & 0xC0000000u) {  // on an edge (0x40000000: on a hole's border)
            sp.kind = geom::SplitPoint::Kind::Edge;
            sp.index = int64_t(bits & 0x3FFFFFFFu);
            const auto f = fractions.find(i);
            sp.fraction = f == fractions.end() ? 0.0 : f->second;
        } else {
            sp.kind = geom::SplitPoint::Kind::Face;
            const auto f = fractions.find(i);
            const double face = maya2015 ? (f == fractions.end() ? -1.0 : f->second) : double(bits);
            sp.index = face >= 0.0 && face < 4294967296.0 ? int64_t(face) : -1;
            const uint32_t slot = maya2015 ? bits : nextFree++;
            const auto at = freePoints.find(slot);
            if (at == freePoints.end()) {
                reason = nodeLabel(node) + ": free point " + std::to_string(slot) + " of the split has no position";
                return std::nullopt;
            }
            sp.position = at->second;
        }
        p.points.push_back(sp);
    }
    p.subdivisions = ev.getInt(n, "s", 1);
    p.smoothingAngle = ev.getDouble(n, "sma", 0.0);
    p.dropFreePoints = ev.getBool(n, "c2v", false);
    if (ev.getBool(n, "iwe", false)) c.out.notes.push_back(nodeLabel(node) + ": insertWithEdgeFlow not applied");
    if (ev.getBool(n, "de", false)) c.out.notes.push_back(nodeLabel(node) + ": detachEdges not applied");
    geom::SplitResult r;
    std::string error;
    if (!geom::splitFaces(*m, p, &r, &error)) {
        reason = nodeLabel(node) + ": " + error;
        return std::nullopt;
    }
    if (r.skippedCuts > 0)
        c.out.notes.push_back(nodeLabel(node) + ": " + std::to_string(r.skippedCuts) +
                              " cut(s) between split points found no face holding both ends");
    return m;
}

// polySmoothFace: Catmull-Clark through OpenSubdiv for the exponential method, on every face.
std::optional<geom::Mesh> evaluateSmoothFace(Context& c, NodeId n, std::string& reason) {
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    if (const int method = ev.getInt(n, "mth", 0); method != 0) {
        reason = nodeLabel(node) + ": the " + (method == 1 ? std::string("linear") : "method " + std::to_string(method)) +
                 " smoothing method is not evaluated";
        return std::nullopt;
    }
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    if (const ComponentList* list = componentListOf(g, n, "ics"); list && !list->items.empty()) {
        const std::vector<bool> faces = componentSelection(*list, ComponentKind::Face, m->faceCount(), node, c.out.notes);
        if (std::find(faces.begin(), faces.end(), false) != faces.end()) {
            reason = nodeLabel(node) + ": smoothing only some of the faces is not evaluated";
            return std::nullopt;
        }
    }
    geom::SubdivideParams p;
    p.levels = ev.getInt(n, "dv", 1);
    p.keepBorder = ev.getBool(n, "kb", true);
    p.keepHardEdges = ev.getBool(n, "khe", false);
    p.smoothUvs = ev.getBool(n, "suv", true);
    p.continuity = ev.getDouble(n, "c", 1.0);
    if (!std::isfinite(p.continuity)) p.continuity = 1.0;
    if (ev.getBool(n, "peh", false)) c.out.notes.push_back(nodeLabel(node) + ": propagateEdgeHardness not applied");
    std::string error;
    if (!geom::subdivideMesh(*m, p, nullptr, &error)) {
        reason = nodeLabel(node) + ": " + error;
        return std::nullopt;
    }
    return m;
}

// Element index of a plug's first segment ("output[3]" → 3), 0 without one.
uint32_t firstIndexOf(std::string_view path) {
    if (std::optional<std::vector<PlugSegment>> segs = parsePlugPath(path);
        segs && !segs->empty() && segs->front().indexed() && segs->front().first < int64_t(kMaxElements))
        return uint32_t(segs->front().first);
    return 0;
}

// polySeparate's output[k]: the k-th shell of its input (shells in the order of their lowest face).
std::optional<geom::Mesh> evaluateSeparate(Context& c, NodeId n, const std::string& path, std::string& reason) {
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPoly", "ip"}, reason);
    if (!m) return m;
    const uint32_t k = firstIndexOf(path);
    std::vector<uint32_t> shell;
    const size_t shells = geom::faceShells(*m, shell);
    if (k >= shells) {
        reason = nodeLabel(c.g.node(n)) + ": output[" + std::to_string(k) + "] asks for a shell past the " +
                 std::to_string(shells) + " the mesh has";
        return std::nullopt;
    }
    std::vector<bool> others(m->faceCount());
    for (size_t f = 0; f < others.size(); ++f) others[f] = shell[f] != k;
    geom::deleteFaces(*m, others);
    return m;
}

// polyUnite: its inputs in index order, each through its inputMat (the input shape's world
// matrix when that is what is connected), in one mesh.
std::optional<geom::Mesh> evaluateUnite(Context& c, NodeId n, std::string& reason) {
    const Graph& g = c.g;
    Evaluator& ev = c.ev;
    const Node& node = g.node(n);
    std::map<uint32_t, Plug> inputs, matrices;
    for (const Connection* conn : g.inputs(n)) {
        std::optional<std::vector<PlugSegment>> segs = parsePlugPath(conn->dst.path);
        if (!segs || segs->size() != 1 || !segs->front().indexed() || segs->front().first >= int64_t(kMaxElements)) continue;
        const std::string& name = segs->front().name;
        const uint32_t k = uint32_t(segs->front().first);
        if (name == "inputPoly" || name == "ip") inputs[k] = conn->src;
        else if (name == "inputMat" || name == "im") matrices[k] = conn->src;
    }
    if (inputs.empty()) {
        reason = nodeLabel(node) + " has no input geometry";
        return std::nullopt;
    }
    geom::Mesh united;
    for (const auto& [k, plug] : inputs) {
        std::string why;
        std::optional<geom::Mesh> part = evaluatePlug(c, plug, why);
        if (!part) {
            reason = nodeLabel(node) + ": inputPoly[" + std::to_string(k) + "]: " + why;
            return std::nullopt;
        }
        // A shape's worldMatrix wired in is that instance's world matrix; otherwise the plug's value.
        glm::dmat4 m(1.0);
        const auto it = matrices.find(k);
        std::vector<double> v;
        if (it != matrices.end() && it->second.node < g.size() && it->second.path.rfind("worldMatrix", 0) == 0) {
            const uint32_t instance = firstIndexOf(it->second.path);
            const std::vector<std::vector<NodeId>> paths = g.dagPaths(it->second.node);
            if (instance < paths.size()) m = ev.worldMatrix(paths[instance]);
        } else if (ev.numbers(n, "im[" + std::to_string(k) + "]", v) && v.size() == 16) {
            m = glm::make_mat4(v.data());
        }
        if (!geom::isFinite(m)) {
            reason = nodeLabel(node) + ": inputMat[" + std::to_string(k) + "] is not finite";
            return std::nullopt;
        }
        if (!geom::appendMesh(united, *part, m)) {
            reason = nodeLabel(node) + ": the united mesh is too large";
            return std::nullopt;
        }
    }
    return united;
}

// polyDelEdge: the listed edges dissolve; with cleanVertices, their ends left on two edges go too.
std::optional<geom::Mesh> evaluateDelEdge(Context& c, NodeId n, std::string& reason) {
    std::optional<geom::Mesh> m = evaluateInput(c, n, {"inputPolymesh", "ip"}, reason);
    if (!m) return m;
    const Graph& g = c.g;
    const Node& node = g.node(n);
    const ComponentList* list = componentListOf(g, n, "ics");
    if (!list || list->items.empty()) return m;
    geom::completeEdges(*m, true);
    const std::vector<bool> edges = componentSelection(*list, ComponentKind::Edge, m->edges.size(), node, c.out.notes);
    geom::dissolveEdges(*m, edges, c.ev.getBool(n, "cv", false));
    return m;
}

std::optional<geom::Mesh> evaluatePlug(Context& c, const Plug& src, std::string& reason) {
    const Graph& g = c.g;
    if (src.node >= g.size()) {
        reason = "connection from a node that does not exist";
        return std::nullopt;
    }
    const Node& node = g.node(src.node);
    if (std::find(c.visiting.begin(), c.visiting.end(), src.node) != c.visiting.end()) {
        reason = "construction history cycle through " + nodeLabel(node);
        return std::nullopt;
    }
    if (int(c.visiting.size()) >= kMaxHistoryDepth) {
        reason = "construction history deeper than " + std::to_string(kMaxHistoryDepth) + " nodes";
        return std::nullopt;
    }
    c.visiting.push_back(src.node);
    struct Pop {
        std::vector<NodeId>& v;
        ~Pop() { v.pop_back(); }
    } pop{c.visiting};
    c.out.history.push_back(node.type + " " + node.name);
    const std::string& type = node.type;
    Evaluator& ev = c.ev;

    if (type == "mesh") {
        std::optional<geom::Mesh> m = evaluateShape(c, src.node, reason);
        // worldMesh carries the shape in world space (of its first instance). A deformer takes its
        // input in object space and goes to world space through its own geometry matrix.
        const bool intoDeformer = std::any_of(c.visiting.begin(), c.visiting.end(), [&](NodeId v) {
            return isEvaluatedDeformer(g.node(v).type);
        });
        if (m && !intoDeformer && src.path.rfind("worldMesh", 0) == 0) {
            geom::transformMesh(*m, ev.worldMatrix(g.firstDagPath(src.node)));
        }
        return m;
    }
    if (type == "polyCube" || type == "polySphere" || type == "polyPlane" || type == "polyCylinder" ||
        type == "polyCone" || type == "polyTorus" || type == "polyPlatonicSolid")
        return evaluateCreator(c, src.node, reason);

    if (type == "polyTweak") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (m) applyPointTweaks(vectorElements(ev, src.node, keyOf(g, src.node, "tweak"), 3), *m, node, c.out.notes);
        return m;
    }
    if (type == "polyExtrudeFace") return evaluateExtrudeFace(c, src.node, reason);
    if (type == "polyExtrudeEdge") return evaluateExtrudeEdge(c, src.node, reason);
    if (type == "polyBevel" || type == "polyBevel3") return evaluateBevel(c, src.node, reason);
    if (type == "polyMergeVert") return evaluateMergeVert(c, src.node, reason);
    if (type == "polySplitRing") return evaluateSplitRing(c, src.node, reason);
    if (type == "polySplit") return evaluateSplit(c, src.node, reason);
    if (type == "polySmoothFace") return evaluateSmoothFace(c, src.node, reason);
    if (type == "polyDelEdge") return evaluateDelEdge(c, src.node, reason);
    if (type == "polyCloseBorder") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (!m) return m;
        geom::completeEdges(*m, true);
        std::vector<bool> edges(m->edges.size(), true);  // every border without a list
        if (const ComponentList* list = componentListOf(g, src.node, "ics"); list && !list->items.empty())
            edges = componentSelection(*list, ComponentKind::Edge, m->edges.size(), node, c.out.notes);
        geom::closeBorders(*m, edges);
        return m;
    }
    if (type == "polySeparate") return evaluateSeparate(c, src.node, src.path, reason);
    if (type == "polyUnite") return evaluateUnite(c, src.node, reason);
    if (type == "polyTweakUV") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (!m) return m;
        const std::string setName = g.getString(src.node, "uvs");
        int set = m->currentUvSet;
        for (size_t s = 0; s < m->uvSets.size(); ++s)
            if (!setName.empty() && m->uvSets[s].name == setName) set = int(s);
        if (set < 0 || size_t(set) >= m->uvSets.size()) {
            c.out.notes.push_back(nodeLabel(node) + ": the mesh has no uv set to tweak");
            return m;
        }
        std::vector<glm::vec2>& uvs = m->uvSets[size_t(set)].uvs;
        for (const auto& [index, t] : vectorElements(ev, src.node, keyOf(g, src.node, "uvTweak"), 2))
            if (index < uvs.size() && std::isfinite(t.x) && std::isfinite(t.y))
                uvs[index] += glm::vec2(float(t.x), float(t.y));
        return m;
    }
    if (type == "groupParts") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputGeometry", "ig"}, reason);
        if (m) {
            MeshComponentGroup group;
            group.groupParts = node.name;
            group.groupId = ev.getInt(src.node, "gi", -1);
            if (const ComponentList* list = componentListOf(g, src.node, "ic")) group.components = *list;
            c.out.groups.push_back(std::move(group));
        }
        return m;
    }
    if (type == "transformGeometry") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputGeometry", "ig"}, reason);
        if (!m) return m;
        std::vector<double> v;
        if (!ev.numbers(src.node, "txf", v) || v.size() != 16) return m;  // identity by default
        // Maya's matrix is row-major for row vectors; read column-major it is the column-vector matrix.
        glm::dmat4 mat = glm::make_mat4(v.data());
        if (ev.getBool(src.node, "itf", false)) mat = glm::inverse(mat);
        if (!geom::isFinite(mat)) {
            reason = nodeLabel(node) + ": the transform is not finite";
            return std::nullopt;
        }
        geom::transformMesh(*m, mat);
        return m;
    }
    if (type == "deleteComponent") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputGeometry", "ig"}, reason);
        if (!m) return m;
        if (const ComponentList* list = componentListOf(g, src.node, "dc")) deleteComponents(*m, *list, node, c.out.notes);
        return m;
    }
    if (type == "polySoftEdge") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (!m) return m;
        // Outside the schema the angle is still in the file's angle unit.
        const AttrSpec* spec = node.findAttr("a");
        const double scale = spec && spec->unit == UnitKind::Angle ? 1.0 : g.units.radiansPerAngleUnit;
        const double angle = ev.getDouble(src.node, "a", 30.0) * scale;
        softenEdges(*m, componentListOf(g, src.node, "ics"), std::isfinite(angle) ? angle : 0.0);
        return m;
    }
    if (type == "createColorSet") {
        // Adds an (empty) colour set; the geometry passes through.
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputGeometry", "ig"}, reason);
        if (m) m->colorSets.push_back({g.getString(src.node, "colos"), {}, {}});
        return m;
    }
    if (type == "polyTriangulate") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (!m) return m;
        // The faces listed in inputComponents (all of them without a list).
        std::vector<bool> faces;
        if (const ComponentList* list = componentListOf(g, src.node, "ics"); list && !list->items.empty())
            faces = componentMask(parseComponents(*list).ranges, ComponentKind::Face, m->faceCount());
        if (const size_t kept = geom::triangulateFaces(*m, faces.empty() ? nullptr : &faces))
            c.out.notes.push_back(nodeLabel(node) + ": " + std::to_string(kept) + " faces with holes are left whole");
        return m;
    }
    if (isEvaluatedDeformer(type)) {
        // outputGeometry[k] is the deformation of input[k].inputGeometry.
        uint32_t k = 0;
        if (std::optional<std::vector<PlugSegment>> segs = parsePlugPath(src.path);
            segs && !segs->empty() && segs->front().indexed() && segs->front().first < int64_t(kMaxElements))
            k = uint32_t(segs->front().first);
        const std::string inputPath =
            g.canonicalPath(src.node, *parsePlugPath("input[" + std::to_string(k) + "].inputGeometry"));
        const Plug* in = g.sourceOfCanonical(src.node, inputPath);
        if (!in) {
            reason = nodeLabel(node) + " has no input geometry";
            return std::nullopt;
        }
        std::optional<geom::Mesh> m = evaluatePlug(c, *in, reason);
        if (!m) return m;
        // The deformer's set: the vertices its groupParts lists.
        std::vector<bool> members;
        bool restricted = false;
        if (in->node < g.size() && g.node(in->node).type == "groupParts")
            if (const ComponentList* list = componentListOf(g, in->node, "ic"); list && !list->items.empty()) {
                members = componentMask(parseComponents(*list).ranges, ComponentKind::Vertex, m->points.size());
                restricted = true;
            }
        std::string error = applyDeformer(ev, src.node, k, restricted ? &members : nullptr, *m, c.out.notes);
        if (!error.empty()) {
            reason = error;
            return std::nullopt;
        }
        return m;
    }
    if (type == "nCloth") {
        // The simulation is not run: the cloth renders as its input mesh, the shape it has at the
        // start frame.
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputMesh", "imsh"}, reason);
        if (m) c.out.notes.push_back(nodeLabel(node) + " is not simulated: its input mesh is used");
        return m;
    }
    if (type == "nurbsTessellate") return evaluateNurbsTessellate(ev, src.node, &reason, &c.out.notes);
    if (isUvOnlyHistory(type)) {
        // These change texture coordinates only: the geometry passes through unchanged.
        std::optional<geom::Mesh> m =
            evaluateInput(c, src.node, {"inputPolymesh", "ip", "inputGeometry", "ig", "inMesh", "im"}, reason);
        if (m) c.out.notes.push_back(nodeLabel(node) + " is passed through: its UV edits are not applied, the UVs are its input's");
        return m;
    }
    if (type == "polyNormal" || type == "polyNormalPerVertex") {
        std::optional<geom::Mesh> m = evaluateInput(c, src.node, {"inputPolymesh", "ip"}, reason);
        if (m) c.out.notes.push_back(nodeLabel(node) + " is passed through: its normal edits are not applied");
        return m;
    }
    reason = "history node " + nodeLabel(node) + " is not evaluated";
    return std::nullopt;
}

// --------------------------------------------------------------------------------- the shape
std::optional<geom::Mesh> evaluateShape(Context& c, NodeId shape, std::string& reason) {
    const Graph& g = c.g;
    const Node& node = g.node(shape);
    std::optional<geom::Mesh> mesh;
    const bool stored = hasStoredMesh(g, shape);
    if (std::optional<Plug> in = inputPlug(g, shape, {"inMesh", "i"})) {
        std::string historyReason;
        mesh = evaluatePlug(c, *in, historyReason);
        if (!mesh) {
            if (!stored) {
                reason = historyReason;
                return std::nullopt;
            }
            c.out.notes.push_back("used the geometry cached on " + node.name + ": " + historyReason);
            c.out.usedCachedData = true;
        }
    }
    if (!mesh) {
        if (!stored) {
            reason = "mesh " + node.name + " stores no geometry and has no construction history";
            return std::nullopt;
        }
        std::string error;
        mesh = decodeStoredMesh(g, shape, &error, &c.out.notes);
        if (!mesh) {
            reason = error;
            return std::nullopt;
        }
    }
    applyPointTweaks(vectorElements(c.ev, shape, keyOf(g, shape, "pnts"), 3), *mesh, node, c.out.notes);
    return mesh;
}

// The smooth mesh preview, rendered as Maya Software renders it. Too many levels for the face
// budget come down until the result fits, with a note.
void applySmoothPreview(Evaluator& ev, NodeId shape, MeshEvaluation& out) {
    const Graph& g = ev.graph();
    const Node& node = g.node(shape);
    geom::SubdivideParams p;
    p.levels = ev.getBool(shape, "uspr", true) ? ev.getInt(shape, "lev", 2) : ev.getInt(shape, "rsl", 1);
    p.levels = std::clamp(p.levels, 0, 8);
    p.keepBorder = ev.getBool(shape, "kb", true);
    p.keepHardEdges = ev.getBool(shape, "khe", false);
    p.smoothUvs = ev.getBool(shape, "suv", true);
    const int asked = p.levels;
    while (p.levels > 0 && geom::subdividedFaceCount(*out.mesh, p.levels) > double(geom::kMaxSubdividedFaces)) --p.levels;
    if (p.levels == 0) {
        if (asked > 0) out.notes.push_back("mesh " + node.name + ": the smooth mesh preview is too large to render; the cage renders");
        return;
    }
    if (p.levels < asked)
        out.notes.push_back("mesh " + node.name + ": smooth mesh preview rendered at level " + std::to_string(p.levels) +
                            " of " + std::to_string(asked) + " (face budget)");
    const size_t sourceFaces = out.mesh->faceCount();
    std::vector<uint32_t> origin;
    std::string error;
    if (!geom::subdivideMesh(*out.mesh, p, &origin, &error)) {
        out.notes.push_back("mesh " + node.name + ": the smooth mesh preview is not rendered: " + error);
        return;
    }
    out.faceOrigin = std::move(origin);
    out.sourceFaceCount = sourceFaces;
    out.degenerateFaces.reset();  // of the cage, not of the smoothed mesh
}

// Runs one evaluation so that scene content never aborts a render: an exception or a mesh that
// fails validation becomes a skip, its reason in out.skipReason (`label` prefixes a validation
// error). `evaluate(reason)` returns the mesh or nullopt with its reason.
template <class Evaluate>
void guardedEvaluation(MeshEvaluation& out, const std::string& label, Evaluate&& evaluate) {
    std::string reason;
    try {
        out.mesh = evaluate(reason);
    } catch (const std::exception& e) {
        out.mesh.reset();
        reason = std::string("evaluation failed: ") + e.what();
    }
    if (out.mesh) {
        geom::MeshValidation v = out.mesh->validate();
        if (!v.ok()) {
            out.mesh.reset();
            reason = label + v.errors.front();
        } else {
            out.degenerateFaces = std::move(v.degenerateFaces);
        }
    }
    if (!out.mesh) out.skipReason = reason;
}

}  // namespace

namespace {

// The stored uv sets of a shape in the order a decoded mesh has them: the multi indices k of its
// uvSet[k] attributes, ascending.
std::vector<uint32_t> storedUvSetIndices(const Node& node) {
    std::vector<uint32_t> out;
    for (const auto& [key, data] : node.attrs)
        if (std::optional<uint32_t> k = leadingIndex(key, "uvSet[")) out.push_back(*k);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// The name of stored uv set `k` at position `position`: its uvSetName, else map1 / uvSetN.
std::string storedUvSetName(const Graph& g, NodeId shape, uint32_t k, size_t position) {
    if (const AttrData* name = g.findAttr(shape, "uvSet[" + std::to_string(k) + "].uvSetName"); name && name->hasValue)
        if (const StringValue* s = std::get_if<StringValue>(&name->value); s && !s->text.empty()) return s->text;
    return position == 0 ? "map1" : "uvSet" + std::to_string(position);
}

// Edge element `v` (`width` ≥ 2 numbers) as a decoded mesh has it: its two points, smooth
// unless a third number is 0.
geom::MeshEdge storedEdge(const double* v, int width) {
    return {uint32_t(v[0]), uint32_t(v[1]), width >= 3 ? v[2] != 0.0 : true};
}

// A stored normal made unit length; zero ("not set, compute") for Maya's 1e20 and for one that
// cannot be.
glm::vec3 storedNormal(const double* v) {
    const glm::dvec3 d(v[0], v[1], v[2]);
    const double len = glm::length(d);
    if (std::abs(d.x) >= kUnsetNormal || std::abs(d.y) >= kUnsetNormal || std::abs(d.z) >= kUnsetNormal ||
        !(len > 0.0) || !std::isfinite(len))
        return glm::vec3(0.0f);
    return glm::vec3(d / len);
}

}  // namespace

bool hasStoredMesh(const Graph& graph, NodeId meshShape) {
    if (meshShape >= graph.size()) return false;
    const AttrData* vt = attrOf(graph, meshShape, "vrts");
    const AttrData* fc = attrOf(graph, meshShape, "face");
    return vt && !vt->multi.empty() && fc && (!fc->multi.empty() || fc->hasValue);
}

namespace {

// forEachNumeric over elements [0, end) of `a` in runs of elements on all threads (isolated: a
// thread waiting for the runs takes no other work of its caller's); fn must only write what its
// element owns.
template <class F>
void forEachNumericOnThreads(const AttrData& a, uint64_t end, F&& fn) {
    constexpr uint64_t kRun = 65536;
    if (end <= 2 * kRun) return forEachNumericIn(a, 0, end, fn);
    util::forEachRun(end, kRun, [&](size_t, uint64_t lo, uint64_t hi) { forEachNumericIn(a, lo, hi, fn); });
}

}  // namespace

std::optional<geom::Mesh> decodeStoredMesh(const Graph& g, NodeId shape, std::string* error,
                                           std::vector<std::string>* notes) {
    auto fail = [&](std::string message) -> std::optional<geom::Mesh> {
        if (error) *error = std::move(message);
        return std::nullopt;
    };
    if (shape >= g.size()) return fail("no such node");
    const Node& node = g.node(shape);
    const std::string who = "mesh " + node.name + ": ";
    auto note = [&](std::string message) {
        if (notes) notes->push_back(who + message);
    };
    geom::Mesh mesh;

    // Points.
    const AttrData* vt = attrOf(g, shape, "vrts");
    if (!vt || vt->multi.empty()) return fail(who + "no vertices (.vt)");
    if (vt->multi.endIndex() > kMaxElements) return fail(who + "vertex index " + std::to_string(vt->multi.endIndex() - 1) + " is too large");
    mesh.points.assign(vt->multi.endIndex(), glm::vec3(0.0f));
    forEachNumericOnThreads(*vt, mesh.points.size(), [&](uint64_t i, const double* v, int w) {
        if (w >= 3) mesh.points[i] = glm::vec3(float(v[0]), float(v[1]), float(v[2]));
    });

    // Edges.
    std::vector<geom::MeshEdge>& edges = mesh.edges;
    if (const AttrData* ed = attrOf(g, shape, "edge")) {
        if (ed->multi.endIndex() > kMaxElements) return fail(who + "edge index too large");
        edges.assign(ed->multi.endIndex(), geom::MeshEdge{});
        std::atomic<bool> bad{false};
        forEachNumericOnThreads(*ed, edges.size(), [&](uint64_t i, const double* v, int w) {
            if (w < 2 || !(v[0] >= 0) || !(v[1] >= 0) || v[0] >= double(mesh.points.size()) ||
                v[1] >= double(mesh.points.size()))
                bad.store(true, std::memory_order_relaxed);
            else edges[i] = storedEdge(v, w);
        });
        if (bad.load()) return fail(who + "an edge (.ed) uses a vertex that does not exist");
    }

    // UV sets: uvSet[k].uvSetName / uvSetPoints, or the older uvpt.
    std::map<uint32_t, size_t> uvSetByIndex;  // multi index → position in mesh.uvSets
    for (uint32_t k : storedUvSetIndices(node)) {
        const size_t position = uvSetByIndex.size();
        uvSetByIndex[k] = position;
        geom::UvSet set;
        set.name = storedUvSetName(g, shape, k, position);
        const std::string base = "uvSet[" + std::to_string(k) + "].";
        if (const AttrData* pts = g.findAttr(shape, base + "uvSetPoints")) {
            if (pts->multi.endIndex() > kMaxElements) return fail(who + "uv index too large");
            set.uvs.assign(pts->multi.endIndex(), glm::vec2(0.0f));
            forEachNumericOnThreads(*pts, set.uvs.size(), [&](uint64_t i, const double* v, int w) {
                if (w >= 2) set.uvs[i] = glm::vec2(float(v[0]), float(v[1]));
            });
        }
        mesh.uvSets.push_back(std::move(set));
    }
    if (const AttrData* old = attrOf(g, shape, "uvpt"); old && !old->multi.empty()) {
        if (uvSetByIndex.empty()) {
            uvSetByIndex[0] = 0;
            mesh.uvSets.push_back({"map1", {}, {}});
        }
        geom::UvSet& set = mesh.uvSets[uvSetByIndex.begin()->second];
        if (set.uvs.empty() && old->multi.endIndex() <= kMaxElements) {
            set.uvs.assign(old->multi.endIndex(), glm::vec2(0.0f));
            forEachNumeric(*old, [&](uint64_t i, const double* v, int w) {
                if (w >= 2) set.uvs[i] = glm::vec2(float(v[0]), float(v[1]));
            });
        }
    }
    const std::string current = g.getString(shape, "currentUVSet");
    for (size_t s = 0; s < mesh.uvSets.size(); ++s)
        if (mesh.uvSets[s].name == current) mesh.currentUvSet = int(s);

    // Colour sets: colorSet[k].colorName / colorSetPoints; polyFaces `fc` ids index the first.
    for (const auto& [key, data] : node.attrs) {
        std::optional<uint32_t> k = leadingIndex(key, "colorSet[");
        if (!k || key != "colorSet[" + std::to_string(*k) + "].colorSetPoints") continue;
        if (data.multi.endIndex() > kMaxElements) continue;
        geom::ColorSet set;
        set.name = g.getString(shape, "colorSet[" + std::to_string(*k) + "].colorName");
        set.colors.assign(data.multi.endIndex(), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        forEachNumeric(data, [&](uint64_t i, const double* v, int w) {
            for (int c = 0; c < std::min(w, 4); ++c) set.colors[i][c] = float(v[c]);
        });
        mesh.colorSets.push_back(std::move(set));
    }

    // Faces: polyFaces runs in index order.
    const AttrData* fc = attrOf(g, shape, "face");
    if (!fc) return fail(who + "no faces (.fc)");
    // Face i is face i - runFirst[r] of runs[r], r = faceRun[i]; kNoRun when no record has it.
    constexpr uint32_t kNoRun = UINT32_MAX;
    std::vector<const PolyFaces*> runs;
    std::vector<uint64_t> runFirst;
    std::vector<uint32_t> faceRun;
    auto addRun = [&](uint64_t first, const Value& value) {
        const auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(&value);
        if (!pf || !*pf) return;
        const size_t count = (*pf)->faceCount();
        if (first + count > kMaxElements) return;
        if (faceRun.size() < first + count) faceRun.resize(first + count, kNoRun);
        std::fill_n(faceRun.begin() + ptrdiff_t(first), count, uint32_t(runs.size()));
        runs.push_back(pf->get());
        runFirst.push_back(first);
    };
    if (fc->hasValue) addRun(0, fc->value);
    for (const auto& [first, run] : fc->multi.runs()) addRun(first, run.value);
    const size_t missing = size_t(std::count(faceRun.begin(), faceRun.end(), kNoRun));
    if (missing) note(std::to_string(missing) + " face indices have no polyFaces record");

    // The faces are read in runs of record faces on all threads (isolated: a thread waiting for the
    // runs takes no other work of its caller's): first each run's count of faces, loops and
    // corners, then each run writes its part of the mesh's arrays, sized once from the counts (no
    // growth, no spare capacity), with the uv ids of each set and the colour ids when there are
    // colours. What a run finds is added up, and the first run with a broken face names it.
    constexpr size_t kRun = 8192;
    const size_t runCount = util::runCount(faceRun.size(), kRun);
    auto eachRun = [&](auto&& body) { util::forEachRun(faceRun.size(), kRun, body); };
    struct RunCounts {
        size_t faces = 0, loops = 0, corners = 0;
    };
    std::vector<RunCounts> runStart(runCount + 1);
    eachRun([&](size_t r, size_t lo, size_t hi) {
        RunCounts& c = runStart[r + 1];
        for (size_t f = lo; f < hi; ++f) {
            if (faceRun[f] == kNoRun) continue;
            const PolyFaces& pf = *runs[faceRun[f]];
            ++c.faces;
            for (size_t loop : pf.loops(size_t(f - runFirst[faceRun[f]]))) {
                ++c.loops;
                c.corners += pf.edgeCount(loop);
            }
        }
    });
    for (size_t r = 0; r < runCount; ++r) {
        runStart[r + 1].faces += runStart[r].faces;
        runStart[r + 1].loops += runStart[r].loops;
        runStart[r + 1].corners += runStart[r].corners;
    }
    const RunCounts total = runStart[runCount];
    if (total.corners >= UINT32_MAX || total.loops >= UINT32_MAX)
        return fail(who + std::to_string(total.corners) + " face-vertices: too many for one mesh");
    mesh.faceVertices.resize(total.corners);
    mesh.loopStarts.assign(total.loops + 1, 0);
    mesh.faceLoopStarts.assign(total.faces + 1, 0);
    // A set without uvs can take no uv id: it gets no table.
    std::vector<std::vector<int32_t>> setIds(mesh.uvSets.size());
    for (size_t s = 0; s < mesh.uvSets.size(); ++s)
        if (!mesh.uvSets[s].uvs.empty()) setIds[s].assign(total.corners, -1);
    std::vector<int32_t> colorIds(mesh.colorSets.empty() ? 0 : total.corners, -1);
    struct RunFound {
        size_t brokenLoops = 0, badUvIds = 0, unknownUvSets = 0;
        bool anyColor = false;
        std::string failure;  // the run's first face that uses an edge that does not exist
    };
    std::vector<RunFound> found(runCount);
    eachRun([&](size_t r, size_t lo, size_t hi) {
        RunFound& out = found[r];
        std::vector<int32_t> edgeScratch, idScratch;
        size_t corner = runStart[r].corners, loopAt = runStart[r].loops, faceAt = runStart[r].faces;
        // Writes `loop`'s points at the next corners; false when it uses an edge that does not exist.
        auto readLoop = [&](const PolyFaces& pf, size_t loop) -> bool {
            const std::span<const int32_t> loopEdges = pf.edges(loop, edgeScratch);
            const size_t base = corner;
            uint32_t previousEnd = 0, first = 0;
            bool meets = true;
            for (size_t i = 0; i < loopEdges.size(); ++i) {
                const int32_t e = loopEdges[i];
                const uint32_t idx = e >= 0 ? uint32_t(e) : uint32_t(~e);
                if (idx >= edges.size()) return false;
                const uint32_t start = e >= 0 ? edges[idx].v0 : edges[idx].v1;
                const uint32_t end = e >= 0 ? edges[idx].v1 : edges[idx].v0;
                if (i == 0) first = start;
                else if (start != previousEnd) meets = false;
                previousEnd = end;
                mesh.faceVertices[base + i] = start;
            }
            if (!loopEdges.empty() && previousEnd != first) meets = false;
            if (!meets) ++out.brokenLoops;
            const size_t count = loopEdges.size();
            corner += count;
            mesh.loopStarts[++loopAt] = uint32_t(corner);
            for (size_t k = 0; k < pf.uvCount(loop); ++k) {
                const PolyFaces::Uv uv = pf.uv(loop, k, idScratch);
                const auto it = uvSetByIndex.find(uint32_t(uv.set));
                if (it == uvSetByIndex.end()) {
                    ++out.unknownUvSets;
                    continue;
                }
                const size_t s = it->second;
                for (size_t i = 0; i < uv.ids.size() && i < count; ++i) {
                    const int32_t id = uv.ids[i];
                    if (id < 0 || size_t(id) >= mesh.uvSets[s].uvs.size()) {
                        ++out.badUvIds;
                        continue;
                    }
                    setIds[s][base + i] = id;
                }
            }
            const std::span<const int32_t> colors = mesh.colorSets.empty() ? std::span<const int32_t>() : pf.colors(loop, idScratch);
            for (size_t i = 0; i < colors.size() && i < count; ++i) {
                const int32_t id = colors[i];
                if (id >= 0 && size_t(id) < mesh.colorSets[0].colors.size()) {
                    colorIds[base + i] = id;
                    out.anyColor = true;
                }
            }
            return true;
        };
        for (size_t f = lo; f < hi; ++f) {
            if (faceRun[f] == kNoRun) continue;
            const PolyFaces& pf = *runs[faceRun[f]];
            const auto loops = pf.loops(size_t(f - runFirst[faceRun[f]]));
            if (!readLoop(pf, loops.front())) {
                out.failure = "face " + std::to_string(f) + " uses an edge that does not exist (of " +
                              std::to_string(edges.size()) + ")";
                return;
            }
            for (size_t k = 1; k < loops.size(); ++k)
                if (!readLoop(pf, loops[k])) {
                    out.failure = "a hole of face " + std::to_string(f) + " uses an edge that does not exist";
                    return;
                }
            mesh.faceLoopStarts[++faceAt] = uint32_t(loopAt);
        }
    });
    size_t brokenLoops = 0, badUvIds = 0, unknownUvSets = 0;
    bool anyColor = false;
    for (const RunFound& r : found) {
        if (!r.failure.empty()) return fail(who + r.failure);
        brokenLoops += r.brokenLoops;
        badUvIds += r.badUvIds;
        unknownUvSets += r.unknownUvSets;
        anyColor |= r.anyColor;
    }
    if (brokenLoops) note(std::to_string(brokenLoops) + " face loops whose edges do not meet");
    if (badUvIds) note(std::to_string(badUvIds) + " uv ids out of range were dropped");
    if (unknownUvSets) note(std::to_string(unknownUvSets) + " uv records name a uv set that does not exist");
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        const bool used = std::any_of(setIds[s].begin(), setIds[s].end(), [](int32_t id) { return id >= 0; });
        mesh.uvSets[s].faceVertexUvs = used ? std::move(setIds[s]) : std::vector<int32_t>{};
    }
    if (anyColor) mesh.colorSets[0].faceVertexColors = std::move(colorIds);

    // Per face-vertex normals, in face order.
    if (const AttrData* n = attrOf(g, shape, "normals"); n && !n->multi.empty()) {
        if (n->multi.endIndex() == mesh.faceVertices.size()) {
            mesh.normals.assign(mesh.faceVertices.size(), glm::vec3(0.0f));
            forEachNumericOnThreads(*n, mesh.normals.size(), [&](uint64_t i, const double* v, int w) {
                if (w >= 3) mesh.normals[i] = storedNormal(v);
            });
        } else {
            note(std::to_string(n->multi.endIndex()) + " normals for " + std::to_string(mesh.faceVertices.size()) +
                 " face-vertices were ignored");
        }
    }

    const geom::MeshValidation v = mesh.validate();
    if (!v.ok()) return fail(who + v.errors.front());
    return mesh;
}

bool storedMeshMakesWindows(Evaluator& ev, NodeId shape) {
    const Graph& g = ev.graph();
    if (shape >= g.size() || g.node(shape).type != "mesh" || !hasStoredMesh(g, shape)) return false;
    if (inputPlug(g, shape, {"inMesh", "i"}) || ev.getInt(shape, "dsm", 0) != 0) return false;
    if (!vectorElements(ev, shape, keyOf(g, shape, "pnts"), 3).empty()) return false;
    if (const AttrData* old = attrOf(g, shape, "uvpt"); old && !old->multi.empty()) return false;
    // Faces from one plain record, or from records that follow one another from face 0.
    const AttrData* fc = attrOf(g, shape, "face");
    if (fc->hasValue) {
        const auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(&fc->value);
        return fc->multi.empty() && pf && *pf;
    }
    uint64_t next = 0;
    for (const auto& [first, run] : fc->multi.runs()) {
        const auto* pf = std::get_if<std::shared_ptr<const PolyFaces>>(&run.value);
        if (!pf || !*pf || first != next) return false;
        next = uint64_t(first) + (*pf)->faceCount();
    }
    return next > 0 && next <= kMaxElements;
}

namespace {

// table[place] = convert(values, width) for each id of `ids` stored as an element of multi
// attribute `a` with at least `minWidth` numbers (read run by run of consecutive ids); the entries
// of ids not stored are left as they are.
template <class T, class Convert>
void readAtPlaces(const AttrData& a, const geom::WindowIds& ids, int minWidth, std::vector<T>& table, Convert&& convert) {
    ids.forEachRun([&](size_t place, uint32_t first, uint64_t end) {
        forEachNumericIn(a, first, end, [&](uint64_t k, const double* v, int width) {
            if (width >= minWidth) table[place + (k - first)] = convert(v, width);
        });
    });
}

}  // namespace

std::optional<geom::MeshWindow> decodeStoredMeshWindow(const Graph& g, NodeId shape, const geom::MeshPieces& pieces,
                                                       size_t piece, uint64_t faceVertexCount) {
    if (shape >= g.size() || piece >= pieces.pieces().size()) return std::nullopt;
    const Node& node = g.node(shape);
    const AttrData* vt = attrOf(g, shape, "vrts");
    const AttrData* fc = attrOf(g, shape, "face");
    if (!vt || !fc) return std::nullopt;
    const std::span<const geom::FaceRun> around = pieces.aroundRuns(piece);
    geom::MeshWindow w;
    w.window = true;
    geom::Mesh& mesh = w.mesh;

    const AttrData* ed = attrOf(g, shape, "edge");

    // The current uv set: its multi index and its uv count.
    const bool mapsUvs = pieces.mapsUvs();
    int32_t currentSet = -1;
    size_t uvCount = 0;
    const AttrData* uvPoints = nullptr;
    geom::UvSet set;
    if (mapsUvs) {
        const std::vector<uint32_t> sets = storedUvSetIndices(node);
        if (sets.empty()) return std::nullopt;
        const std::string current = g.getString(shape, "currentUVSet");
        size_t position = 0;
        for (size_t s = 0; s < sets.size(); ++s)
            if (storedUvSetName(g, shape, sets[s], s) == current) position = s;
        currentSet = int32_t(sets[position]);
        set.name = storedUvSetName(g, shape, sets[position], position);
        if ((uvPoints = g.findAttr(shape, "uvSet[" + std::to_string(currentSet) + "].uvSetPoints"))) {
            if (uvPoints->multi.endIndex() > kMaxElements) return std::nullopt;
            uvCount = uvPoints->multi.endIndex();
        }
    }

    // The faces of the around runs: their loops, with the whole mesh's signed edge ids and uv ids
    // for now.
    mesh.loopStarts.clear();
    mesh.faceLoopStarts.clear();
    std::vector<int32_t>& uvIds = set.faceVertexUvs;
    std::vector<int32_t> cornerEdges, edgeScratch, idScratch;
    for (const geom::FaceRun& r : around)
        for (uint32_t f = r.first; f < r.end; ++f) {
            const PolyFaces* pf = nullptr;
            size_t at = f;
            if (fc->hasValue) {
                pf = std::get<std::shared_ptr<const PolyFaces>>(fc->value).get();
            } else if (uint32_t off = 0; const MultiStore::Run* run = fc->multi.find(f, &off)) {
                pf = std::get<std::shared_ptr<const PolyFaces>>(run->value).get();
                at = off;
            }
            if (!pf || at >= pf->faceCount()) return std::nullopt;
            mesh.faceLoopStarts.push_back(uint32_t(mesh.loopStarts.size()));
            for (size_t loop : pf->loops(at)) {
                mesh.loopStarts.push_back(uint32_t(cornerEdges.size()));
                const size_t base = cornerEdges.size();
                const std::span<const int32_t> loopEdges = pf->edges(loop, edgeScratch);
                cornerEdges.insert(cornerEdges.end(), loopEdges.begin(), loopEdges.end());
                if (!mapsUvs) continue;
                uvIds.resize(cornerEdges.size(), -1);
                for (size_t k = 0; k < pf->uvCount(loop); ++k) {
                    const PolyFaces::Uv uv = pf->uv(loop, k, idScratch);
                    if (uv.set != currentSet) continue;
                    for (size_t i = 0; i < uv.ids.size() && i < loopEdges.size(); ++i) {
                        const int32_t id = uv.ids[i];
                        if (id < 0 || size_t(id) >= uvCount) continue;
                        uvIds[base + i] = id;
                    }
                }
            }
        }
    mesh.loopStarts.push_back(uint32_t(cornerEdges.size()));
    mesh.faceLoopStarts.push_back(uint32_t(mesh.loopStarts.size() - 1));

    // The edges they walk, read in ascending order, as decodeStoredMesh makes them (an unset edge
    // is {0, 0, smooth}); each face-vertex is its edge's first point, or its second walked backwards.
    {
        std::vector<uint32_t> ids(cornerEdges.size());
        for (size_t i = 0; i < cornerEdges.size(); ++i)
            ids[i] = cornerEdges[i] >= 0 ? uint32_t(cornerEdges[i]) : uint32_t(~cornerEdges[i]);
        const geom::WindowIds walked(std::move(ids));
        std::vector<geom::MeshEdge> byPlace(walked.size());
        if (ed) readAtPlaces(*ed, walked, 2, byPlace, storedEdge);
        mesh.faceVertices.resize(cornerEdges.size());
        for (size_t i = 0; i < cornerEdges.size(); ++i) {
            const int32_t e = cornerEdges[i];
            const geom::MeshEdge& edge = byPlace[walked.place(e >= 0 ? uint32_t(e) : uint32_t(~e))];
            mesh.faceVertices[i] = e >= 0 ? edge.v0 : edge.v1;
        }
    }
    util::release(cornerEdges);

    // The points they use, ascending, read run by run; the face-vertices renumbered to them.
    const geom::WindowIds points(mesh.faceVertices);
    for (uint32_t& q : mesh.faceVertices) q = points.place(q);
    mesh.points.assign(points.size(), glm::vec3(0.0f));
    readAtPlaces(*vt, points, 3, mesh.points,
                 [](const double* v, int) { return glm::vec3(float(v[0]), float(v[1]), float(v[2])); });

    // The uvs they use, the same way.
    if (mapsUvs) {
        std::vector<uint32_t> ids;
        for (const int32_t id : uvIds)
            if (id >= 0) ids.push_back(uint32_t(id));
        const geom::WindowIds uvs(std::move(ids));
        for (int32_t& id : uvIds)
            if (id >= 0) id = int32_t(uvs.place(uint32_t(id)));
        set.uvs.assign(uvs.size(), glm::vec2(0.0f));
        if (uvPoints)
            readAtPlaces(*uvPoints, uvs, 2, set.uvs, [](const double* v, int) { return glm::vec2(float(v[0]), float(v[1])); });
        mesh.uvSets.push_back(std::move(set));
        mesh.currentUvSet = 0;
    }

    // The edges of the piece's edge runs between those points, in order (an unset edge joins
    // point 0 to itself).
    if (ed) {
        for (const geom::EdgeRun& r : pieces.edgeRuns(piece)) {
            uint64_t next = r.first;
            auto unsetUpTo = [&](uint64_t end) {
                for (; next < end; ++next)
                    if (points.contains(0)) mesh.edges.push_back({points.place(0), points.place(0), true});
            };
            forEachNumericIn(*ed, r.first, r.end, [&](uint64_t i, const double* v, int width) {
                unsetUpTo(i);
                next = i + 1;
                if (width < 2) return;
                const geom::MeshEdge e = storedEdge(v, width);
                if (points.contains(e.v0) && points.contains(e.v1))
                    mesh.edges.push_back({points.place(e.v0), points.place(e.v1), e.smooth});
            });
            unsetUpTo(r.end);
        }
    }

    // Stored normals of the window's face-vertices, when the shape has one for each face-vertex.
    if (const AttrData* n = attrOf(g, shape, "normals"); n && !n->multi.empty() && n->multi.endIndex() == faceVertexCount) {
        mesh.normals.assign(mesh.faceVertices.size(), glm::vec3(0.0f));
        size_t place = 0;
        for (const geom::FaceRun& r : around) {
            const size_t faces = r.end - r.first;
            const uint64_t count = mesh.faceVertexBegin(place + faces) - mesh.faceVertexBegin(place);
            const uint64_t first = r.firstFaceVertex, to = mesh.faceVertexBegin(place);
            forEachNumericIn(*n, first, first + count, [&](uint64_t i, const double* v, int width) {
                if (width >= 3) mesh.normals[to + (i - first)] = storedNormal(v);
            });
            place += faces;
        }
    }
    return w;
}

MeshEvaluation evaluateMeshShape(Evaluator& ev, NodeId meshShape) {
    MeshEvaluation out;
    const Graph& g = ev.graph();
    if (meshShape >= g.size()) {
        out.skipReason = "no such node";
        return out;
    }
    const Node& node = g.node(meshShape);
    if (node.type != "mesh") {
        out.skipReason = node.name + " is a " + node.type + ", not a mesh";
        return out;
    }
    Context c{ev, g, out, {meshShape}};
    guardedEvaluation(out, "mesh " + node.name + ": ", [&](std::string& reason) { return evaluateShape(c, meshShape, reason); });
    if (out.mesh && ev.getInt(meshShape, "dsm", 0) != 0) applySmoothPreview(ev, meshShape, out);
    if (!out.mesh && out.skipReason.empty()) out.skipReason = "mesh " + node.name + " could not be evaluated";
    return out;
}

MeshEvaluation evaluateMeshPlug(Evaluator& ev, const Plug& output) {
    MeshEvaluation out;
    Context c{ev, ev.graph(), out, {}};
    guardedEvaluation(out, "", [&](std::string& reason) { return evaluatePlug(c, output, reason); });
    if (!out.mesh && out.skipReason.empty()) out.skipReason = "the plug's mesh could not be evaluated";
    return out;
}

std::optional<geom::PrimitiveCounts> primitiveShapeCounts(Evaluator& ev, NodeId meshShape) {
    const Graph& g = ev.graph();
    if (meshShape >= g.size() || g.node(meshShape).type != "mesh") return std::nullopt;
    if (ev.getInt(meshShape, "dsm", 0) != 0) return std::nullopt;
    const std::optional<Plug> in = inputPlug(g, meshShape, {"inMesh", "i"});
    if (!in || in->node >= g.size()) return std::nullopt;
    const NodeId n = in->node;
    const std::string& type = g.node(n).type;
    std::optional<geom::PrimitiveCounts> counts;
    if (type == "polySphere") counts = geom::polySphereCounts(polySphereParams(ev, n));
    else if (type == "polyPlane") counts = geom::polyPlaneCounts(polyPlaneParams(ev, n));
    else if (type == "polyCube") counts = geom::polyCubeCounts(polyCubeParams(ev, n));
    else if (type == "polyCone") counts = geom::polyConeCounts(polyConeParams(ev, n));
    else if (type == "polyTorus") counts = geom::polyTorusCounts(polyTorusParams(ev, n));
    else if (type == "polyCylinder") {
        // A round cap is noted when the mesh is evaluated: that shape is not deferred.
        const geom::PolyCylinderParams p = polyCylinderParams(ev, n);
        if (!p.roundCap) counts = geom::polyCylinderCounts(p);
    }
    // Only a primitive's shape reads its point tweaks here: a tweak that moves a point needs the mesh.
    if (counts)
        for (const auto& [index, t] : vectorElements(ev, meshShape, keyOf(g, meshShape, "pnts"), 3))
            if (t != glm::dvec3(0.0)) return std::nullopt;
    return counts;
}

std::optional<geom::Mesh> evaluateMesh(Evaluator& ev, NodeId meshShape, std::string* skipReason) {
    MeshEvaluation e = evaluateMeshShape(ev, meshShape);
    if (!e.mesh && skipReason) *skipReason = e.skipReason;
    return std::move(e.mesh);
}

}  // namespace pushpin::scene
