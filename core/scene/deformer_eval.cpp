// core/scene/deformer_eval.cpp: tweak, cluster, nonLinear and skinCluster deformation of mesh points.
//
// Every deformer here computes a deformed position d(p) for each point p of its set and blends:
// p' = p + envelope · weight · (d(p) − p), where the weight is the point's weightList entry (1 for
// tweak). Points are computed in double precision into a scratch array and written back only when
// every one of them is finite, so a failing deformer leaves the mesh untouched.
#include "core/scene/deformer_eval.h"

#include "core/geom/finite.h"
#include "core/scene/detail/multi_elements.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

namespace pushpin::scene {

namespace {

using detail::elementIndexAfter;
using detail::forEachNumeric;
using detail::kMaxElements;
using detail::nodeLabel;
using detail::vectorElements;

// Elements beyond this index are ignored: a hostile `.wl[2000000000]` must not allocate.
// Longest chain of history walked upstream to find the geometry's world matrix.
constexpr int kMaxChain = 256;
// Influences of one skinCluster beyond this index are refused (real rigs have a few hundred).
constexpr uint32_t kMaxInfluences = 1u << 16;

// An invertible, finite matrix: its inverse is finite too.
std::optional<glm::dmat4> inverseOf(const glm::dmat4& m) {
    const double det = glm::determinant(m);
    if (!std::isfinite(det) || std::abs(det) < 1e-300) return std::nullopt;
    const glm::dmat4 inv = glm::inverse(m);
    if (!geom::isFinite(inv)) return std::nullopt;
    return inv;
}

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

bool isMember(const std::vector<bool>* members, size_t i) { return !members || (i < members->size() && (*members)[i]); }

// ------------------------------------------------------------------------ reading the graph
// The canonical key of `name[index].child` on `node`, as the Graph stores multi elements
// ("weightList[0].weights"; short names stay as written on nodes outside the schema).
std::string elementKey(const Graph& g, NodeId node, std::string_view name, uint32_t index, std::string_view child) {
    std::vector<PlugSegment> segs{{std::string(name), int64_t(index), int64_t(index)}, {std::string(child), -1, -1}};
    return g.canonicalPath(node, segs);
}

// Whether any connection drives an element of the multi attribute stored under `key`.
bool anyElementConnected(const Graph& g, NodeId node, std::string_view key) {
    for (const Connection* c : g.inputs(node))
        if (c->dst.path.size() > key.size() && c->dst.path.compare(0, key.size(), key) == 0 &&
            (c->dst.path[key.size()] == '[' || c->dst.path[key.size()] == '.'))
            return true;
    return false;
}

// The first incoming connection into any spelling of a plug ("ip[0].ig", "input[0].inputGeometry"):
// nodes outside the schema keep the names as the file wrote them.
std::optional<Plug> sourceOf(const Graph& g, NodeId node, std::initializer_list<std::string> spellings) {
    for (const std::string& s : spellings)
        if (std::optional<Plug> p = g.source(node, s)) return p;
    return std::nullopt;
}

// A matrix plug's value: `present` false when nothing sets or drives it (Maya's default, identity),
// `error` set when it is driven by something that is not evaluated or holds a bad value.
struct MatrixValue {
    bool present = false;
    glm::dmat4 m{1.0};
    std::string error;
};

// The DAG path of instance `index` of a DAG node (the first path when there are fewer).
std::vector<NodeId> instancePath(const Graph& g, NodeId node, int64_t index) {
    if (index <= 0) return g.firstDagPath(node);
    DagPathBudget budget;
    std::vector<std::vector<NodeId>> paths = g.dagPaths(node, &budget);
    if (size_t(index) < paths.size()) return std::move(paths[size_t(index)]);
    return g.firstDagPath(node);
}

// The matrix a source plug carries at this frame. DAG nodes compute theirs from the transform
// stack (worldMatrix, worldInverseMatrix, parentMatrix, parentInverseMatrix, matrix,
// inverseMatrix, xformMatrix); any other source gives its stored value.
MatrixValue matrixFromSource(Evaluator& ev, const Plug& src) {
    const Graph& g = ev.graph();
    MatrixValue out;
    out.present = true;
    if (src.node >= g.size()) {
        out.error = "a matrix comes from a node that does not exist";
        return out;
    }
    const Node& n = g.node(src.node);
    const std::optional<std::vector<PlugSegment>> segs = parsePlugPath(src.path);
    if (segs && segs->size() == 1 && n.isDag()) {
        const std::string& name = segs->front().name;
        const int64_t index = segs->front().indexed() ? segs->front().first : 0;
        auto parentWorld = [&] {
            std::vector<NodeId> path = instancePath(g, src.node, index);
            if (!path.empty()) path.pop_back();
            return path.empty() ? glm::dmat4(1.0) : ev.worldMatrix(path);
        };
        auto is = [&](std::string_view longName, std::string_view shortName) {
            return name == longName || name == shortName;
        };
        const bool inverse = is("worldInverseMatrix", "wim") || is("parentInverseMatrix", "pim") || is("inverseMatrix", "im");
        std::optional<glm::dmat4> m;
        if (is("worldMatrix", "wm") || is("worldInverseMatrix", "wim")) m = ev.worldMatrix(instancePath(g, src.node, index));
        else if (is("parentMatrix", "pm") || is("parentInverseMatrix", "pim")) m = parentWorld();
        else if (is("matrix", "m") || is("xformMatrix", "xm") || is("inverseMatrix", "im")) m = ev.localMatrix(src.node);
        if (m) {
            if (inverse) m = inverseOf(*m);
            if (!m || !geom::isFinite(*m)) out.error = "the matrix of " + n.name + " is not finite or not invertible";
            else out.m = *m;
            return out;
        }
    }
    std::vector<double> v;
    if (!ev.numbers(src.node, src.path, v) || v.size() != 16) {
        out.error = "its matrix comes from " + nodeLabel(n) + "." + src.path + ", which is not evaluated";
        return out;
    }
    // Maya's matrix is row-major for row vectors; read column-major it is the column-vector matrix.
    out.m = glm::make_mat4(v.data());
    if (!geom::isFinite(out.m)) out.error = "the matrix from " + n.name + "." + src.path + " is not finite";
    return out;
}

// The matrix `node.<spelling>` carries: through its incoming connection, else its stored value.
MatrixValue readMatrix(Evaluator& ev, NodeId node, std::initializer_list<std::string> spellings) {
    const Graph& g = ev.graph();
    if (std::optional<Plug> src = sourceOf(g, node, spellings)) return matrixFromSource(ev, *src);
    MatrixValue out;
    std::vector<double> v;
    for (const std::string& s : spellings) {
        if (!ev.numbers(node, s, v) || v.size() != 16) continue;
        out.present = true;
        out.m = glm::make_mat4(v.data());
        if (!geom::isFinite(out.m)) out.error = "its " + s + " matrix is not finite";
        return out;
    }
    return out;
}

// The world matrix the geometry arriving at `deformer.input[index]` carries: the world matrix of
// the shape whose worldMesh starts the chain of history, identity when the chain starts at an
// outMesh or a creator node.
glm::dmat4 upstreamGeometryMatrix(Evaluator& ev, NodeId deformer, uint32_t index) {
    const Graph& g = ev.graph();
    const std::string k = std::to_string(index);
    std::optional<Plug> src = sourceOf(g, deformer, {"ip[" + k + "].ig", "input[" + k + "].inputGeometry"});
    for (int hop = 0; src && hop < kMaxChain; ++hop) {
        if (src->node >= g.size()) break;
        const Node& n = g.node(src->node);
        if (n.type == "mesh") {
            const std::optional<std::vector<PlugSegment>> segs = parsePlugPath(src->path);
            if (segs && !segs->empty() && (segs->front().name == "worldMesh" || segs->front().name == "w"))
                return ev.worldMatrix(instancePath(g, src->node, segs->front().indexed() ? segs->front().first : 0));
            return glm::dmat4(1.0);
        }
        // Another deformer passes input[j] to outputGeometry[j]; other history nodes have one input.
        std::string j = "0";
        if (const std::optional<std::vector<PlugSegment>> segs = parsePlugPath(src->path);
            segs && !segs->empty() && segs->front().indexed())
            j = std::to_string(segs->front().first);
        src = sourceOf(g, src->node, {"ip[" + j + "].ig", "input[" + j + "].inputGeometry", "inputGeometry", "ig",
                                      "inputPolymesh", "ip", "inMesh", "i"});
    }
    return glm::dmat4(1.0);
}

// Per-point weights weightList[index].weights[i] for `count` points, `fallback` where unset.
std::vector<double> pointWeights(Evaluator& ev, NodeId node, uint32_t index, size_t count, double fallback,
                                 std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    std::vector<double> w(count, fallback);
    const std::string key = elementKey(g, node, "wl", index, "w");
    if (const AttrData* a = g.findAttr(node, key))
        forEachNumeric(*a, [&](uint32_t i, const double* v, int) {
            if (i < count) w[i] = v[0];
        });
    if (anyElementConnected(g, node, key))
        notes.push_back(nodeLabel(g.node(node)) + ": connected weights are not evaluated; the stored weights are used");
    return w;
}

// The envelope, or a reason when it is not finite.
std::optional<double> envelopeOf(Evaluator& ev, NodeId node, std::string& reason) {
    const double en = ev.getDouble(node, "en", 1.0);
    if (!std::isfinite(en)) {
        reason = nodeLabel(ev.graph().node(node)) + ": envelope is not finite";
        return std::nullopt;
    }
    return en;
}

// Writes the deformed points back when all are finite (as floats too); else gives a reason.
std::string commitPoints(const Node& node, const std::vector<glm::dvec3>& points, geom::Mesh& mesh,
                         std::vector<std::string>& notes) {
    constexpr double kFloatMax = double(std::numeric_limits<float>::max());
    size_t bad = 0;
    for (const glm::dvec3& p : points)
        if (!geom::isFinite(p) || std::abs(p.x) > kFloatMax || std::abs(p.y) > kFloatMax || std::abs(p.z) > kFloatMax) ++bad;
    if (bad)
        return nodeLabel(node) + ": the deformation gives " + std::to_string(bad) + " non-finite point" +
               (bad == 1 ? "" : "s");
    bool moved = false;
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::vec3 p(points[i]);
        moved = moved || p != mesh.points[i];
        mesh.points[i] = p;
    }
    // Stored normals belong to the undeformed shape; they are recomputed from the moved points.
    if (moved && std::any_of(mesh.normals.begin(), mesh.normals.end(), [](const glm::vec3& n) { return n != glm::vec3(0.0f); })) {
        std::fill(mesh.normals.begin(), mesh.normals.end(), glm::vec3(0.0f));
        notes.push_back(nodeLabel(node) + ": the mesh's stored normals are recomputed after deformation");
    }
    return {};
}

std::vector<glm::dvec3> pointsOf(const geom::Mesh& mesh) {
    std::vector<glm::dvec3> out(mesh.points.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = glm::dvec3(mesh.points[i]);
    return out;
}

// ------------------------------------------------------------------------------------- tweak
std::string applyTweak(Evaluator& ev, NodeId n, uint32_t index, const std::vector<bool>* members, geom::Mesh& mesh,
                       std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    const Node& node = g.node(n);
    std::string reason;
    const std::optional<double> en = envelopeOf(ev, n, reason);
    if (!en) return reason;
    const bool relative = ev.getBool(n, "rtw", true);
    // Mesh tweaks live in vlist (float3) in older files and plist (double3) in newer ones.
    std::map<uint32_t, glm::dvec3> offsets = vectorElements(ev, n, elementKey(g, n, "pl", index, "cp"), 3);
    for (const auto& [i, t] : vectorElements(ev, n, elementKey(g, n, "vl", index, "vt"), 3)) offsets[i] += t;

    std::vector<glm::dvec3> points = pointsOf(mesh);
    size_t outside = 0, nonFinite = 0;
    for (const auto& [i, t] : offsets) {
        if (i >= points.size()) {
            ++outside;
            continue;
        }
        if (!geom::isFinite(t)) {
            ++nonFinite;
            continue;
        }
        if (!isMember(members, i)) continue;
        const glm::dvec3 target = relative ? points[i] + t : t;
        points[i] += *en * (target - points[i]);
    }
    if (nonFinite)
        return nodeLabel(node) + ": " + std::to_string(nonFinite) + " tweak offsets are not finite";
    if (outside)
        notes.push_back(nodeLabel(node) + ": " + std::to_string(outside) + " tweaks past the last of " +
                        std::to_string(points.size()) + " points are ignored");
    return commitPoints(node, points, mesh, notes);
}

// ----------------------------------------------------------------------------------- cluster
std::string applyCluster(Evaluator& ev, NodeId n, uint32_t index, const std::vector<bool>* members, geom::Mesh& mesh,
                         std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    const Node& node = g.node(n);
    const std::string who = nodeLabel(node) + ": ";
    std::string reason;
    const std::optional<double> en = envelopeOf(ev, n, reason);
    if (!en) return reason;
    const std::string k = std::to_string(index);
    const MatrixValue gm = readMatrix(ev, n, {"gm[" + k + "]", "geomMatrix[" + k + "]"});
    if (!gm.error.empty()) return who + "geomMatrix: " + gm.error;
    const std::optional<glm::dmat4> objectFromWorld = inverseOf(gm.m);
    if (!objectFromWorld) return who + "geomMatrix is not invertible";

    // The world-space motion of the cluster (column vectors).
    glm::dmat4 motion(1.0);
    const bool relative = ev.getBool(n, "rel", false);
    const std::optional<Plug> handle = sourceOf(g, n, {"ma", "matrix"});
    const bool handleIsDag = handle && handle->node < g.size() && g.node(handle->node).isDag();
    if (relative && handleIsDag) {
        // Relative: only the handle's own transform counts, taken in its parent's space.
        std::vector<NodeId> path = g.firstDagPath(handle->node);
        if (!path.empty()) path.pop_back();
        const glm::dmat4 parentWorld = path.empty() ? glm::dmat4(1.0) : ev.worldMatrix(path);
        const std::optional<glm::dmat4> parentInverse = inverseOf(parentWorld);
        if (!parentInverse) return who + "the handle's parent matrix is not invertible";
        motion = parentWorld * ev.localMatrix(handle->node) * *parentInverse;
    } else if (relative) {
        // The bundled transforms the handle computes (row vectors: pre · weighted · post).
        const MatrixValue pre = readMatrix(ev, n, {"x.pre", "clusterXforms.preMatrix"});
        const MatrixValue wt = readMatrix(ev, n, {"x.wt", "clusterXforms.weightedMatrix"});
        const MatrixValue post = readMatrix(ev, n, {"x.post", "clusterXforms.postMatrix"});
        for (const MatrixValue* m : {&pre, &wt, &post})
            if (!m->error.empty()) return who + m->error;
        motion = post.m * wt.m * pre.m;
    } else {
        const MatrixValue ma = readMatrix(ev, n, {"ma", "matrix"});
        if (!ma.error.empty()) return who + "matrix: " + ma.error;
        const MatrixValue pm = readMatrix(ev, n, {"pm", "bindPreMatrix"});
        if (!pm.error.empty()) return who + "bindPreMatrix: " + pm.error;
        motion = ma.m * pm.m;
    }
    if (ev.getInt(n, "ai", 0) != 0)
        notes.push_back(who + "angleInterpolation is not modelled; weighted motion is interpolated linearly");
    const glm::dmat4 objectMotion = *objectFromWorld * motion * gm.m;
    if (!geom::isFinite(objectMotion)) return who + "the cluster matrix is not finite";

    const std::vector<double> weights = pointWeights(ev, n, index, mesh.points.size(), 1.0, notes);
    std::vector<glm::dvec3> points = pointsOf(mesh);
    for (size_t i = 0; i < points.size(); ++i) {
        if (!isMember(members, i)) continue;
        const double w = *en * weights[i];
        if (w == 0.0) continue;
        points[i] += w * (transformPoint(objectMotion, points[i]) - points[i]);
    }
    return commitPoints(node, points, mesh, notes);
}

// --------------------------------------------------------------------------------- nonLinear
// Parameters of a nonLinear deformer: the node's own (addAttr'd) attributes, which drive the
// handle's; the handle shape's when the node has none of that name.
class NonLinearParams {
public:
    NonLinearParams(Evaluator& ev, NodeId deformer, NodeId handle) : m_ev(ev), m_deformer(deformer), m_handle(handle) {}

    // `name` is the short name; `angle` marks angle-valued parameters (radians).
    double get(std::string_view name, double fallback, bool angle = false) {
        const Graph& g = m_ev.graph();
        double v = fallback;
        if (g.node(m_deformer).findAttr(name)) {
            v = m_ev.getDouble(m_deformer, name, fallback);
        } else if (g.value(m_deformer, name)) {
            // Set without an addAttr: the value is still in the file's angle unit.
            v = m_ev.getDouble(m_deformer, name, fallback) * (angle ? g.units.radiansPerAngleUnit : 1.0);
        } else if (m_handle != kNoNode) {
            v = m_ev.getDouble(m_handle, name, fallback);
        }
        if (!std::isfinite(v) && m_firstBad.empty()) m_firstBad = std::string(name);
        return v;
    }
    // The first parameter read that was not finite, empty when all were.
    const std::string& firstNonFinite() const { return m_firstBad; }

private:
    Evaluator& m_ev;
    NodeId m_deformer;
    NodeId m_handle;
    std::string m_firstBad;
};

// Position of y between the bounds: 0 at lowBound, 1 at highBound, clamped.
double boundParameter(double y, double lowBound, double highBound) {
    if (!(highBound > lowBound)) return y >= highBound ? 1.0 : 0.0;
    return std::clamp((y - lowBound) / (highBound - lowBound), 0.0, 1.0);
}

// The handle-space deformation of one nonLinear type. Each works on the handle's Y axis between
// lowBound and highBound; points beyond a bound get the deformation at that bound, continued
// rigidly where the deformation moves along Y. Curvature, flare and twist follow Maya's node
// documentation; where it gives only the intent of a parameter (flare curve, squash profile,
// sine and wave dropoff and offset) the formula is ours and a note says so.
struct HandleDeformation {
    virtual ~HandleDeformation() = default;
    virtual glm::dvec3 operator()(const glm::dvec3& p) const = 0;
};

// deformBend: the segment [lowBound, highBound] of the Y axis bends into a circular arc in the XY
// plane toward +X for positive curvature; curvature is the turn in radians per unit of handle
// length (the arc from 0 to y turns by curvature · y), so radius = 1 / curvature, centred at
// (radius, 0). A point at distance x from the axis keeps its distance from the arc.
struct Bend final : HandleDeformation {
    double curvature = 0, lowBound = -1, highBound = 1;
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        if (std::abs(curvature) < 1e-12) return p;
        const double yc = std::clamp(p.y, std::min(lowBound, highBound), std::max(lowBound, highBound));
        const double theta = curvature * yc;
        const double radius = 1.0 / curvature;
        const double beyond = p.y - yc;  // continues straight along the tangent past a bound
        const double c = std::cos(theta), s = std::sin(theta);
        return {radius - (radius - p.x) * c + beyond * s, (radius - p.x) * s + beyond * c, p.z};
    }
};

// deformFlare: X and Z are scaled about the Y axis by a flare interpolated from start (lowBound)
// to end (highBound); curve adds curve · 4t(1 − t), zero at both bounds and largest halfway.
struct Flare final : HandleDeformation {
    double startX = 1, startZ = 1, endX = 1, endZ = 1, curve = 0, lowBound = -1, highBound = 1;
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        const double t = boundParameter(p.y, lowBound, highBound);
        const double bulge = curve * 4.0 * t * (1.0 - t);
        const double sx = startX + (endX - startX) * t + bulge;
        const double sz = startZ + (endZ - startZ) * t + bulge;
        return {p.x * sx, p.y, p.z * sz};
    }
};

