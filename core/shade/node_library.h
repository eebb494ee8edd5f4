// core/shade/node_library.h: the shading node types pushpin evaluates, described as data (ports
// with Maya's long and short names, defaults, renderer-filled fields) plus one kernel per type
// that runs over a whole batch. The network compiler (shading_network.cpp) binds every input
// channel to a constant, another node's output register or a ShadingBatch array, and calls the
// kernel once per batch (STYLE.md §24–26: dispatch once per node per batch, no allocation).
// Adding a node type (e.g. a texture) = one NodeType entry with its kernel, registered in
// node_library.cpp.
// Thread safety: the type table is built once on first use and read-only afterwards.
#pragma once

#include "core/scene/graph.h"
#include "core/shade/light.h"
#include "core/shade/shading_batch.h"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::shade {

// Per-sample values the renderer supplies (reference/nodes.md §8). The first group are arrays of
// the ShadingBatch; FacingRatio and FlippedNormal are derived from it once per batch.
enum class Field : uint8_t {
    None,
    PointCameraX, PointCameraY, PointCameraZ,
    NormalCameraX, NormalCameraY, NormalCameraZ,
    GeometricNormalX, GeometricNormalY, GeometricNormalZ,
    RayDirectionX, RayDirectionY, RayDirectionZ,
    UCoord, VCoord,
    PointWorldX, PointWorldY, PointWorldZ,
    PointObjX, PointObjY, PointObjZ,
    TangentUX, TangentUY, TangentUZ,
    TangentVX, TangentVY, TangentVZ,
    PixelCenterX, PixelCenterY,
    FacingRatio,    // max(0, −N·rayDirection)
    FlippedNormal,  // 1 where the normal was turned toward the eye, else 0
    Count
};

// Where one float channel of an input (or output) comes from.
struct ChannelRef {
    enum class Kind : uint8_t { Constant, Register, Field };
    Kind kind = Kind::Constant;
    uint32_t index = 0;  // into Program constants, register number, or Field value
};

// A channel as a kernel reads it: p[i & mask], mask 0 for a constant (one value for every
// sample), ~0 for an array. Branch-free, the same code for both.
struct Chan {
    const float* p = nullptr;
    uint32_t mask = 0;
    float operator[](int i) const { return p[uint32_t(i) & mask]; }
};

struct NodeType;
struct KernelContext;

// One node of a compiled program. Input channels are laid out port by port in declaration order
// (width channels each), multi ports last, element after element; output channels likewise.
struct CompiledNode {
    const NodeType* type = nullptr;
    scene::NodeId node = scene::kNoNode;
    uint32_t firstInput = 0;   // into the program's input ChannelRefs
    uint32_t inputCount = 0;
    uint32_t firstOutput = 0;  // first register written (kernel nodes), outputs are consecutive
    std::array<int, 4> params{};              // enum attributes read at the frame (e.g. operation)
    std::array<uint32_t, 3> multiCount{};     // elements per multi input port, in port order
};

using Kernel = void (*)(const KernelContext& ctx, const CompiledNode& node);

// Everything a kernel may touch while it runs. Registers are float[kBatchSize] arrays.
struct KernelContext {
    const ShadingBatch& batch;
    int count;  // samples in use, 0..kBatchSize
    std::span<const Light> lights;
    LightSamples& lightSamples;  // working space for illuminate()
    const float* const* fields;  // Field → array (kBatchSize floats)
    float* registers;
    const float* constants;
    const ChannelRef* inputs;

    Chan channel(const ChannelRef& r) const {
        switch (r.kind) {
            case ChannelRef::Kind::Constant: return Chan{constants + r.index, 0u};
            case ChannelRef::Kind::Register: return Chan{registers + size_t(r.index) * kBatchSize, ~0u};
            case ChannelRef::Kind::Field: return Chan{fields[r.index], ~0u};
        }
        return Chan{constants, 0u};
    }
    Chan in(const CompiledNode& n, uint32_t channelIndex) const { return channel(inputs[n.firstInput + channelIndex]); }
    float* out(const CompiledNode& n, uint32_t channelIndex) const {
        return registers + size_t(n.firstOutput + channelIndex) * kBatchSize;
    }
};

struct PortSpec {
    std::string longName, shortName;
    int width = 1;                          // 1, 2 or 3 channels
    std::array<std::string, 3> childLong;   // component children (colorR, inputX …); empty for scalars
    std::array<std::string, 3> childShort;
    std::array<float, 3> defaults{};
    // Inputs: filled by the renderer when unconnected (normalCamera …). Outputs of kernel-less
    // nodes: the renderer value the output is (samplerInfo).
    std::array<Field, 3> fields{Field::None, Field::None, Field::None};
    bool multi = false;  // an array input (plusMinusAverage input3D[i]); always after fixed ports
    int aliasOf = -1;    // outputs of kernel-less nodes: the input port passed through (surfaceShader)

    bool implicit() const { return fields[0] != Field::None; }
};

struct EnumParam {
    std::string longName, shortName;
    int defaultValue = 0;
};

struct NodeType {
    std::string name;  // Maya node type
    std::vector<PortSpec> inputs;
    std::vector<PortSpec> outputs;
    std::vector<EnumParam> params;  // at most 4, read at the frame into CompiledNode::params
    // Writes every output channel into consecutive registers. nullptr: each output is an input
    // passed through (aliasOf) or a renderer field.
    Kernel kernel = nullptr;
    int transparencyInput = -1;  // input port deciding outTransparency (for mayBeTransparent)

    int inputChannels() const;   // fixed (non-multi) input channels
    int outputChannels() const;
    int findInput(std::string_view longName) const;   // port index or -1
    int findOutput(std::string_view longName) const;
};

// Port builders. Colour children are <long>R/G/B and <short>r/g/b; vector children use `suffixes`
// (e.g. "XYZ", or "xyz" as plusMinusAverage names them).
PortSpec scalarPort(const char* longName, const char* shortName, float value);
PortSpec colorPort(const char* longName, const char* shortName, float r, float g, float b);
PortSpec vectorPort(const char* longName, const char* shortName, const char* suffixes, float x, float y, float z);
PortSpec vector2Port(const char* longName, const char* shortName, const char* suffixes, float x, float y);
// A renderer attribute (nodes.md §8) by its long name: normalCamera, pointCamera, pointWorld,
// pointObj, rayDirection, uvCoord, tangentUCamera, tangentVCamera, pixelCenter, facingRatio,
// flippedNormal. Throws pushpin::Error for any other name (a programming error in a table).
PortSpec rendererPort(const char* longName, const char* shortName);

// The type description, or nullptr when pushpin does not evaluate that node type.
const NodeType* findNodeType(std::string_view type);

namespace detail {
void addMaterialTypes(std::vector<NodeType>& types);  // materials.cpp
void addUtilityTypes(std::vector<NodeType>& types);   // utility_nodes.cpp
}  // namespace detail

}  // namespace pushpin::shade
