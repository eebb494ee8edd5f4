// core/scene/nurbs_eval.cpp: nurbsSurface / nurbsCurve shapes → geom::NurbsSurface / geom::NurbsCurve.
#include "core/scene/nurbs_eval.h"

#include "core/geom/nurbs_ops.h"
#include "core/geom/nurbs_primitives.h"
#include "core/scene/detail/multi_elements.h"

#include <glm/mat4x4.hpp>

#include <cctype>
#include <cmath>
#include <algorithm>
#include <initializer_list>
#include <map>
#include <numbers>

namespace pushpin::scene {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxShapeChain = 16;  // shape → shape `create` connections followed at most

std::nullopt_t failWith(std::string* error, const std::string& msg) {
    if (error) *error = msg;
    return std::nullopt;
}

std::string formName(int form) {
    return std::to_string(form) + " is not 0 (open), 1 (closed) or 2 (periodic)";
}

// Checks one direction of Maya's data and returns its CV count (0 on error).
int checkDirection(const char* dir, int degree, int form, const std::vector<double>& knots, int cvCount,
                   std::string* error) {
    if (degree < 1 || degree > geom::kMaxNurbsDegree) {
        failWith(error, std::string("degree") + dir + " " + std::to_string(degree) + " is outside 1.." +
                            std::to_string(geom::kMaxNurbsDegree));
        return 0;
    }
    if (form < 0 || form > 2) {
        failWith(error, std::string("form") + dir + " " + formName(form));
        return 0;
    }
    const int n = cvCount > 0 ? cvCount : int(knots.size()) + 1 - degree;
    if (n < degree + 1 || int(knots.size()) != n + degree - 1) {
        failWith(error, std::string(dir) + (dir[0] ? " " : "") + "knot count " + std::to_string(knots.size()) + " does not match " +
                            std::to_string(n) + " CVs + degree " + std::to_string(degree) + " - 1");
        return 0;
    }
    return n;
}

glm::dvec4 homogeneous(const double* c, int dimension, bool rational, RationalCvLayout layout) {
    glm::dvec3 p(c[0], c[1], dimension >= 3 ? c[2] : 0.0);
    if (!rational) return glm::dvec4(p, 1.0);
    const double w = c[dimension];
    if (layout == RationalCvLayout::PreMultiplied) return glm::dvec4(p, w);
    return glm::dvec4(p * w, w);
}

const NurbsSurfaceData* cachedSurface(const Graph& g, NodeId shape) {
    const Value* v = g.value(shape, "cc");
    if (!v) return nullptr;
    auto p = std::get_if<std::shared_ptr<const NurbsSurfaceData>>(v);
    return p && *p ? p->get() : nullptr;
}

const NurbsCurveData* cachedCurve(const Graph& g, NodeId shape) {
    const Value* v = g.value(shape, "cc");
    if (!v) return nullptr;
    auto p = std::get_if<std::shared_ptr<const NurbsCurveData>>(v);
    return p && *p ? p->get() : nullptr;
}

// Attribute values of a creator node. An attribute nobody set or connected takes Maya's default for
// that node type (given by the caller); this also covers creator types and attributes the schema
// does not model, and defaults that differ between creator types sharing a base (sphere spans = 4).
class CreatorAttrs {
public:
    CreatorAttrs(Evaluator& ev, NodeId node) : m_ev(ev), m_node(node) {}