// deformTwist: rotation about +Y by an angle interpolated from startAngle (lowBound) to endAngle
// (highBound), right-handed like Maya's rotateY.
struct Twist final : HandleDeformation {
    double startAngle = 0, endAngle = 0, lowBound = -1, highBound = 1;
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        const double t = boundParameter(p.y, lowBound, highBound);
        const double a = startAngle + (endAngle - startAngle) * t;
        const double c = std::cos(a), s = std::sin(a);
        return {p.x * c + p.z * s, p.y, -p.x * s + p.z * c};
    }
};

// deformSquash: Y between the bounds is scaled about the handle's centre by 1 + factor (factor
// >= 0, a stretch) or 1 / (1 − factor) (factor < 0, a squash), which is continuous and always
// positive; beyond a bound the rest of the shape moves rigidly with the bound. X and Z expand by
// expand · (1/√heightScale − 1) · profile(t), so at the maximum expansion position (profile 1,
// expand 1) a thin slice keeps its volume. The profile rises from 0 at lowBound to 1 at
// maxExpandPos and falls back to 0 at highBound: a parabola blended toward a smoothstep by
// startSmoothness below the peak and endSmoothness above it.
struct Squash final : HandleDeformation {
    double factor = 0, expand = 1, maxExpandPos = 0.5, startSmoothness = 0, endSmoothness = 0, lowBound = -1,
           highBound = 1;
    double heightScale() const { return factor >= 0.0 ? 1.0 + factor : 1.0 / (1.0 - factor); }
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        const double h = heightScale();
        const double lo = std::min(lowBound, highBound), hi = std::max(lowBound, highBound);
        const double yc = std::clamp(p.y, lo, hi);
        const double y = yc * h + (p.y - yc);
        double profile = 0.0;
        if (p.y >= lo && p.y <= hi && hi > lo) {
            const double t = (p.y - lo) / (hi - lo);
            const double peak = std::clamp(maxExpandPos, 1e-6, 1.0 - 1e-6);
            const double u = t <= peak ? t / peak : (1.0 - t) / (1.0 - peak);
            const double smooth = std::clamp(t <= peak ? startSmoothness : endSmoothness, 0.0, 1.0);
            const double parabola = 1.0 - (1.0 - u) * (1.0 - u);
            const double smoothstep = u * u * (3.0 - 2.0 * u);
            profile = (1.0 - smooth) * parabola + smooth * smoothstep;
        }
        const double radial = 1.0 + expand * (1.0 / std::sqrt(h) - 1.0) * profile;
        return {p.x * radial, y, p.z * radial};
    }
};

