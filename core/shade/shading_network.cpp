// Compiles a shading network into a flat program and evaluates it over batches
// (core/shade/shading_network.h).
//
// compile() walks upstream from the surface shader depth-first; a node is appended to the program
// after everything it reads, so the program order is a topological order. Every input channel of
// a compiled node is bound once, here, to one of:
// - another node's output (a register, or for kernel-less nodes the input or renderer field that
//   output passes through), with component selection (outColorR → a float input) and broadcast
//   (a float output → every channel of a colour input);
// - a renderer field of the batch (an unconnected normalCamera, uvCoord … input, nodes.md §8);
// - a constant read through the Evaluator at its frame: an unconnected value, or one driven by an
//   animCurve / unitConversion / time node or by a node pushpin does not evaluate.
// evaluate() then only walks the node list calling one kernel per node: no lookups, no allocation
// once the scratch registers have their size.
#include "core/shade/shading_network.h"

#include "core/shade/node_library.h"
#include "core/util/format.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <unordered_map>

namespace pushpin::shade {

// Registers 0 and 1 hold the derived renderer fields facingRatio and flippedNormal.
constexpr uint32_t kFacingRatioRegister = 0;
constexpr uint32_t kFlippedRegister = 1;
constexpr uint32_t kFirstFreeRegister = 2;

struct ShadingNetwork::Program {
    std::vector<CompiledNode> nodes;  // topological order
    std::vector<ChannelRef> inputs;   // every node's input channels, see CompiledNode::firstInput
    std::vector<float> constants{0.0f};
    uint32_t registerCount = kFirstFreeRegister;
    bool usesDerivedFields = false;  // facingRatio / flippedNormal are read
    std::array<ChannelRef, 3> color{};
    std::array<ChannelRef, 3> transparency{};
};

namespace {

using scene::NodeId;
using scene::kNoNode;

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// Nodes whose outputs are one value per frame, which the Evaluator computes.
bool isFrameConstantSource(const scene::Node& n) {
    return startsWith(n.type, "animCurve") || n.type == "unitConversion" || n.type == "time" ||
           (n.schema && (n.schema->isA("unitConversion") || n.schema->isA("time")));
}

// Where a plug path lands on a node type's ports.
struct PortMatch {
    int port = -1;
    int64_t element = -1;  // multi ports
    int component = -1;    // -1: the whole port
};

PortMatch matchPort(const std::vector<PortSpec>& ports, std::string_view path) {
    PortMatch m;
    auto segs = scene::parsePlugPath(path);
    if (!segs || segs->empty() || segs->size() > 2) return m;
    const scene::PlugSegment& s0 = segs->front();
    if (s0.indexed() && s0.first != s0.last) return m;  // a range of elements: not a single plug
    for (size_t p = 0; p < ports.size(); ++p) {
        const PortSpec& port = ports[p];
        const bool named = s0.name == port.longName || s0.name == port.shortName;
        if (segs->size() == 1) {
            if (named && port.multi == s0.indexed()) {
                m.port = int(p);
                m.element = s0.first;
                return m;
            }
            if (!port.multi && !s0.indexed()) {
                for (int k = 0; k < port.width && port.width > 1; ++k) {
                    if (s0.name == port.childLong[size_t(k)] || s0.name == port.childShort[size_t(k)]) {
                        m.port = int(p);
                        m.component = k;
                        return m;
                    }
                }
            }
        } else if (named && port.multi && s0.indexed()) {
            const scene::PlugSegment& s1 = (*segs)[1];
            for (int k = 0; k < port.width && port.width > 1; ++k) {
                if (!s1.indexed() && (s1.name == port.childLong[size_t(k)] || s1.name == port.childShort[size_t(k)])) {
                    m.port = int(p);
                    m.element = s0.first;
                    m.component = k;
                    return m;
                }
            }
        }
    }
    return m;
}

// Channel offset of output port `port` within a node's outputs.
uint32_t outputOffset(const NodeType& t, int port) {
    uint32_t off = 0;
    for (int p = 0; p < port; ++p) off += uint32_t(t.outputs[size_t(p)].width);
    return off;
}

uint32_t inputOffset(const NodeType& t, int port) {
    uint32_t off = 0;
    for (int p = 0; p < port; ++p)
        if (!t.inputs[size_t(p)].multi) off += uint32_t(t.inputs[size_t(p)].width);
    return off;
}

class Compiler {
public:
    Compiler(scene::Evaluator& ev, std::vector<std::string>& notes, ShadingNetwork::Program& program)
        : m_ev(ev), m_graph(ev.graph()), m_notes(notes), m_program(program) {}

