// core/shade/shading_network.h: compiles a Maya shading network (the nodes upstream of a shading
// group's surfaceShader) once per frame into an ordered program, and evaluates it over batches of
// samples (DESIGN.md 6d; STYLE.md §24–26): every node runs once per batch over all its samples,
// inputs are constants or earlier nodes' outputs, dispatch happens once per node per batch.
// Nodes so far (core/shade/node_library.h): lambert, blinn, phong, phongE, surfaceShader,
// samplerInfo, reverse, multiplyDivide, blendColors, clamp, condition, plusMinusAverage, setRange,
// luminance, gammaCorrect, and the renderer's implicit attributes (pointCamera, normalCamera,
// rayDirection, facingRatio, uvCoord, …) on any node that declares them. Unknown node types are
// reported once and read as their plugs' values.
// Thread safety: a compiled ShadingNetwork is immutable and shared by all threads; each thread
// passes its own ShadingScratch.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/graph.h"
#include "core/shade/light.h"
#include "core/shade/shading_batch.h"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pushpin::shade {

// Per-thread working memory for evaluate(): the network's registers. Sized on first use.
struct ShadingScratch {
    std::vector<float> registers;
    LightSamples lightSamples;
};

class ShadingNetwork {
public:
    // Compiles the network rooted at `surfaceShader` (the node wired to a shading group's
    // surfaceShader plug) with attribute values taken at the evaluator's frame. kNoNode gives
    // Maya's behaviour for a shading group without a shader: black and opaque. Problems that do
    // not stop rendering (unsupported node types, connections that cannot be followed, NaN/Inf
    // values replaced by the attribute's default) are appended to `notes`, one line each, naming
    // the node. Never throws for bad scene content.
    static std::shared_ptr<const ShadingNetwork> compile(scene::Evaluator& ev, scene::NodeId surfaceShader,
                                                         std::vector<std::string>& notes);

    // Evaluates the network over the batch's samples with the given lights (in the batch's
    // space), writing outColor and outTransparency. Allocation-free once `scratch` is sized.
    void evaluate(const ShadingBatch& batch, std::span<const Light> lights, ShadingScratch& scratch,
                  ShadingResult& out) const;

    // True when outTransparency can be non-zero (a non-zero constant or any connection).
    bool mayBeTransparent() const { return m_mayBeTransparent; }
    const std::string& rootName() const { return m_rootName; }
    size_t nodeCount() const;

    struct Program;  // the compiled node list, registers and constants (shading_network.cpp)
    ~ShadingNetwork();
    ShadingNetwork();

private:
    std::unique_ptr<Program> m_program;
    bool m_mayBeTransparent = false;
    std::string m_rootName;
};

}  // namespace pushpin::shade
