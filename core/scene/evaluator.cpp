#include "core/scene/evaluator.h"

#include "cache/error.h"
#include "core/scene/anim_curve.h"
#include "core/scene/transform.h"
#include "core/util/format.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::scene {

namespace {

bool isNumericCompound(const AttrSpec& spec) { return spec.component < 0 && componentCount(spec.type) > 1; }

// The numeric children (translateX, translateY …) of a compound attribute, by component index.
std::vector<const AttrSpec*> componentChildren(const Node& node, const AttrSpec& compound) {
    std::vector<const AttrSpec*> out;
    auto consider = [&](const AttrSpec& s) {
        if (s.component >= 0 && s.parent == compound.longName) {
            if (out.size() <= size_t(s.component)) out.resize(size_t(s.component) + 1, nullptr);
            if (!out[size_t(s.component)]) out[size_t(s.component)] = &s;
        }
    };
    for (const NodeSchema* schema = node.schema; schema; schema = schema->base())
        for (const AttrSpec& s : schema->ownAttributes()) consider(s);
    for (const AttrSpec& s : node.dynamicAttrs()) consider(s);
    return out;
}

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

bool isA(const Node& node, std::string_view type) {
    return node.type == type || (node.schema && node.schema->isA(type));
}

bool isAnimCurveNode(const Node& n) { return isA(n, "animCurve") || startsWith(n.type, "animCurve"); }

}  // namespace

Evaluator::Evaluator(const Graph& graph, double frame) : m_graph(graph), m_frame(frame) {}

bool Evaluator::numbers(NodeId node, std::string_view plugPath, std::vector<double>& out) {
    out.clear();
    if (node >= m_graph.size()) return false;
    if (holdsStoredValues(node)) return m_graph.numbers(node, plugPath, out);
    auto segs = parsePlugPath(plugPath);
    if (!segs) return false;
    return evaluatePlug(node, m_graph.canonicalPath(node, *segs), out);
}

// A node nothing drives and that computes nothing holds its stored values: they are read directly.
bool Evaluator::holdsStoredValues(NodeId node) {
    return m_graph.node(node).inConnections().empty() && !computesOutputs(node);
}

bool Evaluator::computesOutputs(NodeId node) {
    if (m_computesOutputs.size() != m_graph.size()) m_computesOutputs.resize(m_graph.size(), 0);
    uint8_t& known = m_computesOutputs[node];
    if (known == 0) {
        const Node& n = m_graph.node(node);
        known = isAnimCurveNode(n) || isA(n, "unitConversion") || isA(n, "time") ? 1 : 2;
    }
    return known == 1;
}

uint32_t Evaluator::findEntry(NodeId node, std::string_view path) const {
    if (node >= m_firstEntry.size() || m_firstEntry[node] == kNoEntry) return kNoEntry;
    if (!hashedEntries(node)) {
        for (uint32_t e = m_firstEntry[node]; e != kNoEntry; e = m_entries[e].nextOfNode)
            if (m_entries[e].path == path) return e;
        return kNoEntry;
    }
    return m_entryIndex.find(util::hashIdAndBytes(node, path), [&](uint32_t e) {
        return m_entries[e].node == node && m_entries[e].path == path;
    });
}

uint32_t Evaluator::addEntry(NodeId node, std::string path) {
    if (m_entries.size() >= kNoEntry) throw Error("evaluation: more than 4 billion plugs cached");
    if (m_firstEntry.size() != m_graph.size()) {
        m_firstEntry.resize(m_graph.size(), kNoEntry);
        m_entriesOfNode.resize(m_graph.size(), 0);
    }
    const uint32_t e = uint32_t(m_entries.size());
    CacheEntry& entry = m_entries.emplace_back();
    entry.node = node;
    entry.path = std::move(path);
    entry.nextOfNode = m_firstEntry[node];
    m_firstEntry[node] = e;
    if (hashedEntries(node)) {
        m_entryIndex.insert(util::hashIdAndBytes(node, entry.path), e);
    } else if (++m_entriesOfNode[node] > kListedEntriesPerNode) {
        // Past a few plugs a node's list would make lookups linear: its plugs move to the table.
        for (uint32_t k = e; k != kNoEntry; k = m_entries[k].nextOfNode)
            m_entryIndex.insert(util::hashIdAndBytes(node, m_entries[k].path), k);
    }
    return e;
}