// Linear dropoff from the centre of the bounds: dropoff > 0 fades the amplitude toward the bounds,
// dropoff < 0 toward the centre; `n` is the distance from the centre as a fraction (0..1).
double dropoffScale(double dropoff, double n) {
    const double d = std::clamp(dropoff, -1.0, 1.0);
    return d >= 0.0 ? 1.0 - d * n : 1.0 + d * (1.0 - n);
}

// deformSine: X is displaced by amplitude · sin(2π·y / wavelength + offset) along Y between the
// bounds (beyond a bound, the displacement at the bound).
struct Sine final : HandleDeformation {
    double amplitude = 0, wavelength = 2, offset = 0, dropoff = 0, lowBound = -1, highBound = 1;
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        const double lo = std::min(lowBound, highBound), hi = std::max(lowBound, highBound);
        const double yc = std::clamp(p.y, lo, hi);
        const double reach = yc >= 0.0 ? hi : -lo;
        const double n = reach > 0.0 ? std::abs(yc) / reach : 0.0;
        const double phase = 2.0 * std::numbers::pi * yc / wavelength + offset;
        return {p.x + amplitude * dropoffScale(dropoff, n) * std::sin(phase), p.y, p.z};
    }
};

// deformWave: Y is displaced by amplitude · sin(2π·r / wavelength + offset), r the distance from
// the Y axis clamped to [minRadius, maxRadius]; dropoff fades it away from dropoffPosition
// (a fraction of the way from minRadius to maxRadius).
struct Wave final : HandleDeformation {
    double amplitude = 0, wavelength = 1, offset = 0, dropoff = 0, dropoffPosition = 0, minRadius = 0, maxRadius = 1;
    glm::dvec3 operator()(const glm::dvec3& p) const override {
        const double lo = std::min(minRadius, maxRadius), hi = std::max(minRadius, maxRadius);
        const double r = std::clamp(std::sqrt(p.x * p.x + p.z * p.z), lo, hi);
        const double f = hi > lo ? (r - lo) / (hi - lo) : 0.0;
        const double n = std::min(1.0, std::abs(f - std::clamp(dropoffPosition, 0.0, 1.0)));
        const double phase = 2.0 * std::numbers::pi * r / wavelength + offset;
        return {p.x, p.y + amplitude * dropoffScale(dropoff, n) * std::sin(phase), p.z};
    }
};