    static constexpr int kCycle = -2;

    // Compiles `id` (whose type is in the node library) and everything upstream of it; returns its
    // index in the program, or kCycle when `id` is being compiled further down the stack.
    int compileNode(NodeId id);

    // Output channels of a compiled node, flattened over its output ports.
    const std::vector<ChannelRef>& outputs(int index) const { return m_outputs[size_t(index)]; }

    ChannelRef constant(float v) {
        m_program.constants.push_back(v);
        return ChannelRef{ChannelRef::Kind::Constant, uint32_t(m_program.constants.size() - 1)};
    }

    // A value read at the frame, or `fallback` (with a note) when it is NaN/Inf.
    float checkedConstant(NodeId id, const std::string& attr, double value, float fallback) {
        if (std::isfinite(value) && std::abs(value) <= double(std::numeric_limits<float>::max()))
            return float(value);
        note("'" + m_graph.node(id).name + "." + attr + "' is " + (std::isnan(value) ? "NaN" : "infinite") +
             "; using its default " + util::formatNumber(fallback));
        return fallback;
    }

    void note(const std::string& text) {
        if (m_noted.insert(text).second) m_notes.push_back(text);
    }

    void noteUnsupported(const scene::Node& n) {
        note("unsupported shading node '" + n.name + "' (type " + n.type + "): its outputs read as their stored values");
    }

    // The library type that evaluates `id`: its own, or lambert's for other materials derived from
    // lambert (anisotropic …), noted once; nullptr when pushpin does not evaluate it.
    const NodeType* typeOf(NodeId id) {
        const scene::Node& n = m_graph.node(id);
        if (const NodeType* t = findNodeType(n.type)) return t;
        if (n.schema && n.schema->isA("lambert")) {
            note("material '" + n.name + "' (type " + n.type +
                 ") is not supported: it is shaded as a lambert with its colour, transparency, ambient, "
                 "incandescence and diffuse values");
            return findNodeType("lambert");
        }
        return nullptr;
    }

    // A unitConversion between shading nodes is read as a constant; say so.
    void noteConversionOfShadingOutput(NodeId conversion) {
        const auto src = m_graph.source(conversion, "input");
        if (!src || !typeOf(src->node)) return;
        const scene::Node& n = m_graph.node(conversion);
        note("unitConversion '" + n.name + "' converts a per-sample shading value; it reads as its value at the frame");
    }

    // Numbers of `node.path` at the frame; false when the plug has no value and no default.
    bool read(NodeId id, const std::string& path, std::vector<double>& out) {
        return m_ev.numbers(id, path, out) && !out.empty();
    }

private:
    struct Source {
        scene::Plug src;
        std::string dstPath;
        bool whole = false;  // connected to the whole port, not one component
    };
    using ChannelKey = std::tuple<int, int64_t, int>;  // port, element, component (-1 whole)

    ChannelRef bindInput(NodeId id, const NodeType& type, int port, int64_t element, int component,
                         const std::map<ChannelKey, Source>& sources);
    ChannelRef constantInput(NodeId id, const PortSpec& port, int64_t element, int component, const Source* source);
    ChannelRef fieldRef(Field f) {
        if (f == Field::FacingRatio || f == Field::FlippedNormal) m_program.usesDerivedFields = true;
        return ChannelRef{ChannelRef::Kind::Field, uint32_t(f)};
    }
    std::vector<int64_t> multiElements(NodeId id, const PortSpec& port, const std::map<ChannelKey, Source>& sources,
                                       int portIndex) const;