void Evaluator::readEntry(const CacheEntry& e, std::vector<double>& out) const {
    out.assign(m_values.begin() + ptrdiff_t(e.valueOffset), m_values.begin() + ptrdiff_t(e.valueOffset + e.valueCount));
}

void Evaluator::reportCycle(NodeId node, const std::string& path) {
    const Node& n = m_graph.node(node);
    const std::string message =
        "connection cycle through '" + util::excerpt(n.name) + "." + util::excerpt(path) + "'; using its static value";
    if (m_reportedCycles.insert(message).second)
        m_diagnostics.push_back(Diagnostic{m_graph.sourceFile, n.line, 0, util::excerpt(n.name), message});
}

bool Evaluator::evaluatePlug(NodeId node, const std::string& path, std::vector<double>& out) {
    out.clear();
    if (node >= m_graph.size()) return false;
    if (const uint32_t e = findEntry(node, path); e != kNoEntry) {
        switch (m_entries[e].state) {
            case CacheEntry::State::Ready: readEntry(m_entries[e], out); return true;
            case CacheEntry::State::Missing: return false;
            case CacheEntry::State::Evaluating:
                // A connection cycle: break it here with the plug's static value, and say so once.
                reportCycle(node, path);
                return m_graph.numbers(node, path, out);
        }
    }
    if (!needsCache(node, path)) return computePlug(node, path, out);

    // Depth-first over the dependencies with an explicit stack: a plug is computed once all the
    // plugs it reads are in the cache, so computePlug never has to descend itself. Entries are
    // referred to by number, since m_entries grows as the walk opens new plugs.
    struct Frame {
        uint32_t entry;
        uint32_t next;  // dependencies already pushed or skipped
    };
    const uint32_t root = addEntry(node, path);
    std::vector<Frame> stack{{root, 0}};
    std::vector<double> value;
    std::vector<Plug> deps, depsOfDep;
    bool haveDeps = false;  // `deps` already holds the top's dependencies
    while (!stack.empty()) {
        Frame& top = stack.back();
        // Recomputed when a frame is returned to rather than kept per frame: a plug has a few
        // dependencies, and a million-deep chain then costs 8 bytes of stack per plug.
        if (!haveDeps) {
            const CacheEntry& e = m_entries[top.entry];
            deps = dependencies(e.node, e.path);
        }
        haveDeps = false;
        bool descended = false;
        while (top.next < deps.size()) {
            Plug& d = deps[top.next++];
            if (d.node >= m_graph.size() || findEntry(d.node, d.path) != kNoEntry) continue;  // invalid, done or on the stack
            depsOfDep = dependencies(d.node, d.path);
            if (depsOfDep.empty() && !isCachedOutput(d.node, d.path)) continue;  // read directly
            const uint32_t opened = addEntry(d.node, std::move(d.path));
            stack.push_back(Frame{opened, 0});  // invalidates `top`
            deps.swap(depsOfDep);  // the new top's, just computed
            haveDeps = true;
            descended = true;
            break;
        }
        if (descended) continue;
        const uint32_t current = top.entry;
        const bool ok = computePlug(m_entries[current].node, m_entries[current].path, value);
        CacheEntry& e = m_entries[current];
        e.state = ok ? CacheEntry::State::Ready : CacheEntry::State::Missing;
        if (ok) {
            e.valueOffset = m_values.size();
            e.valueCount = uint32_t(value.size());
            m_values.insert(m_values.end(), value.begin(), value.end());
        }
        stack.pop_back();
    }
    const CacheEntry& done = m_entries[root];
    if (done.state != CacheEntry::State::Ready) return false;
    readEntry(done, out);
    return true;
}