// The handle shape of a nonLinear node: the source of its deformerData, else a deform* shape
// under the transform driving its matrix.
NodeId nonLinearHandle(const Graph& g, NodeId n) {
    auto isHandle = [&](NodeId id) { return id < g.size() && g.node(id).type.rfind("deform", 0) == 0; };
    if (std::optional<Plug> dd = sourceOf(g, n, {"dd", "deformerData"}); dd && isHandle(dd->node)) return dd->node;
    if (std::optional<Plug> ma = sourceOf(g, n, {"ma", "matrix"}); ma && ma->node < g.size())
        for (NodeId child : g.node(ma->node).children())
            if (isHandle(child)) return child;
    return kNoNode;
}

std::unique_ptr<HandleDeformation> handleDeformation(const std::string& type, NonLinearParams& p,
                                                     const std::string& who, std::vector<std::string>& notes,
                                                     std::string& reason) {
    if (type == "deformBend") {
        auto d = std::make_unique<Bend>();
        d->curvature = p.get("cur", 0.0, true);
        d->lowBound = p.get("lb", -1.0);
        d->highBound = p.get("hb", 1.0);
        return d;
    }
    if (type == "deformFlare") {
        auto d = std::make_unique<Flare>();
        d->startX = p.get("sfx", 1.0);
        d->startZ = p.get("sfz", 1.0);
        d->endX = p.get("efx", 1.0);
        d->endZ = p.get("efz", 1.0);
        d->curve = p.get("crv", 0.0);
        d->lowBound = p.get("lb", -1.0);
        d->highBound = p.get("hb", 1.0);
        if (d->curve != 0.0) notes.push_back(who + "the flare curve's profile is approximated (curve · 4t(1 − t))");
        return d;
    }
    if (type == "deformTwist") {
        auto d = std::make_unique<Twist>();
        d->startAngle = p.get("sa", 0.0, true);
        d->endAngle = p.get("ea", 0.0, true);
        d->lowBound = p.get("lb", -1.0);
        d->highBound = p.get("hb", 1.0);
        return d;
    }
    if (type == "deformSquash") {
        auto d = std::make_unique<Squash>();
        d->factor = p.get("fac", 0.0);
        d->expand = p.get("exp", 1.0);
        d->maxExpandPos = p.get("mp", 0.5);
        d->startSmoothness = p.get("ss", 0.0);
        d->endSmoothness = p.get("es", 0.0);
        d->lowBound = p.get("lb", -1.0);
        d->highBound = p.get("hb", 1.0);
        if (d->factor != 0.0 && d->expand != 0.0)
            notes.push_back(who + "the squash expansion profile between the bounds is approximated");
        return d;
    }
    if (type == "deformSine") {
        auto d = std::make_unique<Sine>();
        d->amplitude = p.get("amp", 0.0);
        d->wavelength = p.get("wav", 2.0);
        d->offset = p.get("off", 0.0);
        d->dropoff = p.get("dr", 0.0);
        d->lowBound = p.get("lb", -1.0);
        d->highBound = p.get("hb", 1.0);
        if (!(std::abs(d->wavelength) > 1e-9)) {
            reason = who + "the sine wavelength is 0";
            return nullptr;
        }
        if (d->amplitude != 0.0)
            notes.push_back(who + "the sine phase offset and dropoff follow an approximated convention");
        return d;
    }
    if (type == "deformWave") {
        auto d = std::make_unique<Wave>();
        d->amplitude = p.get("amp", 0.0);
        d->wavelength = p.get("wav", 1.0);
        d->offset = p.get("off", 0.0);
        d->dropoff = p.get("dr", 0.0);
        d->dropoffPosition = p.get("dp", 0.0);
        d->minRadius = p.get("mnr", 0.0);
        d->maxRadius = p.get("mxr", 1.0);
        if (!(std::abs(d->wavelength) > 1e-9)) {
            reason = who + "the wave wavelength is 0";
            return nullptr;
        }
        if (d->amplitude != 0.0)
            notes.push_back(who + "the wave phase offset and dropoff follow an approximated convention");
        return d;
    }
    reason = who + "handle type " + type + " is not evaluated";
    return nullptr;
}