    double number(const char* name, double mayaDefault) {
        if (!isSet({name})) return mayaDefault;
        std::vector<double> v;
        if (m_ev.numbers(m_node, name, v) && !v.empty()) return v[0];
        return mayaDefault;
    }
    int integer(const char* name, int mayaDefault) {
        const double x = number(name, mayaDefault);
        return std::isfinite(x) && std::abs(x) < 1e9 ? int(std::lround(x)) : -1;
    }
    glm::dvec3 vec3(const char* name, std::initializer_list<const char*> children, glm::dvec3 mayaDefault) {
        bool set = isSet({name});
        for (const char* c : children) set = set || isSet({c});
        if (!set) return mayaDefault;
        std::vector<double> v;
        if (m_ev.numbers(m_node, name, v) && v.size() >= 3) return glm::dvec3(v[0], v[1], v[2]);
        return mayaDefault;
    }

private:
    bool isSet(std::initializer_list<const char*> names) const {
        const Graph& g = m_ev.graph();
        for (const char* n : names) {
            if (g.value(m_node, n) || g.source(m_node, n)) return true;
        }
        return false;
    }
    Evaluator& m_ev;
    NodeId m_node;
};

// Which face of makeNurbCube a source plug names: outputSurface[i] / os[i] or outputSurfaceN / osN.
int cubeFaceIndex(const std::string& plugPath) {
    const size_t bracket = plugPath.find('[');
    if (bracket != std::string::npos) {
        const int i = std::atoi(plugPath.c_str() + bracket + 1);
        return i;
    }
    size_t digits = plugPath.size();
    while (digits > 0 && std::isdigit(static_cast<unsigned char>(plugPath[digits - 1]))) --digits;
    if (digits == plugPath.size()) return 0;
    return std::atoi(plugPath.c_str() + digits);
}

bool isSurfaceCreator(const std::string& type) {
    return type == "makeNurbSphere" || type == "makeNurbPlane" || type == "makeNurbCylinder" ||
           type == "makeNurbCone" || type == "makeNurbTorus" || type == "makeNurbCube";
}

const glm::dvec3 kDefaultAxis(1.0, 0.0, 0.0);  // primitive.axis default

std::optional<geom::NurbsSurface> evaluateCreator(Evaluator& ev, NodeId node, const std::string& sourcePlug,
                                                  std::string* error) {
    const std::string& type = ev.graph().node(node).type;
    CreatorAttrs a(ev, node);
    const glm::dvec3 axis = a.vec3("ax", {"axx", "axy", "axz"}, kDefaultAxis);
    const glm::dvec3 pivot = a.vec3("p", {"px", "py", "pz"}, glm::dvec3(0.0));
    if (type == "makeNurbSphere") {
        geom::NurbsSphereParams p;
        p.radius = a.number("r", 1.0);
        p.startSweep = a.number("ssw", 0.0);
        p.endSweep = a.number("esw", kTwoPi);
        p.degree = a.integer("d", 3);
        p.sections = a.integer("s", 8);
        p.spans = a.integer("nsp", 4);
        p.axis = axis;
        p.pivot = pivot;
        return geom::makeNurbSphere(p, error);
    }
    if (type == "makeNurbCylinder" || type == "makeNurbCone") {
        geom::NurbsCylinderParams p;
        p.radius = a.number("r", 1.0);
        p.heightRatio = a.number("hr", 2.0);
        p.startSweep = a.number("ssw", 0.0);
        p.endSweep = a.number("esw", kTwoPi);
        p.degree = a.integer("d", 3);
        p.sections = a.integer("s", 8);
        p.spans = a.integer("nsp", 1);
        p.axis = axis;
        p.pivot = pivot;
        return type == "makeNurbCone" ? geom::makeNurbCone(p, error) : geom::makeNurbCylinder(p, error);
    }
    if (type == "makeNurbTorus") {
        geom::NurbsTorusParams p;
        p.radius = a.number("r", 1.0);
        p.heightRatio = a.number("hr", 0.5);
        p.minorSweep = a.number("msw", kTwoPi);
        p.startSweep = a.number("ssw", 0.0);
        p.endSweep = a.number("esw", kTwoPi);
        p.degree = a.integer("d", 3);
        p.sections = a.integer("s", 8);
        p.spans = a.integer("nsp", 4);
        p.axis = axis;
        p.pivot = pivot;
        return geom::makeNurbTorus(p, error);
    }
    if (type == "makeNurbPlane") {
        geom::NurbsPlaneParams p;
        p.width = a.number("w", 1.0);
        p.lengthRatio = a.number("lr", 1.0);
        p.patchesU = a.integer("u", 1);
        p.patchesV = a.integer("v", 1);
        p.degree = a.integer("d", 3);
        p.axis = axis;
        p.pivot = pivot;
        return geom::makeNurbPlane(p, error);
    }
    if (type == "makeNurbCube") {
        geom::NurbsCubeParams p;
        p.width = a.number("w", 1.0);
        p.lengthRatio = a.number("lr", 1.0);
        p.heightRatio = a.number("hr", 1.0);
        p.patchesU = a.integer("u", 1);
        p.patchesV = a.integer("v", 1);
        p.degree = a.integer("d", 3);
        p.axis = axis;
        p.pivot = pivot;
        const int face = cubeFaceIndex(sourcePlug);
        if (face < 0 || face > 5) return failWith(error, "makeNurbCube has no output surface " + std::to_string(face));
        auto faces = geom::makeNurbCube(p, error);
        if (!faces) return std::nullopt;
        return std::move((*faces)[size_t(face)]);
    }
    return failWith(error, "node type " + type + " is not a NURBS surface creator");
}

std::optional<geom::NurbsCurve> curveOfShape(Evaluator& ev, NodeId shape, std::string* skipReason, std::string* note,
                                             int depth);
std::optional<geom::NurbsSurface> surfaceOfShape(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                 std::string* note, int depth);

void addNote(std::string* note, const std::string& text) {
    if (note && !text.empty()) *note += (note->empty() ? "" : "; ") + text;
}

bool startsWith(const std::string& s, std::string_view prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

// The element index of a multi plug path ("worldSpace[2]" → 2); 0 without an index.
int plugIndex(const std::string& path) {
    const size_t bracket = path.find('[');
    return bracket == std::string::npos ? 0 : std::atoi(path.c_str() + bracket + 1);
}

// The world matrix of DAG instance `index` of a shape (worldSpace[index] is in that space).
std::optional<glm::dmat4> instanceMatrix(Evaluator& ev, NodeId shape, int index) {
    const auto paths = ev.graph().dagPaths(shape);
    if (index < 0 || size_t(index) >= paths.size()) return std::nullopt;
    return ev.worldMatrix(paths[size_t(index)]);
}

std::optional<geom::NurbsCurve> circleOfCreator(Evaluator& ev, NodeId node, std::string* error) {
    CreatorAttrs a(ev, node);
    geom::NurbsCircleParams p;
    p.radius = a.number("r", 1.0);
    p.sweep = a.number("sw", kTwoPi);
    p.degree = a.integer("d", 3);
    p.sections = a.integer("s", 8);
    p.normal = a.vec3("nr", {"nrx", "nry", "nrz"}, glm::dvec3(0, 0, 1));
    p.center = a.vec3("c", {"cx", "cy", "cz"}, glm::dvec3(0.0));
    return geom::makeNurbCircle(p, error);
}

// The curve a plug carries: a nurbsCurve shape's `local` (or `create`) in object space, its
// `worldSpace[i]` in world space, or a makeNurbCircle output.
std::optional<geom::NurbsCurve> curveAtPlug(Evaluator& ev, const Plug& src, std::string* error, std::string* note,
                                            int depth) {
    const Graph& g = ev.graph();
    const Node& n = g.node(src.node);
    if (n.type == "nurbsCurve") {
        auto c = curveOfShape(ev, src.node, error, note, depth + 1);
        if (!c || !startsWith(src.path, "worldSpace")) return c;
        const int instance = plugIndex(src.path);
        const auto m = instanceMatrix(ev, src.node, instance);
        if (!m) return failWith(error, n.name + " has no DAG instance " + std::to_string(instance));
        std::string err;
        auto world = geom::transformCurve(*c, *m, &err);
        if (!world) return failWith(error, n.name + " in world space: " + err);
        return world;
    }
    if (n.type == "makeNurbCircle") {
        std::string err;
        auto c = circleOfCreator(ev, src.node, &err);
        if (!c) return failWith(error, "makeNurbCircle (" + n.name + "): " + err);
        return c;
    }
    return failWith(error, "history node " + n.type + " (" + n.name + ") is not evaluated");
}

std::optional<geom::NurbsSurface> evaluateRevolve(Evaluator& ev, NodeId node, std::string* error, std::string* note,
                                                  int depth) {
    const Graph& g = ev.graph();
    const auto src = g.source(node, "inputCurve");
    if (!src) return failWith(error, "no input curve");
    auto profile = curveAtPlug(ev, *src, error, note, depth);
    if (!profile) return std::nullopt;
    CreatorAttrs a(ev, node);
    geom::RevolveParams p;
    p.axis = a.vec3("ax", {"axx", "axy", "axz"}, kDefaultAxis);
    p.pivot = a.vec3("p", {"px", "py", "pz"}, glm::dvec3(0.0));
    p.startSweep = a.number("ssw", 0.0);
    p.endSweep = a.number("esw", kTwoPi);
    p.degree = a.integer("d", 3);
    p.sections = a.integer("s", 8);
    p.useTolerance = a.integer("ut", 0) != 0;
    p.tolerance = a.number("tol", 0.01);
    p.autoCorrectNormal = a.integer("acn", 0) != 0;
    const std::string& name = g.node(node).name;
    if (a.integer("cpa", 0) != 0) {
        addNote(note, "revolve " + name + ": computePivotAndAxis is not modelled; its axis and pivot attributes are used");
    }
    if (a.integer("br", 0) != 0) addNote(note, "revolve " + name + ": bridge is not modelled");
    return geom::revolveCurve(*profile, p, error);
}

// extrude: a profile moved by a distance, or along a path curve (flat or tube).
std::optional<geom::NurbsSurface> evaluateExtrude(Evaluator& ev, NodeId node, std::string* error, std::string* note,
                                                  int depth) {
    const Graph& g = ev.graph();
    const auto src = g.source(node, "profile");
    if (!src) return failWith(error, "no profile curve");
    auto profile = curveAtPlug(ev, *src, error, note, depth);
    if (!profile) return std::nullopt;
    CreatorAttrs a(ev, node);
    geom::ExtrudeParams p;
    const int type = a.integer("et", 2);
    if (type < 0 || type > 2) return failWith(error, "extrudeType " + std::to_string(type) + " is not distance, flat or tube");
    p.type = type == 0 ? geom::ExtrudeType::Distance : type == 1 ? geom::ExtrudeType::Flat : geom::ExtrudeType::Tube;
    p.direction = a.vec3("d", {"dx", "dy", "dz"}, glm::dvec3(0, 1, 0));
    p.length = a.number("l", 1.0);
    p.degreeAlongLength = a.integer("dl", 1);
    p.fixedPath = a.integer("fpt", 0) != 0;
    std::optional<geom::NurbsCurve> path;
    if (p.type != geom::ExtrudeType::Distance) {
        const auto along = g.source(node, "path");
        if (!along) return failWith(error, "no path curve");
        path = curveAtPlug(ev, *along, error, note, depth);
        if (!path) return std::nullopt;
    }
    const std::string& name = g.node(node).name;
    std::string ignored;
    if (a.number("ro", 0.0) != 0.0) ignored += ", rotation";
    if (a.number("sc", 1.0) != 1.0) ignored += ", scale";
    if (a.integer("upn", 0) != 0) ignored += ", useProfileNormal";
    if (a.integer("ucp", 0) != 0) ignored += ", useComponentPivot";
    if (!ignored.empty()) addNote(note, "extrude " + name + ": " + ignored.substr(2) + " not applied");
    if (p.type == geom::ExtrudeType::Tube) addNote(note, "extrude " + name + ": the tube is approximated by lofted sections");
    return geom::extrudeCurve(*profile, path ? &*path : nullptr, p, error);
}

std::optional<geom::NurbsSurface> evaluateLoft(Evaluator& ev, NodeId node, std::string* error, std::string* note,
                                               int depth) {
    const Graph& g = ev.graph();
    std::vector<std::pair<int, Plug>> inputs;
    for (const Connection* c : g.inputs(node)) {
        if (startsWith(c->dst.path, "inputCurve[")) inputs.emplace_back(plugIndex(c->dst.path), c->src);
    }
    std::sort(inputs.begin(), inputs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (inputs.size() < 2) return failWith(error, std::to_string(inputs.size()) + " input curves connected, a loft needs 2");
    CreatorAttrs a(ev, node);
    geom::LoftParams p;
    p.uniform = a.integer("u", 0) != 0;
    p.close = a.integer("c", 0) != 0;
    p.degree = a.integer("d", 3);
    p.reverseSurfaceNormals = a.integer("rsn", 0) != 0;
    p.autoReverse = a.integer("ar", 1) != 0;
    p.sectionSpans = a.integer("ss", 1);
    std::vector<geom::NurbsCurve> curves;
    bool cusp = false;
    for (const auto& [index, plug] : inputs) {
        std::string err;
        auto c = curveAtPlug(ev, plug, &err, note, depth);
        if (!c) return failWith(error, "inputCurve[" + std::to_string(index) + "]: " + err);
        curves.push_back(std::move(*c));
        const std::string k = "[" + std::to_string(index) + "]";
        p.reverse.push_back(ev.getBool(node, "reverse" + k, false));
        cusp = cusp || ev.getBool(node, "createCusp" + k, false);
    }
    if (cusp) addNote(note, "loft " + g.node(node).name + ": createCusp is not modelled");
    return geom::loftCurves(curves, p, error);
}

std::optional<geom::NurbsSurface> surfaceAtPlug(Evaluator& ev, const Plug& src, std::string* error, std::string* note,
                                                int depth);

bool isSurfaceHistory(std::string_view type) {
    return type == "revolve" || type == "loft" || type == "extrude" || type == "detachSurface" ||
           type == "insertKnotSurface" || type == "rebuildSurface";
}

// The input surface of a surface-editing node (`is`), through its own history.
std::optional<geom::NurbsSurface> inputSurface(Evaluator& ev, NodeId node, std::string* error, std::string* note, int depth) {
    if (depth >= kMaxShapeChain) return failWith(error, "the surface history is deeper than " + std::to_string(kMaxShapeChain));
    const std::optional<Plug> src = ev.graph().source(node, "is");
    if (!src) return failWith(error, "no input surface is connected");
    std::string err;
    std::optional<geom::NurbsSurface> in = surfaceAtPlug(ev, *src, &err, note, depth + 1);
    if (!in) return failWith(error, "inputSurface: " + err);
    return in;
}

// The numbers of multi attribute `name` in index order.
std::vector<double> multiNumbers(const Graph& g, NodeId node, std::string_view name) {
    std::vector<double> out;
    if (const AttrData* a = g.findAttr(node, name))
        detail::forEachNumeric(*a, [&](uint64_t, const double* v, int) { out.push_back(v[0]); });
    return out;
}

// insertKnotSurface: its parameters inserted numberOfKnots times each.
std::optional<geom::NurbsSurface> evaluateInsertKnots(Evaluator& ev, NodeId node, std::string* error, std::string* note,
                                                      int depth) {
    std::optional<geom::NurbsSurface> in = inputSurface(ev, node, error, note, depth);
    if (!in) return std::nullopt;
    CreatorAttrs a(ev, node);
    if (a.integer("ib", 0) != 0) return failWith(error, "insertBetween is not evaluated");
    if (a.integer("add", 1) == 0) return failWith(error, "setting the knots' multiplicity (addKnots off) is not evaluated");
    const std::vector<double> params = multiNumbers(ev.graph(), node, "parameter");
    const std::vector<double> counts = multiNumbers(ev.graph(), node, "numberOfKnots");
    std::vector<std::pair<double, int>> inserts;
    for (size_t i = 0; i < params.size(); ++i) {
        const double n = i < counts.size() ? counts[i] : 1.0;
        inserts.emplace_back(params[i], std::isfinite(n) ? int(std::clamp(n, 0.0, 64.0)) : 0);
    }
    return geom::insertSurfaceKnots(*in, a.integer("d", 1) != 0, inserts, error);
}

// rebuildSurface: the uniform rebuild (or the same CVs over a new range with keepControlPoints).
std::optional<geom::NurbsSurface> evaluateRebuild(Evaluator& ev, NodeId node, std::string* error, std::string* note, int depth) {
    std::optional<geom::NurbsSurface> in = inputSurface(ev, node, error, note, depth);
    if (!in) return std::nullopt;
    CreatorAttrs a(ev, node);
    if (const int type = a.integer("rt", 0); type != 0)
        return failWith(error, "rebuildType " + std::to_string(type) + " is not evaluated (only the uniform rebuild is)");
    geom::RebuildParams p;
    const int direction = a.integer("dir", 2);
    p.rebuildU = direction == 0 || direction == 2;
    p.rebuildV = direction == 1 || direction == 2;
    p.spansU = a.integer("su", 4);
    p.spansV = a.integer("sv", 4);
    p.degreeU = a.integer("du", 3);
    p.degreeV = a.integer("dv", 3);
    const int range = a.integer("kr", 1);
    p.range = range == 0 ? geom::RebuildRange::ZeroToOne : range == 2 ? geom::RebuildRange::ZeroToSpans : geom::RebuildRange::Original;
    p.keepControlPoints = a.integer("kc", 0) != 0;
    if (a.integer("end", 1) != 1) addNote(note, "rebuildSurface " + ev.graph().node(node).name + ": end knots are made multiple");
    addNote(note, "rebuildSurface " + ev.graph().node(node).name + ": fitted by interpolation; its CVs may differ from Maya's");
    return geom::rebuildSurface(*in, p, error);
}

// detachSurface: piece `os[i]` of its input cut at its parameters (keep[i] off: no piece).
std::optional<geom::NurbsSurface> evaluateDetach(Evaluator& ev, NodeId node, const std::string& path, std::string* error,
                                                 std::string* note, int depth) {
    std::optional<geom::NurbsSurface> in = inputSurface(ev, node, error, note, depth);
    if (!in) return std::nullopt;
    CreatorAttrs a(ev, node);
    const bool directionU = a.integer("d", 1) != 0;
    std::vector<double> params = multiNumbers(ev.graph(), node, "parameter");
    std::string err;
    const int piece = plugIndex(path);
    if (!ev.getBool(node, "keep[" + std::to_string(piece) + "]", true))
        return failWith(error, "piece " + std::to_string(piece) + " is not kept");
    std::optional<std::vector<geom::NurbsSurface>> pieces = geom::detachSurface(*in, directionU, std::move(params), &err);
    if (!pieces) return failWith(error, err);
    if (piece < 0 || size_t(piece) >= pieces->size())
        return failWith(error, "the cut makes " + std::to_string(pieces->size()) + " pieces, not a piece " + std::to_string(piece));
    return std::move((*pieces)[size_t(piece)]);
}

// The surface a plug carries: a nurbsSurface shape's `local` (object space) or `worldSpace[i]` (world
// space), or the output of a creator, revolve or loft node.
std::optional<geom::NurbsSurface> surfaceAtPlug(Evaluator& ev, const Plug& src, std::string* error, std::string* note,
                                                int depth) {
    const Graph& g = ev.graph();
    const Node& n = g.node(src.node);
    std::string err;
    if (n.type == "nurbsSurface") {
        auto s = surfaceOfShape(ev, src.node, error, note, depth + 1);
        if (!s || !startsWith(src.path, "worldSpace")) return s;
        const int instance = plugIndex(src.path);
        const auto m = instanceMatrix(ev, src.node, instance);
        if (!m) return failWith(error, n.name + " has no DAG instance " + std::to_string(instance));
        auto world = geom::transformSurface(*s, *m, &err);
        if (!world) return failWith(error, n.name + " in world space: " + err);
        return world;
    }
    std::optional<geom::NurbsSurface> s;
    if (isSurfaceCreator(n.type)) s = evaluateCreator(ev, src.node, src.path, &err);
    else if (n.type == "revolve") s = evaluateRevolve(ev, src.node, &err, note, depth);
    else if (n.type == "loft") s = evaluateLoft(ev, src.node, &err, note, depth);
    else if (n.type == "extrude") s = evaluateExtrude(ev, src.node, &err, note, depth);
    else if (n.type == "detachSurface") s = evaluateDetach(ev, src.node, src.path, &err, note, depth);
    else if (n.type == "insertKnotSurface") s = evaluateInsertKnots(ev, src.node, &err, note, depth);
    else if (n.type == "rebuildSurface") s = evaluateRebuild(ev, src.node, &err, note, depth);
    else return failWith(error, "history node " + n.type + " (" + n.name + ") is not evaluated");
    if (!s) return failWith(error, n.type + " (" + n.name + "): " + err);
    return s;
}

// A shape's relative control-point tweaks (`tweak` on, `controlPoints[k]` offsets in object space
// for CV k: k / cvCountV, k % cvCountV on a surface) added to the CVs its history makes. False when
// there are none.
bool offsetControlPoints(Evaluator& ev, NodeId shape, std::vector<glm::dvec4>& cvs, std::string* note) {
    if (!ev.getBool(shape, "tw", false)) return false;
    const std::map<uint32_t, glm::dvec3> tweaks = detail::vectorElements(ev, shape, "controlPoints", 3);
    if (tweaks.empty()) return false;
    size_t outside = 0;
    for (const auto& [k, offset] : tweaks) {
        if (k >= cvs.size()) {
            ++outside;
            continue;
        }
        glm::dvec4& c = cvs[k];
        c = glm::dvec4((glm::dvec3(c) / c.w + offset) * c.w, c.w);
    }
    if (outside > 0)
        addNote(note, ev.graph().node(shape).name + ": " + std::to_string(outside) +
                          " control-point tweaks past the last CV are not applied");
    return true;
}

std::optional<geom::NurbsSurface> withControlPointTweaks(Evaluator& ev, NodeId shape, geom::NurbsSurface s,
                                                         std::string* note) {
    std::vector<glm::dvec4> cvs = s.cvs();
    if (!offsetControlPoints(ev, shape, cvs, note)) return s;
    std::string err;
    std::optional<geom::NurbsSurface> t = geom::NurbsSurface::create(s.degreeU(), s.degreeV(), s.formU(), s.formV(), s.knotsU(),
                                                                     s.knotsV(), s.cvCountU(), s.cvCountV(), std::move(cvs),
                                                                     s.rational(), &err);
    if (!t) {
        addNote(note, ev.graph().node(shape).name + ": its control-point tweaks are not applied (" + err + ")");
        return s;
    }
    return t;
}

std::optional<geom::NurbsCurve> withControlPointTweaks(Evaluator& ev, NodeId shape, geom::NurbsCurve c, std::string* note) {
    std::vector<glm::dvec4> cvs = c.cvs();
    if (!offsetControlPoints(ev, shape, cvs, note)) return c;
    std::string err;
    std::optional<geom::NurbsCurve> t = geom::NurbsCurve::create(c.degree(), c.form(), c.knots(), std::move(cvs), c.rational(), &err);
    if (!t) {
        addNote(note, ev.graph().node(shape).name + ": its control-point tweaks are not applied (" + err + ")");
        return c;
    }
    return t;
}

std::optional<geom::NurbsSurface> surfaceOfShape(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                 std::string* note, int depth) {
    const Graph& g = ev.graph();
    const Node& n = g.node(shape);
    const NurbsSurfaceData* cached = cachedSurface(g, shape);
    auto fromCache = [&]() -> std::optional<geom::NurbsSurface> {
        std::string err;
        auto s = decodeNurbsSurface(*cached, &err);
        if (!s) return failWith(skipReason, n.name + ": " + err);
        if (cached->trimmed && note) {
            *note += (note->empty() ? "" : "; ") + std::string("trim curves of ") + n.name + " are not applied";
        }
        return s;
    };

    if (auto src = g.source(shape, "cr")) {
        const Node& c = g.node(src->node);
        if (isSurfaceCreator(c.type)) {
            std::string err;
            auto s = evaluateCreator(ev, src->node, src->path, &err);
            if (!s) return failWith(skipReason, n.name + ": " + c.type + " (" + c.name + "): " + err);
            return withControlPointTweaks(ev, shape, std::move(*s), note);
        }
        if (isSurfaceHistory(c.type) && depth < kMaxShapeChain) {
            std::string err, historyNote;
            auto s = surfaceAtPlug(ev, *src, &err, &historyNote, depth);
            if (s) {
                addNote(note, historyNote);
                return withControlPointTweaks(ev, shape, std::move(*s), note);
            }
            if (cached) {
                addNote(note, err + "; using the cached surface of " + n.name);
                return fromCache();
            }
            return failWith(skipReason, n.name + ": " + err);
        }
        if (c.type == "nurbsSurface" && depth < kMaxShapeChain && src->node != shape) {
            return surfaceOfShape(ev, src->node, skipReason, note, depth + 1);
        }
        const std::string history = "history node " + c.type + " (" + c.name + ") is not evaluated";
        if (cached) {
            if (note) *note += (note->empty() ? "" : "; ") + history + "; using the cached surface of " + n.name;
            return fromCache();
        }
        return failWith(skipReason, history);
    }
    if (cached) return fromCache();
    return failWith(skipReason, n.name + ": no cached surface data and no create connection");
}

std::optional<geom::NurbsCurve> curveOfShape(Evaluator& ev, NodeId shape, std::string* skipReason, std::string* note,
                                             int depth) {
    const Graph& g = ev.graph();
    const Node& n = g.node(shape);
    const NurbsCurveData* cached = cachedCurve(g, shape);
    auto fromCache = [&]() -> std::optional<geom::NurbsCurve> {
        std::string err;
        auto c = decodeNurbsCurve(*cached, &err);
        if (!c) return failWith(skipReason, n.name + ": " + err);
        return c;
    };
    if (auto src = g.source(shape, "cr")) {
        const Node& c = g.node(src->node);
        if (c.type == "makeNurbCircle") {
            std::string err;
            auto curve = circleOfCreator(ev, src->node, &err);
            if (!curve) return failWith(skipReason, n.name + ": makeNurbCircle (" + c.name + "): " + err);
            return withControlPointTweaks(ev, shape, std::move(*curve), note);
        }
        if (c.type == "nurbsCurve" && depth < kMaxShapeChain && src->node != shape) {
            return curveOfShape(ev, src->node, skipReason, note, depth + 1);
        }
        const std::string history = "history node " + c.type + " (" + c.name + ") is not evaluated";
        if (cached) {
            if (note) *note += (note->empty() ? "" : "; ") + history + "; using the cached curve of " + n.name;
            return fromCache();
        }
        return failWith(skipReason, history);
    }
    if (cached) return fromCache();
    return failWith(skipReason, n.name + ": no cached curve data and no create connection");
}

}  // namespace

std::optional<geom::NurbsSurface> decodeNurbsSurface(const NurbsSurfaceData& d, std::string* error,
                                                     RationalCvLayout layout) {
    std::string err;
    const int nu = checkDirection("U", d.degreeU, d.formU, d.knotsU, d.cvCountU, &err);
    const int nv = nu ? checkDirection("V", d.degreeV, d.formV, d.knotsV, d.cvCountV, &err) : 0;
    if (!nu || !nv) return failWith(error, "nurbsSurface data: " + err);
    const size_t stride = d.rational ? 4 : 3;
    const size_t count = size_t(nu) * size_t(nv);
    if (d.cvs.size() != count * stride) {
        return failWith(error, "nurbsSurface data: " + std::to_string(d.cvs.size()) + " CV numbers, expected " +
                                   std::to_string(nu) + " x " + std::to_string(nv) + " CVs x " +
                                   std::to_string(stride) + " = " + std::to_string(count * stride));
    }
    std::vector<glm::dvec4> cvs(count);
    for (size_t k = 0; k < count; ++k) cvs[k] = homogeneous(&d.cvs[k * stride], 3, d.rational, layout);
    const auto formU = geom::NurbsForm(d.formU), formV = geom::NurbsForm(d.formV);
    auto s = geom::NurbsSurface::create(d.degreeU, d.degreeV, formU, formV,
                                        geom::textbookKnotsFromMaya(d.knotsU, d.degreeU, formU),
                                        geom::textbookKnotsFromMaya(d.knotsV, d.degreeV, formV), nu, nv,
                                        std::move(cvs), d.rational, &err);
    if (!s) return failWith(error, "nurbsSurface data: " + err);
    return s;
}

std::optional<geom::NurbsCurve> decodeNurbsCurve(const NurbsCurveData& d, std::string* error,
                                                 RationalCvLayout layout) {
    std::string err;
    if (d.dimension != 2 && d.dimension != 3) {
        return failWith(error, "nurbsCurve data: dimension " + std::to_string(d.dimension) + " is not 2 or 3");
    }
    const int n = checkDirection("", d.degree, d.form, d.knots, 0, &err);
    if (!n) return failWith(error, "nurbsCurve data: " + err);
    const size_t stride = size_t(d.dimension) + (d.rational ? 1 : 0);
    if (d.cvs.size() != size_t(n) * stride) {
        return failWith(error, "nurbsCurve data: " + std::to_string(d.cvs.size()) + " CV numbers, expected " +
                                   std::to_string(n) + " CVs x " + std::to_string(stride) + " = " +
                                   std::to_string(size_t(n) * stride));
    }
    std::vector<glm::dvec4> cvs(static_cast<size_t>(n));
    for (size_t k = 0; k < cvs.size(); ++k) cvs[k] = homogeneous(&d.cvs[k * stride], d.dimension, d.rational, layout);
    const auto form = geom::NurbsForm(d.form);
    auto c = geom::NurbsCurve::create(d.degree, form, geom::textbookKnotsFromMaya(d.knots, d.degree, form),
                                      std::move(cvs), d.rational, &err);
    if (!c) return failWith(error, "nurbsCurve data: " + err);
    return c;
}

std::optional<geom::NurbsSurface> evaluateNurbsSurface(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                       std::string* note) {
    return surfaceOfShape(ev, shape, skipReason, note, 0);
}

std::optional<geom::NurbsCurve> evaluateNurbsCurve(Evaluator& ev, NodeId shape, std::string* skipReason,
                                                   std::string* note) {
    return curveOfShape(ev, shape, skipReason, note, 0);
}

std::optional<geom::Mesh> evaluateNurbsTessellate(Evaluator& ev, NodeId tessellateNode, std::string* reason,
                                                  std::vector<std::string>* notes) {
    const Graph& g = ev.graph();
    const std::string& name = g.node(tessellateNode).name;
    const auto src = g.source(tessellateNode, "inputSurface");
    if (!src) return failWith(reason, name + ": no input surface");
    std::string err, note;
    auto surface = surfaceAtPlug(ev, *src, &err, &note, 0);
    if (!surface) return failWith(reason, name + ": " + err);
    CreatorAttrs a(ev, tessellateNode);
    geom::TessellateParams p;
    p.format = a.integer("f", 1);
    p.polygonType = a.integer("pt", 0);
    p.polygonCount = a.integer("pc", 200);
    p.uType = a.integer("ut", 3);
    p.vType = a.integer("vt", 3);
    p.uNumber = a.integer("un", 3);
    p.vNumber = a.integer("vn", 3);
    p.useChordHeight = a.integer("uch", 0) != 0;
    p.chordHeight = a.number("cht", 0.1);
    p.useChordHeightRatio = a.integer("ucr", 1) != 0;
    p.chordHeightRatio = a.number("chr", 0.983);
    p.delta = a.number("d", 0.1);
    p.matchNormalDir = a.integer("mnd", 0) != 0;
    std::vector<std::string> tessNotes;
    if (a.integer("eta", 1) == 0) {
        tessNotes.push_back("explicitTessellationAttributes off (curvatureTolerance, division factors) is not modelled; "
                            "the explicit attributes are used");
    }
    if (a.integer("es", 0) != 0) tessNotes.push_back("edgeSwap is not modelled");
    auto mesh = geom::tessellateSurface(*surface, p, &err, &tessNotes);
    if (!mesh) return failWith(reason, name + ": " + err);
    if (notes) {
        if (!note.empty()) notes->push_back(note);
        for (const std::string& t : tessNotes) notes->push_back(name + ": " + t);
    }
    return mesh;
}

}  // namespace pushpin::scene