namespace {


// animCurveT* are driven by time, animCurveU* by their `input` plug (set driven keys).
bool timeDrivenCurve(const Node& n) { return startsWith(n.type, "animCurveT") || !startsWith(n.type, "animCurveU"); }

// The plug path of the numeric compound whose component `spec` is (translate for translateX),
// given the parsed path `segs` that ends in the component.
std::string parentCompoundPath(const Node& n, const std::vector<PlugSegment>& segs, const AttrSpec* parentSpec) {
    std::vector<PlugSegment> parentSegs(segs.begin(), segs.end() - 1);
    if (parentSegs.empty() || n.findAttr(parentSegs.back().name) != parentSpec)
        parentSegs.push_back(PlugSegment{parentSpec->longName});
    return formatPlugPath(parentSegs);
}

// The plug path of component `child` of the compound at `path` (parsed as `segs`): translateX
// for translate, colorEntryList[0].colorR style for an indexed compound.
std::string componentChildPath(const std::string& path, const std::vector<PlugSegment>& segs, const AttrSpec& child) {
    if (segs.back().indexed()) return path + "." + child.longName;
    std::vector<PlugSegment> childSegs = segs;
    childSegs.back().name = child.longName;
    return formatPlugPath(childSegs);
}

}  // namespace

std::vector<Plug> Evaluator::dependencies(NodeId node, const std::string& path) const {
    std::vector<Plug> deps;
    const Node& n = m_graph.node(node);
    // Without incoming connections every plug of the node is static or computed from its own
    // static plugs, which computePlug reads directly: nothing to evaluate first.
    if (n.inConnections().empty()) return deps;
    if (const Plug* src = m_graph.sourceOfCanonical(node, path)) {
        deps.push_back(*src);
        return deps;
    }
    if (path == "output") {
        if (isAnimCurveNode(n)) {
            if (!timeDrivenCurve(n) || m_graph.sourceOfCanonical(node, "input")) deps.push_back(Plug{node, "input"});
            return deps;
        }
        if (isA(n, "unitConversion")) {
            deps.push_back(Plug{node, "input"});
            deps.push_back(Plug{node, "conversionFactor"});
        }
    }
    // A plain attribute name (the usual case) needs no parsing: its compound parent and its
    // component children are plain names too.
    const bool plain = isPlainPlugName(path);
    std::optional<std::vector<PlugSegment>> segs;
    if (!plain) segs = parsePlugPath(path);
    const AttrSpec* spec = plain ? n.findAttr(path) : segs ? n.findAttr(segs->back().name) : nullptr;
    const AttrSpec* parentSpec = spec && spec->component >= 0 ? n.findAttr(spec->parent) : nullptr;
    if (parentSpec && isNumericCompound(*parentSpec))
        if (const Plug* parentSrc = m_graph.sourceOfCanonical(
                node, plain ? parentSpec->longName : parentCompoundPath(n, *segs, parentSpec)))
            deps.push_back(*parentSrc);
    if (spec && isNumericCompound(*spec)) {
        for (const AttrSpec* child : componentChildren(n, *spec)) {
            if (!child) continue;
            if (const Plug* childSrc = m_graph.sourceOfCanonical(
                    node, plain ? child->longName : componentChildPath(path, *segs, *child)))
                deps.push_back(*childSrc);
        }
    }
    return deps;
}

// An animCurve output is worth keeping even when driven by time alone: its keys are decoded from
// the Graph on each computation.
bool Evaluator::isCachedOutput(NodeId node, std::string_view path) const {
    return path == "output" && isAnimCurveNode(m_graph.node(node));
}

bool Evaluator::needsCache(NodeId node, const std::string& path) const {
    return isCachedOutput(node, path) || !dependencies(node, path).empty();
}

bool Evaluator::computePlug(NodeId node, const std::string& path, std::vector<double>& out) {
    out.clear();
    const Node& n = m_graph.node(node);
    if (const Plug* src = m_graph.sourceOfCanonical(node, path)) {
        const Plug from = *src;
        return evaluatePlug(from.node, from.path, out);
    }
    if (computeOutput(node, path, out)) return true;  // animCurve.output, unitConversion.output, time.outTime
    if (n.inConnections().empty()) return m_graph.numbers(node, path, out);  // nothing drives a component
    bool ok = false;
    auto segs = parsePlugPath(path);
    const AttrSpec* spec = segs ? n.findAttr(segs->back().name) : nullptr;
    // A plug that is neither a component nor a numeric compound has nothing else to gather.
    if (!spec || (spec->component < 0 && !isNumericCompound(*spec))) return m_graph.numbers(node, path, out);
    const AttrSpec* parentSpec = spec && spec->component >= 0 ? n.findAttr(spec->parent) : nullptr;
    if (parentSpec && isNumericCompound(*parentSpec)) {
        // translateX with `translate` connected as a whole: take the component of the source.
        if (auto parentSrc = m_graph.source(node, parentCompoundPath(n, *segs, parentSpec))) {
            std::vector<double> whole;
            if (evaluatePlug(parentSrc->node, parentSrc->path, whole) && size_t(spec->component) < whole.size()) {
                out.assign(1, whole[size_t(spec->component)]);
                ok = true;
            }
        }
    }
    if (!ok) ok = m_graph.numbers(node, path, out);
    if (ok && spec && isNumericCompound(*spec)) {
        // translate with translateX/Y/Z connected one by one (the usual animCurve wiring).
        const auto children = componentChildren(n, *spec);
        for (size_t k = 0; k < children.size() && k < out.size(); ++k) {
            if (!children[k]) continue;
            if (auto childSrc = m_graph.source(node, componentChildPath(path, *segs, *children[k]))) {
                std::vector<double> v;
                if (evaluatePlug(childSrc->node, childSrc->path, v) && !v.empty()) out[k] = v[0];
            }
        }
    }
    return ok;
}