std::string applyNonLinear(Evaluator& ev, NodeId n, uint32_t index, const std::vector<bool>* members,
                           geom::Mesh& mesh, std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    const Node& node = g.node(n);
    const std::string who = nodeLabel(node) + ": ";
    std::string reason;
    const std::optional<double> en = envelopeOf(ev, n, reason);
    if (!en) return reason;
    const NodeId handle = nonLinearHandle(g, n);
    if (handle == kNoNode) return who + "no deformer handle (deformerData is not connected)";

    NonLinearParams params(ev, n, handle);
    std::vector<std::string> typeNotes;
    const std::unique_ptr<HandleDeformation> deform = handleDeformation(g.node(handle).type, params, who, typeNotes, reason);
    if (!deform) return reason;
    if (!params.firstNonFinite().empty()) return who + "parameter " + params.firstNonFinite() + " is not finite";

    const std::string k = std::to_string(index);
    MatrixValue gm = readMatrix(ev, n, {"gm[" + k + "]", "geomMatrix[" + k + "]"});
    if (!gm.error.empty()) return who + "geomMatrix: " + gm.error;
    if (!gm.present) gm.m = upstreamGeometryMatrix(ev, n, index);
    const MatrixValue ma = readMatrix(ev, n, {"ma", "matrix"});
    if (!ma.error.empty()) return who + "matrix: " + ma.error;
    const std::optional<glm::dmat4> handleFromWorld = inverseOf(ma.m);
    if (!handleFromWorld) return who + "the handle matrix is not invertible";
    const glm::dmat4 handleFromObject = *handleFromWorld * gm.m;
    const std::optional<glm::dmat4> objectFromHandle = inverseOf(handleFromObject);
    if (!geom::isFinite(gm.m) || !objectFromHandle) return who + "the geometry matrix is not finite or not invertible";

    const std::vector<double> weights = pointWeights(ev, n, index, mesh.points.size(), 1.0, notes);
    std::vector<glm::dvec3> points = pointsOf(mesh);
    for (size_t i = 0; i < points.size(); ++i) {
        if (!isMember(members, i)) continue;
        const double w = *en * weights[i];
        if (w == 0.0) continue;
        const glm::dvec3 deformed =
            transformPoint(*objectFromHandle, (*deform)(transformPoint(handleFromObject, points[i])));
        points[i] += w * (deformed - points[i]);
    }
    std::string result = commitPoints(node, points, mesh, notes);
    if (result.empty()) notes.insert(notes.end(), typeNotes.begin(), typeNotes.end());
    return result;
}