    scene::Evaluator& m_ev;
    const scene::Graph& m_graph;
    std::vector<std::string>& m_notes;
    ShadingNetwork::Program& m_program;
    std::unordered_map<NodeId, int> m_index;  // compiled node index, or kCycle while in progress
    std::vector<std::vector<ChannelRef>> m_outputs;
    std::set<std::string> m_noted;
};

int Compiler::compileNode(NodeId id) {
    if (auto it = m_index.find(id); it != m_index.end()) return it->second;
    const scene::Node& n = m_graph.node(id);
    const NodeType& type = *typeOf(id);
    m_index[id] = kCycle;

    // Incoming connections, by the port channel they land on.
    std::map<ChannelKey, Source> sources;
    for (const scene::Connection* c : m_graph.inputs(id)) {
        const PortMatch m = matchPort(type.inputs, c->dst.path);
        if (m.port < 0) {
            const scene::Node& src = m_graph.node(c->src.node);
            note("input '" + n.name + "." + c->dst.path + "' is not evaluated by pushpin; its connection from '" +
                 src.name + "." + c->src.path + "' is ignored");
            continue;
        }
        sources[{m.port, m.element, m.component}] = Source{c->src, c->dst.path, m.component < 0};
    }

    CompiledNode node;
    node.type = &type;
    node.node = id;
    std::vector<ChannelRef> inputs;
    inputs.reserve(size_t(type.inputChannels()));
    for (size_t p = 0; p < type.inputs.size(); ++p) {
        const PortSpec& port = type.inputs[p];
        if (port.multi) continue;
        for (int k = 0; k < port.width; ++k) inputs.push_back(bindInput(id, type, int(p), -1, k, sources));
    }
    size_t multiPort = 0;
    for (size_t p = 0; p < type.inputs.size(); ++p) {
        const PortSpec& port = type.inputs[p];
        if (!port.multi) continue;
        const std::vector<int64_t> elements = multiElements(id, port, sources, int(p));
        if (multiPort < node.multiCount.size()) node.multiCount[multiPort++] = uint32_t(elements.size());
        for (int64_t e : elements)
            for (int k = 0; k < port.width; ++k) inputs.push_back(bindInput(id, type, int(p), e, k, sources));
    }

    for (size_t i = 0; i < type.params.size() && i < node.params.size(); ++i) {
        const EnumParam& param = type.params[i];
        std::vector<double> v;
        double value = param.defaultValue;
        if (read(id, param.longName, v) || read(id, param.shortName, v)) value = v[0];
        node.params[i] = int(std::lround(checkedConstant(id, param.longName, value, float(param.defaultValue))));
    }

    node.firstInput = uint32_t(m_program.inputs.size());
    node.inputCount = uint32_t(inputs.size());
    m_program.inputs.insert(m_program.inputs.end(), inputs.begin(), inputs.end());

    std::vector<ChannelRef> outs;
    if (type.kernel) {
        node.firstOutput = m_program.registerCount;
        const uint32_t channels = uint32_t(type.outputChannels());
        m_program.registerCount += channels;
        for (uint32_t k = 0; k < channels; ++k)
            outs.push_back(ChannelRef{ChannelRef::Kind::Register, node.firstOutput + k});
    } else {
        for (const PortSpec& port : type.outputs) {
            for (int k = 0; k < port.width; ++k) {
                if (port.aliasOf >= 0)
                    outs.push_back(inputs[inputOffset(type, port.aliasOf) + uint32_t(k)]);
                else if (port.fields[size_t(k)] != Field::None)
                    outs.push_back(fieldRef(port.fields[size_t(k)]));
                else
                    outs.push_back(constant(port.defaults[size_t(k)]));
            }
        }
    }

    const int index = int(m_program.nodes.size());
    m_program.nodes.push_back(node);
    m_outputs.push_back(std::move(outs));
    m_index[id] = index;
    return index;
}

std::vector<int64_t> Compiler::multiElements(NodeId id, const PortSpec& port,
                                             const std::map<ChannelKey, Source>& sources, int portIndex) const {
    std::set<int64_t> found;
    for (const auto& [key, src] : sources)
        if (std::get<0>(key) == portIndex && std::get<1>(key) >= 0) found.insert(std::get<1>(key));
    for (const auto& [key, data] : m_graph.node(id).attrs) {
        auto segs = scene::parsePlugPath(key);
        if (!segs || segs->empty()) continue;
        const scene::PlugSegment& s0 = segs->front();
        if (s0.name != port.longName && s0.name != port.shortName) continue;
        if (s0.indexed()) {
            for (int64_t e = s0.first; e <= s0.last && e - s0.first < 4096; ++e) found.insert(e);
        } else if (segs->size() == 1) {
            for (uint32_t e : data.multi.indices()) found.insert(int64_t(e));
        }
    }
    return {found.begin(), found.end()};
}

ChannelRef Compiler::bindInput(NodeId id, const NodeType& type, int portIndex, int64_t element, int component,
                               const std::map<ChannelKey, Source>& sources) {
    const PortSpec& port = type.inputs[size_t(portIndex)];
    const Source* source = nullptr;
    if (auto it = sources.find({portIndex, element, component}); it != sources.end()) source = &it->second;
    else if (auto whole = sources.find({portIndex, element, -1}); whole != sources.end()) source = &whole->second;

    if (!source) {
        if (port.fields[size_t(component)] != Field::None) return fieldRef(port.fields[size_t(component)]);
        return constantInput(id, port, element, component, nullptr);
    }

    const scene::Node& src = m_graph.node(source->src.node);
    // A renderer attribute driven by something pushpin does not evaluate per sample (a bump2d
    // before textures exist, a static value) keeps the renderer's value, not a constant.
    const Field implicitField = port.fields[size_t(component)];
    const NodeType* srcType = typeOf(source->src.node);
    if (!srcType) {
        if (implicitField != Field::None) {
            if (!isFrameConstantSource(src)) noteUnsupported(src);
            return fieldRef(implicitField);
        }
        if (!isFrameConstantSource(src)) noteUnsupported(src);
        else if (src.type == "unitConversion" || (src.schema && src.schema->isA("unitConversion")))
            noteConversionOfShadingOutput(source->src.node);
        return constantInput(id, port, element, component, source);
    }
    const PortMatch m = matchPort(srcType->outputs, source->src.path);
    if (m.port < 0 || m.element >= 0) {
        note("output '" + src.name + "." + source->src.path + "' (type " + src.type +
             ") is not computed by pushpin; it reads its stored value");
        if (implicitField != Field::None) return fieldRef(implicitField);
        return constantInput(id, port, element, component, source);
    }
    const int index = compileNode(source->src.node);
    if (index == kCycle) {
        const scene::Node& n = m_graph.node(id);
        note("connection cycle: '" + src.name + "." + source->src.path + "' depends on '" + n.name +
             "'; '" + n.name + "." + source->dstPath + "' reads its stored value");
        return constantInput(id, port, element, component, source);
    }
    const PortSpec& srcPort = srcType->outputs[size_t(m.port)];
    int selected;
    if (m.component >= 0) selected = m.component;            // outColorR → this channel
    else if (srcPort.width == 1) selected = 0;               // a float broadcast to every channel
    else if (component < srcPort.width) selected = component;
    else return constant(0.0f);                              // a 2-channel source has no third channel
    return outputs(index)[outputOffset(*srcType, m.port) + uint32_t(selected)];
}

ChannelRef Compiler::constantInput(NodeId id, const PortSpec& port, int64_t element, int component,
                                   const Source* source) {
    const float fallback = port.defaults[size_t(component)];
    std::vector<double> v;
    double value = fallback;
    bool found = false;
    const std::string attr =
        port.width > 1 && !port.childLong[size_t(component)].empty() ? port.childLong[size_t(component)] : port.longName;
    if (source) {
        // The Evaluator follows the connection (animCurve at the frame, unitConversion, stored values).
        if (read(id, source->dstPath, v)) {
            if (!source->whole) value = v[0], found = true;
            else if (size_t(component) < v.size()) value = v[size_t(component)], found = true;
            else if (v.size() == 1) value = v[0], found = true;
        }
    }
    if (!found) {
        const std::string suffix = element >= 0 ? "[" + std::to_string(element) + "]" : "";
        // A stored component (colorR, or on nodes without a schema the short ix / i3[0].i3x) first,
        // then the whole value.
        if (port.width > 1) {
            for (const std::string* parent : {&port.longName, &port.shortName}) {
                for (const std::string* child : {&port.childLong[size_t(component)], &port.childShort[size_t(component)]}) {
                    const std::string path = element >= 0 ? *parent + suffix + "." + *child : *child;
                    if (!found && read(id, path, v)) value = v[0], found = true;
                }
                if (element < 0) break;  // plain children do not depend on the parent's name
            }
        }
        for (const std::string* parent : {&port.longName, &port.shortName}) {
            if (found) break;
            if (read(id, *parent + suffix, v)) {
                if (size_t(component) < v.size()) value = v[size_t(component)], found = true;
                else if (v.size() == 1) value = v[0], found = true;
            }
        }
    }
    return constant(checkedConstant(id, attr, value, fallback));
}

ChannelRef selectChannel(const std::vector<ChannelRef>& outs, uint32_t offset, int width, int k, Compiler& c) {
    if (width == 1) return outs[offset];
    if (k < width) return outs[offset + uint32_t(k)];
    return c.constant(0.0f);
}

bool mayBeNonZero(const ChannelRef& r, const std::vector<float>& constants) {
    return r.kind != ChannelRef::Kind::Constant || constants[r.index] != 0.0f;
}

}  // namespace

ShadingNetwork::ShadingNetwork() = default;
ShadingNetwork::~ShadingNetwork() = default;

size_t ShadingNetwork::nodeCount() const { return m_program ? m_program->nodes.size() : 0; }

std::shared_ptr<const ShadingNetwork> ShadingNetwork::compile(scene::Evaluator& ev, scene::NodeId surfaceShader,
                                                              std::vector<std::string>& notes) {
    auto net = std::make_shared<ShadingNetwork>();
    net->m_program = std::make_unique<Program>();
    Program& prog = *net->m_program;
    const ChannelRef zero{ChannelRef::Kind::Constant, 0};
    prog.color = {zero, zero, zero};
    prog.transparency = {zero, zero, zero};
    const scene::Graph& g = ev.graph();
    if (surfaceShader == kNoNode || surfaceShader >= g.size()) return net;  // black and opaque

    const scene::Node& root = g.node(surfaceShader);
    net->m_rootName = root.name;
    Compiler c(ev, notes, prog);
    const NodeType* type = c.typeOf(surfaceShader);
    if (!type) {
        // Not evaluated: its stored outColor / outTransparency (else black, opaque).
        c.noteUnsupported(root);
        std::vector<double> v;
        for (int k = 0; k < 3; ++k) {
            if (c.read(surfaceShader, "outColor", v) && size_t(k) < v.size())
                prog.color[size_t(k)] = c.constant(c.checkedConstant(surfaceShader, "outColor", v[size_t(k)], 0.0f));
            if (c.read(surfaceShader, "outTransparency", v) && size_t(k) < v.size())
                prog.transparency[size_t(k)] =
                    c.constant(c.checkedConstant(surfaceShader, "outTransparency", v[size_t(k)], 0.0f));
        }
        for (int k = 0; k < 3; ++k) net->m_mayBeTransparent |= mayBeNonZero(prog.transparency[size_t(k)], prog.constants);
        return net;
    }

    const int index = c.compileNode(surfaceShader);
    const std::vector<ChannelRef>& outs = c.outputs(index);
    // The shading group reads outColor, or the first output of a node that has none (a utility
    // wired straight into surfaceShader).
    int colorPort = type->findOutput("outColor");
    if (colorPort < 0 && !type->outputs.empty()) colorPort = 0;
    if (colorPort >= 0)
        for (int k = 0; k < 3; ++k)
            prog.color[size_t(k)] = selectChannel(outs, outputOffset(*type, colorPort),
                                                  type->outputs[size_t(colorPort)].width, k, c);
    if (const int tPort = type->findOutput("outTransparency"); tPort >= 0)
        for (int k = 0; k < 3; ++k)
            prog.transparency[size_t(k)] = selectChannel(outs, outputOffset(*type, tPort),
                                                         type->outputs[size_t(tPort)].width, k, c);
    if (type->transparencyInput >= 0) {
        const CompiledNode& node = prog.nodes[size_t(index)];
        const uint32_t off = node.firstInput + inputOffset(*type, type->transparencyInput);
        for (uint32_t k = 0; k < uint32_t(type->inputs[size_t(type->transparencyInput)].width); ++k)
            net->m_mayBeTransparent |= mayBeNonZero(prog.inputs[off + k], prog.constants);
    } else {
        for (int k = 0; k < 3; ++k) net->m_mayBeTransparent |= mayBeNonZero(prog.transparency[size_t(k)], prog.constants);
    }
    return net;
}

void ShadingNetwork::evaluate(const ShadingBatch& batch, std::span<const Light> lights, ShadingScratch& scratch,
                              ShadingResult& out) const {
    const int count = std::clamp(batch.count, 0, kBatchSize);
    if (!m_program) {
        for (int i = 0; i < count; ++i) out.cr[i] = out.cg[i] = out.cb[i] = out.tr[i] = out.tg[i] = out.tb[i] = 0.0f;
        return;
    }
    const Program& prog = *m_program;
    const size_t need = size_t(prog.registerCount) * kBatchSize;
    if (scratch.registers.size() < need) scratch.registers.resize(need);
    float* regs = scratch.registers.data();

    static const float kZeros[kBatchSize] = {};
    static_assert(size_t(Field::Count) == 31, "one entry per Field below");
    const float* fields[size_t(Field::Count)] = {
        kZeros,
        batch.px, batch.py, batch.pz,
        batch.nx, batch.ny, batch.nz,
        batch.gx, batch.gy, batch.gz,
        batch.rx, batch.ry, batch.rz,
        batch.u, batch.v,
        batch.wx, batch.wy, batch.wz,
        batch.ox, batch.oy, batch.oz,
        batch.tux, batch.tuy, batch.tuz,
        batch.tvx, batch.tvy, batch.tvz,
        batch.pixelX, batch.pixelY,
        regs + size_t(kFacingRatioRegister) * kBatchSize,
        regs + size_t(kFlippedRegister) * kBatchSize,
    };
    if (prog.usesDerivedFields) {
        float* facing = regs + size_t(kFacingRatioRegister) * kBatchSize;
        float* flipped = regs + size_t(kFlippedRegister) * kBatchSize;
        for (int i = 0; i < count; ++i) {
            // The normal faces the eye, so −N·rayDirection is the cosine toward the viewer.
            const float d = -(batch.nx[i] * batch.rx[i] + batch.ny[i] * batch.ry[i] + batch.nz[i] * batch.rz[i]);
            facing[i] = d > 0.0f ? std::min(d, 1.0f) : 0.0f;
            flipped[i] = batch.flipped[i] ? 1.0f : 0.0f;
        }
    }

    KernelContext ctx{batch, count, lights, scratch.lightSamples, fields, regs, prog.constants.data(), prog.inputs.data()};
    for (const CompiledNode& node : prog.nodes)
        if (node.type->kernel) node.type->kernel(ctx, node);

    // Results, with anything non-finite (from non-finite batch data) turned into 0 so it cannot
    // reach a pixel.
    float* dst[6] = {out.cr, out.cg, out.cb, out.tr, out.tg, out.tb};
    for (int c = 0; c < 6; ++c) {
        const Chan ch = ctx.channel(c < 3 ? prog.color[size_t(c)] : prog.transparency[size_t(c - 3)]);
        for (int i = 0; i < count; ++i) {
            const float v = ch[i];
            dst[c][i] = std::isfinite(v) ? v : 0.0f;
        }
    }
}

}  // namespace pushpin::shade
