// core/scene/nurbs_eval.cpp: nurbsSurface / nurbsCurve shapes → geom::NurbsSurface / geom::NurbsCurve.
#include "core/scene/nurbs_eval.h"

#include "core/geom/nurbs_primitives.h"

#include <cctype>
#include <cmath>
#include <initializer_list>
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
            return s;
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
            CreatorAttrs a(ev, src->node);
            geom::NurbsCircleParams p;
            p.radius = a.number("r", 1.0);
            p.sweep = a.number("sw", kTwoPi);
            p.degree = a.integer("d", 3);
            p.sections = a.integer("s", 8);
            p.normal = a.vec3("nr", {"nrx", "nry", "nrz"}, glm::dvec3(0, 0, 1));
            p.center = a.vec3("c", {"cx", "cy", "cz"}, glm::dvec3(0.0));
            std::string err;
            auto curve = geom::makeNurbCircle(p, &err);
            if (!curve) return failWith(skipReason, n.name + ": makeNurbCircle (" + c.name + "): " + err);
            return curve;
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

}  // namespace pushpin::scene