// ------------------------------------------------------------------------------- skinCluster
// A rigid transform as a unit dual quaternion (real part: rotation; dual part: ½·t·real).
struct DualQuat {
    glm::dquat real{1, 0, 0, 0};
    glm::dquat dual{0, 0, 0, 0};
};

// The rotation and translation of a column-vector matrix; `rigid` false when it also scales or
// shears (the rotation is then that of its orthonormalized axes).
DualQuat toDualQuat(const glm::dmat4& m, bool& rigid) {
    glm::dmat3 r(m);
    const glm::dmat3 gram = glm::transpose(r) * r;
    rigid = true;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row)
            if (std::abs(gram[c][row] - (c == row ? 1.0 : 0.0)) > 1e-4) rigid = false;
    // Gram-Schmidt keeps a proper rotation for a matrix with scale or shear.
    glm::dvec3 x = glm::normalize(r[0]);
    glm::dvec3 y = glm::normalize(r[1] - glm::dot(r[1], x) * x);
    glm::dvec3 z = glm::cross(x, y);
    if (glm::dot(z, r[2]) < 0.0) rigid = false;  // a mirror cannot be a rotation
    const glm::dquat real = glm::normalize(glm::quat_cast(glm::dmat3(x, y, z)));
    const glm::dvec3 t(m[3]);
    DualQuat out;
    out.real = real;
    out.dual = 0.5 * (glm::dquat(0.0, t.x, t.y, t.z) * real);
    return out;
}