bool Evaluator::computeOutput(NodeId node, const std::string& path, std::vector<double>& out) {
    const Node& n = m_graph.node(node);
    if (path != "output" && path != "outTime") return false;
    if (isAnimCurveNode(n)) {
        if (path != "output") return false;
        out.assign(1, evaluateAnimCurve(node));
        return true;
    }
    if (isA(n, "unitConversion")) {
        if (path != "output") return false;
        std::vector<double> in;
        if (!evaluatePlug(node, "input", in)) return false;
        std::vector<double> factor;
        const double f = evaluatePlug(node, "conversionFactor", factor) && !factor.empty() ? factor[0] : 1.0;
        for (double& v : in) v *= f;
        out = std::move(in);
        return true;
    }
    if (isA(n, "time") && path == "outTime") {
        out.assign(1, m_frame);
        return true;
    }
    return false;
}

double Evaluator::evaluateAnimCurve(NodeId curve) {
    const Node& n = m_graph.node(curve);
    const bool timeInput = timeDrivenCurve(n);
    const char outKind = n.type.size() == std::string_view("animCurveTL").size() ? n.type.back() : 'U';

    // Key values are stored in the file's units; explicit tangent y (kiy/koy) is in Maya's internal
    // units (centimetres, radians) and tangent x in seconds for time-driven curves (checked against
    // spline tangents Maya wrote into files with degrees and 30 fps).
    double valueScale = 1.0;
    if (outKind == 'L') valueScale = m_graph.units.cmPerLinearUnit;
    else if (outKind == 'A') valueScale = m_graph.units.radiansPerAngleUnit;
    const double xScale = timeInput ? m_graph.units.framesPerSecond : 1.0;

    double x = m_frame;
    const bool inputConnected = m_graph.sourceOfCanonical(curve, "input") != nullptr;
    if (!timeInput || inputConnected) {
        std::vector<double> in;
        x = evaluatePlug(curve, "input", in) && !in.empty() ? in[0] : (timeInput ? m_frame : 0.0);
    }

    AnimCurveData data;
    data.tangentType = tangentTypeFromInt(m_graph.getInt(curve, "tangentType", int(TangentType::Auto)));
    data.weightedTangents = m_graph.getBool(curve, "weightedTangents", true);
    data.preInfinity = infinityTypeFromInt(m_graph.getInt(curve, "preInfinity", 0));
    data.postInfinity = infinityTypeFromInt(m_graph.getInt(curve, "postInfinity", 0));

    auto multiOf = [&](const char* name) -> const MultiStore* {
        const AttrData* a = m_graph.findAttr(curve, m_graph.canonicalPath(curve, {PlugSegment{name}}));
        return a ? &a->multi : nullptr;
    };
    std::vector<double> el;
    auto element = [&el](const MultiStore* m, uint32_t i, double& v) {
        if (!m || !m->numbers(i, el) || el.empty() || !std::isfinite(el[0])) return false;
        v = el[0];
        return true;
    };
    const MultiStore* ktv = multiOf("keyTimeValue");
    if (!ktv) return 0.0;
    const MultiStore* kit = multiOf("keyTanInType");
    const MultiStore* kot = multiOf("keyTanOutType");
    const MultiStore* kix = multiOf("keyTanInX");
    const MultiStore* kiy = multiOf("keyTanInY");
    const MultiStore* kox = multiOf("keyTanOutX");
    const MultiStore* koy = multiOf("keyTanOutY");
    const MultiStore* kbd = multiOf("keyBreakdown");
    std::vector<double> tv;
    for (uint32_t i : ktv->indices()) {
        if (!ktv->numbers(i, tv) || tv.size() < 2 || !std::isfinite(tv[0]) || !std::isfinite(tv[1])) continue;
        AnimKey k;
        k.time = tv[0];
        k.value = tv[1] * valueScale;
        double v = 0.0;
        if (element(kit, i, v)) k.inType = tangentTypeFromInt(int(v));
        if (element(kot, i, v)) k.outType = tangentTypeFromInt(int(v));
        double tx = 1.0, ty = 0.0;
        bool hasX = element(kix, i, tx), hasY = element(kiy, i, ty);
        if (hasX || hasY) {
            k.hasInTangent = true;
            k.inX = (hasX ? tx : 1.0) * xScale;
            k.inY = hasY ? ty : 0.0;
        }
        tx = 1.0;
        ty = 0.0;
        hasX = element(kox, i, tx);
        hasY = element(koy, i, ty);
        if (hasX || hasY) {
            k.hasOutTangent = true;
            k.outX = (hasX ? tx : 1.0) * xScale;
            k.outY = hasY ? ty : 0.0;
        }
        if (element(kbd, i, v)) k.breakdown = v != 0.0;
        data.keys.push_back(k);
    }
    return AnimCurve(std::move(data)).evaluate(x);
}

