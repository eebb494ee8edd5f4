// core/render/renderer.h: renders one camera's view of a FrameScene (DESIGN.md steps 4, 6b–e, 7):
// visible set (far-plane culling per object, frustum culling by screen-space bounds, near-plane
// clipping of triangles, back faces of single-sided objects dropped), tiles rendered in parallel
// with oneTBB, Exact Area Sampling visibility, shading of merged fragments in vectors of samples,
// adaptive shading by contrast at the Highest level, box or multi-pixel filtering of fragments,
// and the background.
// Thread safety: renderFrame() runs its own parallel loop; the FrameScene and camera are read-only.
// Determinism: the image depends only on the scene, camera and settings — not on the thread
// count, the tile size or the tile order. Each tile renders an apron of neighbouring pixels so
// that filters and the contrast test see the same data wherever the tile boundaries fall.
#pragma once

#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/framebuffer.h"
#include "core/render/render_settings.h"
#include "core/util/json_writer.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pushpin::render {

struct RenderStats {
    // seconds of wall time per phase
    double prepareSeconds = 0.0;     // culling, projection, clipping, binning
    double tilesSeconds = 0.0;       // the parallel tile loop
    // seconds summed over threads inside the tile loop
    double rasterSeconds = 0.0, resolveSeconds = 0.0, shadeSeconds = 0.0, filterSeconds = 0.0;
    uint64_t tiles = 0;
    uint64_t pixels = 0;                   // pixels written (the render region)
    uint64_t objects = 0, objectsCulledFrustum = 0, objectsCulledFar = 0;
    uint64_t triangles = 0;                // triangles of the objects kept
    uint64_t trianglesBackfacing = 0;      // dropped: back faces of single-sided objects
    uint64_t trianglesNearClipped = 0;     // crossed the near plane and were clipped
    uint64_t trianglesOutside = 0;         // behind the near plane or off screen
    uint64_t trianglesRasterized = 0;      // per tile, summed (a triangle in two tiles counts twice)
    uint64_t fragments = 0, mergedFragments = 0, surfaces = 0;
    uint64_t shadingSamplesBase = 0, shadingSamplesAdaptive = 0;
    uint64_t adaptivePixels = 0;           // pixels that took extra samples
    uint64_t apronPixels = 0;              // pixels rendered outside their tile for filters/contrast
};

struct RenderOptions {
    // When not null, receives width × height flags: 1 where the pixel took adaptive samples.
    std::vector<uint8_t>* adaptiveMask = nullptr;
};

// Renders `camera`'s view. The framebuffer has the camera's size; pixels outside the render
// region (settings.useRenderRegion) stay 0. Depth is kept when settings.depth is set.
Framebuffer renderFrame(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        RenderStats& stats, const RenderOptions& options = {});

// Writes the stats as one JSON object value (the --stats file holds one per rendered image).
void writeRenderStats(util::JsonWriter& json, const RenderStats& stats);

}  // namespace pushpin::render