glm::dvec3 dualQuatTransform(const DualQuat& q, const glm::dvec3& p) {
    const glm::dvec3 v(q.real.x, q.real.y, q.real.z), d(q.dual.x, q.dual.y, q.dual.z);
    const glm::dvec3 t = 2.0 * (q.real.w * d - q.dual.w * v + glm::cross(v, d));
    return q.real * p + t;
}

std::string applySkinCluster(Evaluator& ev, NodeId n, uint32_t index, const std::vector<bool>* members,
                             geom::Mesh& mesh, std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    const Node& node = g.node(n);
    const std::string who = nodeLabel(node) + ": ";
    std::string reason;
    const std::optional<double> en = envelopeOf(ev, n, reason);
    if (!en) return reason;
    const size_t count = mesh.points.size();

    // Weights per point: (influence, weight) pairs, unset weights being 0.
    std::vector<std::vector<std::pair<uint32_t, double>>> weights(count);
    const std::string sample = elementKey(g, n, "wl", 0, "w");  // "weightList[0].weights"
    const size_t open = sample.find("[0]");
    const std::string listPrefix = sample.substr(0, open), weightSuffix = sample.substr(open + 3);
    uint32_t influences = 0;
    size_t nonFiniteWeights = 0;
    for (auto it = node.attrs.lower_bound(listPrefix + "["); it != node.attrs.end() && it->first.rfind(listPrefix + "[", 0) == 0;
         ++it) {
        const std::optional<uint32_t> i = elementIndexAfter(it->first, listPrefix);
        if (!i || *i >= count) continue;
        const std::string expected = listPrefix + "[" + std::to_string(*i) + "]" + weightSuffix;
        if (it->first != expected) continue;
        forEachNumeric(it->second, [&](uint32_t j, const double* v, int) {
            if (j >= kMaxInfluences) return;
            if (!std::isfinite(v[0])) {
                ++nonFiniteWeights;
                return;
            }
            if (v[0] == 0.0) return;
            weights[*i].emplace_back(j, v[0]);
            influences = std::max(influences, j + 1);
        });
    }
    if (nonFiniteWeights) return who + std::to_string(nonFiniteWeights) + " skin weights are not finite";
    if (anyElementConnected(g, n, listPrefix))
        notes.push_back(who + "connected weights are not evaluated; the stored weights are used");

    // geomMatrix: one matrix on skinCluster (an element per geometry on older files).
    const std::string k = std::to_string(index);
    const MatrixValue gm = readMatrix(ev, n, {"gm", "geomMatrix", "gm[" + k + "]", "geomMatrix[" + k + "]"});
    if (!gm.error.empty()) return who + "geomMatrix: " + gm.error;
    const std::optional<glm::dmat4> objectFromWorld = inverseOf(gm.m);
    if (!objectFromWorld) return who + "geomMatrix is not invertible";

    // Each weighted influence's motion, in the geometry's object space:
    // gm⁻¹ · matrix[j] · bindPreMatrix[j] · gm.
    std::vector<bool> used(influences, false);
    for (const auto& list : weights)
        for (const auto& [j, w] : list) used[j] = true;
    std::vector<glm::dmat4> motion(influences, glm::dmat4(1.0));
    std::vector<bool> hasMatrix(influences, true);
    size_t withoutMatrix = 0;
    for (uint32_t j = 0; j < influences; ++j) {
        if (!used[j]) continue;
        const std::string e = std::to_string(j);
        const MatrixValue ma = readMatrix(ev, n, {"ma[" + e + "]", "matrix[" + e + "]"});
        if (!ma.error.empty()) return who + "matrix[" + e + "]: " + ma.error;
        const MatrixValue pm = readMatrix(ev, n, {"pm[" + e + "]", "bindPreMatrix[" + e + "]"});
        if (!pm.error.empty()) return who + "bindPreMatrix[" + e + "]: " + pm.error;
        hasMatrix[j] = ma.present;
        motion[j] = *objectFromWorld * ma.m * pm.m * gm.m;
        if (!geom::isFinite(motion[j])) return who + "the matrix of influence " + e + " is not finite";
    }

    const int method = ev.getInt(n, "skm", 0);
    const int normalize = ev.getInt(n, "nw", 1);
    const bool useDualQuat = method == 1 || method == 2;
    if (method < 0 || method > 2) notes.push_back(who + "skinningMethod " + std::to_string(method) + " is unknown; linear skinning is used");
    std::vector<DualQuat> dual;
    if (useDualQuat) {
        bool allRigid = true;
        for (const glm::dmat4& m : motion) {
            bool rigid = true;
            dual.push_back(toDualQuat(m, rigid));
            allRigid = allRigid && rigid;
        }
        if (!allRigid)
            notes.push_back(who + "scale and shear of influences are not modelled by dual quaternion skinning; their rotation and translation are used");
    }
    std::vector<double> blend;
    if (method == 2) {
        blend.assign(count, 0.0);
        if (const AttrData* a = g.findAttr(n, g.canonicalPath(n, {{"bw", -1, -1}})))
            forEachNumeric(*a, [&](uint32_t i, const double* v, int) {
                if (i < count && std::isfinite(v[0])) blend[i] = std::clamp(v[0], 0.0, 1.0);
            });
    }

    std::vector<glm::dvec3> points = pointsOf(mesh);
    size_t unweighted = 0;
    for (size_t i = 0; i < count; ++i) {
        if (!isMember(members, i) || *en == 0.0) continue;
        double sum = 0.0;
        for (const auto& [j, w] : weights[i]) sum += w;
        if (sum == 0.0) {
            ++unweighted;
            continue;
        }
        const double scale = normalize == 2 ? 1.0 / sum : 1.0;
        const glm::dvec3 p = points[i];
        glm::dvec3 linear(0.0);
        for (const auto& [j, w] : weights[i]) linear += w * scale * transformPoint(motion[j], p);
        glm::dvec3 skinned = linear;
        if (useDualQuat) {
            // Blend in the hemisphere of the heaviest influence so opposite quaternions do not cancel.
            const auto heaviest = std::max_element(weights[i].begin(), weights[i].end(),
                                                   [](const auto& a, const auto& b) { return a.second < b.second; });
            const glm::dquat pivot = dual[heaviest->first].real;
            DualQuat b;
            b.real = glm::dquat(0, 0, 0, 0);
            for (const auto& [j, w] : weights[i]) {
                const double s = glm::dot(dual[j].real, pivot) < 0.0 ? -w : w;
                b.real += s * dual[j].real;
                b.dual += s * dual[j].dual;
            }
            const double length = glm::length(b.real);
            if (length > 1e-12) {
                b.real /= length;
                b.dual /= length;
                const glm::dvec3 dq = dualQuatTransform(b, p);
                const double t = method == 2 ? blend[i] : 1.0;
                skinned = (1.0 - t) * linear + t * dq;
            }
        }
        points[i] = p + *en * (skinned - p);
    }
    if (unweighted)
        notes.push_back(who + std::to_string(unweighted) + " points without skin weights are left in place");
    for (uint32_t j = 0; j < influences; ++j)
        if (!hasMatrix[j]) ++withoutMatrix;
    if (withoutMatrix)
        notes.push_back(who + std::to_string(withoutMatrix) + " weighted influences have no matrix; identity is used");
    return commitPoints(node, points, mesh, notes);
}

}  // namespace