namespace {
// A read's numbers as one value, or `fallback` when the read found none.
double firstOr(bool read, const std::vector<double>& v, double fallback) { return read && !v.empty() ? v[0] : fallback; }
bool boolOr(bool read, const std::vector<double>& v, bool fallback) { return read && !v.empty() ? v[0] != 0.0 : fallback; }
int intOr(bool read, const std::vector<double>& v, int fallback) {
    return read && !v.empty() ? int(std::lround(v[0])) : fallback;
}
glm::dvec3 double3Or(bool read, const std::vector<double>& v, glm::dvec3 fallback) {
    return read && v.size() >= 3 ? glm::dvec3(v[0], v[1], v[2]) : fallback;
}
}  // namespace

double Evaluator::getDouble(NodeId node, std::string_view plugPath, double fallback) {
    return firstOr(numbers(node, plugPath, m_scratch), m_scratch, fallback);
}

bool Evaluator::getBool(NodeId node, std::string_view plugPath, bool fallback) {
    return boolOr(numbers(node, plugPath, m_scratch), m_scratch, fallback);
}

int Evaluator::getInt(NodeId node, std::string_view plugPath, int fallback) {
    return intOr(numbers(node, plugPath, m_scratch), m_scratch, fallback);
}

// Names of the Channel values, in their order.
const std::array<std::string_view, Evaluator::kChannels> Evaluator::kChannelNames = {
    "translate", "rotate", "scale", "shear", "rotateOrder", "rotateAxis", "rotatePivot", "rotatePivotTranslate",
    "scalePivot", "scalePivotTranslate", "inheritsTransform", "visibility", "lodVisibility", "intermediateObject",
    "template", "overrideEnabled", "overrideVisibility", "overrideDisplayType"};

const Evaluator::ChannelSpecs& Evaluator::channelSpecs(const NodeSchema& schema) {
    if (m_lastChannelSchema == &schema) return *m_lastChannelSpecs;
    auto [it, added] = m_channelSpecs.try_emplace(&schema);
    if (added)
        for (size_t c = 0; c < kChannels; ++c) {
            const AttrSpec* spec = schema.find(kChannelNames[c]);
            // Only whole attributes read this way; a component (never one of these in Maya's
            // schemas) takes the general path.
            it->second[c] = spec && spec->component < 0 ? spec : nullptr;
        }
    m_lastChannelSchema = &schema;
    m_lastChannelSpecs = &it->second;
    return it->second;
}

bool Evaluator::channel(NodeId node, Channel c, std::vector<double>& out) {
    if (node < m_graph.size()) {
        const Node& n = m_graph.node(node);
        if (n.schema && holdsStoredValues(node))
            if (const AttrSpec* spec = channelSpecs(*n.schema)[size_t(c)]) return m_graph.numbers(node, *spec, out);
    }
    return numbers(node, kChannelNames[size_t(c)], out);
}

