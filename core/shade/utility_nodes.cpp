// Maya's utility nodes as batch kernels (reference/nodes.md §7): samplerInfo, reverse,
// multiplyDivide, blendColors, clamp, condition, plusMinusAverage, setRange, luminance,
// gammaCorrect. Where nodes.md leaves a case open (division by zero, an empty old range, a
// non-positive gamma) the choice is written next to the code.
#include "core/shade/node_library.h"

#include <algorithm>
#include <cmath>

namespace pushpin::shade::detail {

namespace {

// Every NaN a kernel could make from finite inputs (0/0, pow of a negative base) becomes 0.
inline float finiteOr0(float v) { return std::isfinite(v) ? v : 0.0f; }

// reverse: output = 1 − input, per component.
void reverseKernel(const KernelContext& ctx, const CompiledNode& node) {
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan in = ctx.in(node, c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) out[i] = 1.0f - in[i];
    }
}

// multiplyDivide: operation 0 none (input1), 1 multiply, 2 divide (x/0 gives 0: Maya's value is
// not documented), 3 power (a NaN result, e.g. a negative base with a fractional power, gives 0).
void multiplyDivideKernel(const KernelContext& ctx, const CompiledNode& node) {
    const int op = node.params[0];
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan a = ctx.in(node, c), b = ctx.in(node, 3 + c);
        float* out = ctx.out(node, c);
        switch (op) {
            case 1: for (int i = 0; i < ctx.count; ++i) out[i] = a[i] * b[i]; break;
            case 2: for (int i = 0; i < ctx.count; ++i) out[i] = b[i] != 0.0f ? a[i] / b[i] : 0.0f; break;
            case 3: for (int i = 0; i < ctx.count; ++i) out[i] = finiteOr0(std::pow(a[i], b[i])); break;
            default: for (int i = 0; i < ctx.count; ++i) out[i] = a[i]; break;
        }
    }
}

// blendColors: output = color1·blender + color2·(1 − blender).
void blendColorsKernel(const KernelContext& ctx, const CompiledNode& node) {
    const Chan blender = ctx.in(node, 0);
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan c1 = ctx.in(node, 1 + c), c2 = ctx.in(node, 4 + c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) out[i] = c1[i] * blender[i] + c2[i] * (1.0f - blender[i]);
    }
}

// clamp: per channel, below min → min, above max → max (min is tested first, so min > max gives min).
void clampKernel(const KernelContext& ctx, const CompiledNode& node) {
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan in = ctx.in(node, c), lo = ctx.in(node, 3 + c), hi = ctx.in(node, 6 + c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) {
            const float v = in[i];
            out[i] = v < lo[i] ? lo[i] : (v > hi[i] ? hi[i] : v);
        }
    }
}

// condition: firstTerm op secondTerm ? colorIfTrue : colorIfFalse; op 0 ==, 1 !=, 2 >, 3 >=, 4 <, 5 <=.
void conditionKernel(const KernelContext& ctx, const CompiledNode& node) {
    const Chan a = ctx.in(node, 0), b = ctx.in(node, 1);
    bool pick[kBatchSize];
    const int op = node.params[0];
    for (int i = 0; i < ctx.count; ++i) {
        const float x = a[i], y = b[i];
        switch (op) {
            case 0: pick[i] = x == y; break;
            case 1: pick[i] = x != y; break;
            case 2: pick[i] = x > y; break;
            case 3: pick[i] = x >= y; break;
            case 4: pick[i] = x < y; break;
            case 5: pick[i] = x <= y; break;
            default: pick[i] = false; break;
        }
    }
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan t = ctx.in(node, 2 + c), f = ctx.in(node, 5 + c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) out[i] = pick[i] ? t[i] : f[i];
    }
}

// plusMinusAverage over the set elements of input1D[], input2D[], input3D[] (in index order):
// operation 0 none (the first element), 1 sum, 2 subtract (first − the rest), 3 average.
// No elements: 0. Outputs output1D (channel 0), output2D (1..2), output3D (3..5).
void plusMinusAverageKernel(const KernelContext& ctx, const CompiledNode& node) {
    const int op = node.params[0];
    uint32_t channel = 0;  // multi inputs start at channel 0 (the node has no fixed inputs)
    uint32_t outChannel = 0;
    for (uint32_t port = 0; port < 3; ++port) {
        const uint32_t width = port + 1;
        const uint32_t elements = node.multiCount[port];
        for (uint32_t c = 0; c < width; ++c) {
            float* out = ctx.out(node, outChannel + c);
            std::fill(out, out + ctx.count, 0.0f);
            for (uint32_t e = 0; e < elements; ++e) {
                const Chan in = ctx.in(node, channel + e * width + c);
                if (e == 0 || op == 0) {
                    if (e == 0)
                        for (int i = 0; i < ctx.count; ++i) out[i] = in[i];
                } else if (op == 2) {
                    for (int i = 0; i < ctx.count; ++i) out[i] -= in[i];
                } else {
                    for (int i = 0; i < ctx.count; ++i) out[i] += in[i];
                }
            }
            if (op == 3 && elements > 0)
                for (int i = 0; i < ctx.count; ++i) out[i] /= float(elements);
        }
        channel += elements * width;
        outChannel += width;
    }
}

// setRange: outValue = min + (value − oldMin)/(oldMax − oldMin)·(max − min); an empty old range
// (oldMax == oldMin) gives min.
void setRangeKernel(const KernelContext& ctx, const CompiledNode& node) {
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan v = ctx.in(node, c), lo = ctx.in(node, 3 + c), hi = ctx.in(node, 6 + c);
        const Chan oldLo = ctx.in(node, 9 + c), oldHi = ctx.in(node, 12 + c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) {
            const float span = oldHi[i] - oldLo[i];
            out[i] = span != 0.0f ? lo[i] + (v[i] - oldLo[i]) / span * (hi[i] - lo[i]) : lo[i];
        }
    }
}