bool isEvaluatedDeformer(std::string_view type) {
    return type == "tweak" || type == "cluster" || type == "nonLinear" || type == "skinCluster";
}

std::string applyDeformer(Evaluator& ev, NodeId deformer, uint32_t geometryIndex, const std::vector<bool>* members,
                          geom::Mesh& mesh, std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    if (deformer >= g.size()) return "no such deformer node";
    const Node& node = g.node(deformer);
    if (geometryIndex >= kMaxElements) return nodeLabel(node) + ": geometry index " + std::to_string(geometryIndex) + " is too large";
    try {
        if (node.type == "tweak") return applyTweak(ev, deformer, geometryIndex, members, mesh, notes);
        if (node.type == "cluster") return applyCluster(ev, deformer, geometryIndex, members, mesh, notes);
        if (node.type == "nonLinear") return applyNonLinear(ev, deformer, geometryIndex, members, mesh, notes);
        if (node.type == "skinCluster") return applySkinCluster(ev, deformer, geometryIndex, members, mesh, notes);
    } catch (const std::exception& e) {
        // Scene content must never abort a render; anything unexpected becomes a reason.
        return nodeLabel(node) + ": evaluation failed: " + e.what();
    }
    return "deformer " + nodeLabel(node) + " is not evaluated";
}

}  // namespace pushpin::scene