glm::dvec3 Evaluator::channel3(NodeId node, Channel c, glm::dvec3 fallback) {
    return double3Or(channel(node, c, m_scratch), m_scratch, fallback);
}

bool Evaluator::channelBool(NodeId node, Channel c, bool fallback) {
    return boolOr(channel(node, c, m_scratch), m_scratch, fallback);
}

int Evaluator::channelInt(NodeId node, Channel c, int fallback) {
    return intOr(channel(node, c, m_scratch), m_scratch, fallback);
}

glm::dvec3 Evaluator::getDouble3(NodeId node, std::string_view plugPath, glm::dvec3 fallback) {
    return double3Or(numbers(node, plugPath, m_scratch), m_scratch, fallback);
}

glm::dmat4 Evaluator::localMatrix(NodeId transform) {
    const Node& n = m_graph.node(transform);
    return localMatrixUnder(transform, n.parents().empty() ? kNoNode : n.parents().front());
}

glm::dmat4 Evaluator::localMatrixUnder(NodeId id, NodeId dagParent) {
    const Node& n = m_graph.node(id);
    if (!isA(n, "transform")) return glm::dmat4(1.0);  // shapes live in their parent's space
    glm::dmat4 local(1.0);
    if (isA(n, "joint")) {
        JointAttrs j;
        j.translate = getDouble3(id, "translate", j.translate);
        j.rotate = getDouble3(id, "rotate", j.rotate);
        j.scale = getDouble3(id, "scale", j.scale);
        j.rotateOrder = getInt(id, "rotateOrder", 0);
        j.rotateAxis = getDouble3(id, "rotateAxis", j.rotateAxis);
        j.jointOrient = getDouble3(id, "jointOrient", j.jointOrient);
        j.segmentScaleCompensate = getBool(id, "segmentScaleCompensate", true);
        // Maya connects parentJoint.scale → joint.inverseScale when joints are parented. Without that
        // connection (or a stored value) the parent joint's scale is compensated directly.
        bool explicitInverse = false;
        for (const char* p : {"inverseScale", "inverseScaleX", "inverseScaleY", "inverseScaleZ"})
            explicitInverse = explicitInverse || m_graph.source(id, p).has_value() || m_graph.value(id, p) != nullptr;
        if (explicitInverse) j.inverseScale = getDouble3(id, "inverseScale", j.inverseScale);
        else if (dagParent != kNoNode && isA(m_graph.node(dagParent), "joint"))
            j.inverseScale = getDouble3(dagParent, "scale", glm::dvec3(1.0));
        local = jointMatrix(j);
    } else {
        TransformAttrs t;
        t.translate = channel3(id, Channel::Translate, t.translate);
        t.rotate = channel3(id, Channel::Rotate, t.rotate);
        t.scale = channel3(id, Channel::Scale, t.scale);
        t.shear = channel3(id, Channel::Shear, t.shear);
        t.rotateOrder = channelInt(id, Channel::RotateOrder, 0);
        t.rotateAxis = channel3(id, Channel::RotateAxis, t.rotateAxis);
        t.rotatePivot = channel3(id, Channel::RotatePivot, t.rotatePivot);
        t.rotatePivotTranslate = channel3(id, Channel::RotatePivotTranslate, t.rotatePivotTranslate);
        t.scalePivot = channel3(id, Channel::ScalePivot, t.scalePivot);
        t.scalePivotTranslate = channel3(id, Channel::ScalePivotTranslate, t.scalePivotTranslate);
        local = transformMatrix(t);
    }
    // Maya 2020+ offsetParentMatrix (row-major, row vectors) sits between the local and the parent:
    // world = local · offsetParentMatrix · parentWorld.
    for (const char* name : {"offsetParentMatrix", "opm"}) {
        if (const Value* v = m_graph.value(id, name))
            if (auto* nums = std::get_if<Numbers>(v); nums && nums->values.size() == 16) {
                // Reading Maya's row-major numbers column by column transposes them into column form.
                const glm::dmat4 offset = glm::make_mat4(nums->values.data());
                local = offset * local;
                break;
            }
    }
    return local;
}