// luminance: 0.3R + 0.59G + 0.11B (the weights Maya's docs are believed to give, nodes.md §7).
void luminanceKernel(const KernelContext& ctx, const CompiledNode& node) {
    const Chan r = ctx.in(node, 0), g = ctx.in(node, 1), b = ctx.in(node, 2);
    float* out = ctx.out(node, 0);
    for (int i = 0; i < ctx.count; ++i) out[i] = 0.3f * r[i] + 0.59f * g[i] + 0.11f * b[i];
}

// gammaCorrect: value^(1/gamma) per component (exponent direction unverified, nodes.md §7);
// values ≤ 0 give 0, and a gamma ≤ 0 passes the value through.
void gammaCorrectKernel(const KernelContext& ctx, const CompiledNode& node) {
    for (uint32_t c = 0; c < 3; ++c) {
        const Chan v = ctx.in(node, c), g = ctx.in(node, 3 + c);
        float* out = ctx.out(node, c);
        for (int i = 0; i < ctx.count; ++i) {
            const float x = v[i], gamma = g[i];
            if (!(gamma > 0.0f)) out[i] = x;
            else out[i] = x > 0.0f ? finiteOr0(std::pow(x, 1.0f / gamma)) : 0.0f;
        }
    }
}

NodeType makeType(const char* name, std::vector<PortSpec> inputs, std::vector<PortSpec> outputs, Kernel kernel,
                  std::vector<EnumParam> params = {}) {
    NodeType t;
    t.name = name;
    t.inputs = std::move(inputs);
    t.outputs = std::move(outputs);
    t.kernel = kernel;
    t.params = std::move(params);
    return t;
}

PortSpec multi(PortSpec p) {
    p.multi = true;
    return p;
}

}  // namespace

void addUtilityTypes(std::vector<NodeType>& types) {
    // samplerInfo: every output is a renderer value (no kernel).
    types.push_back(makeType("samplerInfo", {},
                             {rendererPort("pointCamera", "p"), rendererPort("pointObj", "po"),
                              rendererPort("pointWorld", "pw"), rendererPort("normalCamera", "n"),
                              rendererPort("uvCoord", "uv"), rendererPort("rayDirection", "r"),
                              rendererPort("tangentUCamera", "tu"), rendererPort("tangentVCamera", "tv"),
                              rendererPort("pixelCenter", "pc"), rendererPort("flippedNormal", "fn"),
                              rendererPort("facingRatio", "fr")},
                             nullptr));
    types.push_back(makeType("reverse", {vectorPort("input", "i", "XYZ", 0, 0, 0)},
                             {vectorPort("output", "o", "XYZ", 0, 0, 0)}, &reverseKernel));
    types.push_back(makeType("multiplyDivide",
                             {vectorPort("input1", "i1", "XYZ", 0, 0, 0), vectorPort("input2", "i2", "XYZ", 1, 1, 1)},
                             {vectorPort("output", "o", "XYZ", 0, 0, 0)}, &multiplyDivideKernel,
                             {{"operation", "op", 1}}));
    types.push_back(makeType("blendColors",
                             {scalarPort("blender", "b", 0.5f), colorPort("color1", "c1", 1, 0, 0),
                              colorPort("color2", "c2", 0, 0, 1)},
                             {colorPort("output", "op", 0, 0, 0)}, &blendColorsKernel));
    types.push_back(makeType("clamp",
                             {colorPort("input", "ip", 0, 0, 0), colorPort("min", "mn", 0, 0, 0),
                              colorPort("max", "mx", 0, 0, 0)},
                             {colorPort("output", "op", 0, 0, 0)}, &clampKernel));
    types.push_back(makeType("condition",
                             {scalarPort("firstTerm", "ft", 0), scalarPort("secondTerm", "st", 0),
                              colorPort("colorIfTrue", "ct", 0, 0, 0), colorPort("colorIfFalse", "cf", 1, 1, 1)},
                             {colorPort("outColor", "oc", 0, 0, 0)}, &conditionKernel, {{"operation", "op", 0}}));
    types.push_back(makeType("plusMinusAverage",
                             {multi(scalarPort("input1D", "i1", 0)), multi(vector2Port("input2D", "i2", "xy", 0, 0)),
                              multi(vectorPort("input3D", "i3", "xyz", 0, 0, 0))},
                             {scalarPort("output1D", "o1", 0), vector2Port("output2D", "o2", "xy", 0, 0),
                              vectorPort("output3D", "o3", "xyz", 0, 0, 0)},
                             &plusMinusAverageKernel, {{"operation", "op", 1}}));
    types.push_back(makeType("setRange",
                             {vectorPort("value", "v", "XYZ", 0, 0, 0), vectorPort("min", "n", "XYZ", 0, 0, 0),
                              vectorPort("max", "m", "XYZ", 0, 0, 0), vectorPort("oldMin", "on", "XYZ", 0, 0, 0),
                              vectorPort("oldMax", "om", "XYZ", 0, 0, 0)},
                             {vectorPort("outValue", "o", "XYZ", 0, 0, 0)}, &setRangeKernel));
    types.push_back(makeType("luminance", {colorPort("value", "v", 0, 0, 0)}, {scalarPort("outValue", "o", 0)},
                             &luminanceKernel));
    types.push_back(makeType("gammaCorrect",
                             {vectorPort("value", "v", "XYZ", 0, 0, 0), vectorPort("gamma", "g", "XYZ", 1, 1, 1)},
                             {vectorPort("outValue", "o", "XYZ", 0, 0, 0)}, &gammaCorrectKernel));
}

}  // namespace pushpin::shade::detail
