// core/render/render_settings.h: the render globals a frame is rendered with — Maya's
// defaultRenderGlobals, defaultRenderQuality and defaultResolution values in effect
// (reference/render-globals.md), read from the scene with Maya's defaults where the file is
// silent, then overridden by the command line. Field names are the Maya attribute long names.
// The memory cap of a render (memoryCap()) comes from the command line (-mm) or the scheduler
// ($SLURM_MEM_PER_NODE), never from the scene: Maya's maximumMemory attribute is a tiling hint
// (default 48 MB, reference/render-globals.md) and is not read.
// Plain data; thread-safe.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/render_setup.h"

#include <cstdint>
#include <optional>
#include <string>

namespace pushpin::render {

struct RenderSettings {
    // defaultResolution
    int width = 640, height = 480;
    double deviceAspectRatio = 4.0 / 3.0;
    // defaultRenderQuality
    int edgeAntiAliasing = 3;  // 0 Highest, 1 High, 2 Medium, 3 Low
    int shadingSamples = 1, maxShadingSamples = 8;
    bool useMultiPixelFilter = false;
    int pixelFilterType = 2;   // 0 box, 2 triangle, 4 gaussian, 5 quadratic B-spline, 6 cubic B-spline 3×3
    double pixelFilterWidthX = 2.2, pixelFilterWidthY = 2.2;
    double redThreshold = 0.4, greenThreshold = 0.3, blueThreshold = 0.6;
    double coverageThreshold = 0.125;
    // defaultRenderGlobals
    bool animation = false;
    double startFrame = 1, endFrame = 1, byFrameStep = 1;
    int extensionPadding = 1;
    int imageFormat = 7;            // Maya's outf code
    std::string imfPluginKey;       // "exr" … when imageFormat is 40/51
    std::string imageFilePrefix;    // empty: the scene's name
    int outFormatControl = 0;       // 0 normal extension, 1 none, 2 outFormatExt
    std::string outFormatExt;
    bool putFrameBeforeExt = false;
    int periodInExt = 1;            // 0 none, 1 period, 2 underscore
    double gammaCorrection = 1.0;
    bool clipFinalShadedColor = true;
    bool jitterFinalColor = true;
    bool composite = false;
    bool enableDefaultLight = true;
    int numCpusToUse = 0;           // 0: all
    bool forceTileSize = false;
    int tileWidth = 64, tileHeight = 64;
    bool useRenderRegion = false;
    int left = 0, rght = 0, bot = 0, top = 0;  // inclusive pixels, y from the bottom (Maya's convention)
    // camera outputs (the rendered camera's image/mask/depth unless the command line says)
    std::optional<bool> image, mask, depth;
    // The memory cap given on the command line (`-mm MB`, 1 MB = 2^20 bytes), in bytes; 0 when
    // none was given. applyOverrides() fills it; see memoryCap() for the cap a render obeys.
    uint64_t maximumMemoryBytes = 0;
};

// The memory cap one render obeys, and where it came from (for messages).
struct MemoryCap {
    uint64_t bytes = 0;   // 0: unlimited
    std::string source;   // "-mm", "$SLURM_MEM_PER_NODE", or empty when unlimited
};

// The cap of a render: settings.maximumMemoryBytes when the command line gave one (-mm), else
// `slurmMemPerNode` (the value of $SLURM_MEM_PER_NODE, MiB, farm.md §6 "Memory cap follows the
// scheduler") when it is a positive whole number, else unlimited. Slurm's 0 ("all the node's
// memory") and text that is not a number give no cap. Pure; never throws.
MemoryCap memoryCap(const RenderSettings& settings, const char* slurmMemPerNode);
// The same with $SLURM_MEM_PER_NODE read from the environment (std::getenv; call it from one
// thread at a time with anything that changes the environment).
MemoryCap memoryCap(const RenderSettings& settings);
// memoryCap(settings).bytes.
uint64_t memoryCapBytes(const RenderSettings& settings);

// Reads the three render-globals nodes of `setup` at the evaluator's frame. Values that are NaN,
// Inf or out of range are replaced by Maya's default and reported in `notes` naming the node and
// attribute. Never throws.
RenderSettings readRenderSettings(scene::Evaluator& ev, const scene::RenderSetup& setup,
                                  std::vector<std::string>& notes);

}  // namespace pushpin::render