bool Evaluator::hasSinglePath(NodeId id) {
    if (m_singlePath.size() != m_graph.size()) m_singlePath.assign(m_graph.size(), 0);
    // Walk up while each node has exactly one parent and no world instance of its own; every node
    // on the walk gets the answer of where it stopped, so each node is walked once per Evaluator.
    std::vector<NodeId> walked;
    NodeId at = id;
    while (m_singlePath[at] == 0) {
        const Node& n = m_graph.node(at);
        if (n.parents().empty()) m_singlePath[at] = 1;
        else if (n.parents().size() > 1 || n.underWorld || walked.size() > m_graph.size()) m_singlePath[at] = 2;
        else {
            walked.push_back(at);
            at = n.parents().front();
        }
    }
    for (NodeId w : walked) m_singlePath[w] = m_singlePath[at];
    return m_singlePath[id] == 1;
}

glm::dmat4 Evaluator::worldMatrix(const std::vector<NodeId>& dagPath) {
    // The nodes of a path that have a single DAG path form its head (below an instanced node every
    // node has several paths), and their world matrices are cached: start after the deepest cached
    // one, so asking for every node of a deep chain costs one pass over it.
    glm::dmat4 world(1.0);
    size_t begin = 0;
    for (size_t k = dagPath.size(); k-- > 0;) {
        const NodeId id = dagPath[k];
        if (id >= m_graph.size()) return glm::dmat4(1.0);
        if (!hasSinglePath(id)) continue;
        if (auto it = m_worldOfSinglePath.find(id); it != m_worldOfSinglePath.end()) {
            world = it->second;
            begin = k + 1;
            break;
        }
    }
    for (size_t k = begin; k < dagPath.size(); ++k) {
        const NodeId id = dagPath[k];
        if (id >= m_graph.size()) return glm::dmat4(1.0);
        const glm::dmat4 local = localMatrixUnder(id, k > 0 ? dagPath[k - 1] : kNoNode);
        if (isA(m_graph.node(id), "transform") && !channelBool(id, Channel::InheritsTransform, true)) world = local;
        else world = world * local;
        if (hasSinglePath(id)) m_worldOfSinglePath.emplace(id, world);
    }
    return world;
}

bool Evaluator::nodeVisible(NodeId id) {
    // Remembered per node: a shape instanced along many paths shares the nodes above it.
    if (m_nodeVisible.size() != m_graph.size()) m_nodeVisible.assign(m_graph.size(), 0);
    if (m_nodeVisible[id] == 0) m_nodeVisible[id] = nodeVisibleUncached(id) ? 1 : 2;
    return m_nodeVisible[id] == 1;
}

bool Evaluator::nodeVisibleUncached(NodeId id) {
    // Templated objects are drawn as wireframes for reference and never rendered.
    if (!channelBool(id, Channel::Visibility, true) || !channelBool(id, Channel::LodVisibility, true) ||
        channelBool(id, Channel::IntermediateObject, false) || channelBool(id, Channel::Template, false))
        return false;
    // Drawing overrides: a display layer drives the node's drawOverride through its drawInfo;
    // otherwise the node's own overrideEnabled/overrideVisibility/overrideDisplayType apply.
    // Display type 1 is a template.
    if (auto layer = m_graph.source(id, "drawOverride"); layer && isA(m_graph.node(layer->node), "displayLayer")) {
        if (!getBool(layer->node, "enabled", true)) return true;
        return getBool(layer->node, "visibility", true) && getInt(layer->node, "displayType", 0) != 1;
    }
    if (!channelBool(id, Channel::OverrideEnabled, false)) return true;
    return channelBool(id, Channel::OverrideVisibility, true) && channelInt(id, Channel::OverrideDisplayType, 0) != 1;
}

bool Evaluator::visible(const std::vector<NodeId>& dagPath) {
    for (NodeId id : dagPath)
        if (id >= m_graph.size() || !nodeVisible(id)) return false;
    return !dagPath.empty();
}

std::string Evaluator::hiddenReason(const std::vector<NodeId>& dagPath) {
    // The first node on the path that hides it, found in one pass.
    for (NodeId id : dagPath) {
        if (id >= m_graph.size()) return "hidden";
        if (!nodeVisible(id))
            return "hidden by '" + util::excerpt(m_graph.node(id).name) +
                   "' (visibility, a template, a drawing override or a display layer)";
    }
    return dagPath.empty() ? "hidden" : std::string();
}

}  // namespace pushpin::scene
