// core/render/renderer.h: renders one camera's view of a FrameScene (DESIGN.md steps 4, 6b–e, 7):
// visible set (far-plane culling per object, frustum culling by screen-space bounds, near-plane
// clipping of triangles, back faces of single-sided objects dropped), tiles rendered in parallel
// with oneTBB, Exact Area Sampling visibility, shading of merged fragments in vectors of samples,
// adaptive shading by contrast at the Highest level, box or multi-pixel filtering of fragments,
// and the background.
// Per tile, objects are taken front to back; one that nearer opaque geometry already rasterized in
// the tile hides in every pixel it reaches is neither tessellated nor rasterized there
// (PixelResolver::occludingDepth), which changes no bit of the image.
// Thread safety: renderFrame() runs its own parallel loop; the FrameScene and camera are read-only.
// Determinism: the image depends only on the scene, camera and settings — not on the thread
// count, the tile size or the tile order. At the Highest level each tile renders an apron of the
// neighbouring pixels the contrast test reads (two columns left, one right, one row above); a
// multi-pixel filter needs none: pixels whose window reaches past their tile are filtered once all
// tiles are done, from the surfaces the tiles kept near their edges (filter_borders.h), summed in
// the same order as inside a tile.
// Memory: before it allocates, renderFrame charges one MemoryBudget (RenderOptions::memoryBudget,
// else its own with the cap of memoryCap(settings)) with every buffer whose size it knows
// (frameMemory()): "framebuffer" for the frame, the image writer's copy and the adaptive mask,
// "fragments" for the tile list and each thread's share of the tile buffers, "tessellation" for
// each object's view, "geometry" for the sources that stay resident. A frame the cap cannot hold
// fails with pushpin::MemoryCapError before any of them is allocated. Tessellations are made when a
// tile first needs them and kept in an LRU charged as "tessellation" (lazy_tessellation.h), and a
// tile's buffers beyond its thread's share are charged as "fragments" as they grow; a tile that
// cannot fit stops the render with MemoryCapError too. Every charge is released when renderFrame
// returns or throws.
#pragma once

#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/framebuffer.h"
#include "core/render/render_settings.h"
#include "core/render/tile_plan.h"
#include "core/util/json_writer.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cache/memory_budget.h"

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
    uint64_t apronPixels = 0;              // pixels rendered outside their tile for the contrast test
    // tiles
    int tileMinSize = 0, tileMaxSize = 0;  // shortest and longest tile side, pixels
    double maxTileCost = 0.0;              // the plan's cost limit (triangles per tile scanline); 0: fixed tiles
    uint64_t tilesDeferred = 0;            // rendered again alone: their triangles did not fit beside other tiles'
    // tessellation (made per tile on first need, shared by instances, dropped under memory pressure)
    uint64_t tessellationShapes = 0;       // distinct shapes among the objects kept
    uint64_t tessellationInstances = 0;    // objects kept (instances of those shapes)
    uint64_t objectTileVisits = 0;         // objects rasterized per tile, summed over tiles
    uint64_t skippedOccluded = 0;          // object-tile visits skipped: hidden by opaque geometry
    uint64_t tessellationsMade = 0;        // tessellations made (first time and again)
    uint64_t trianglesMade = 0;            // their triangles
    uint64_t tessellationsEvicted = 0;     // dropped to make room
    uint64_t tessellationsRecomputed = 0;  // made again after being dropped
    // Tessellations a tile let go before it was shaded, keeping a copy of the triangles it
    // rasterized, to make room for the next one it needed (under a cap only).
    uint64_t tileCopies = 0;
    // Meshes of shapes in pieces made again for their pieces (they do not keep them), and how
    // many of those were dropped to make room before the frame ended.
    uint64_t meshesMade = 0;
    uint64_t meshesEvicted = 0;
    // memory
    uint64_t memoryCapBytes = 0;           // 0: unlimited
    uint64_t memoryPeakCharged = 0;        // most the render's budget held at once
    std::array<uint64_t, cache::kMemoryCategoryCount> memoryPeakByCategory{};
    uint64_t peakRssBytes = 0;             // the process's peak resident size when the render ended
};

struct RenderOptions {
    // When not null, receives width × height flags: 1 where the pixel took adaptive samples.
    std::vector<uint8_t>* adaptiveMask = nullptr;
    // The render's memory budget. Null: renderFrame makes one with the cap memoryCap(settings)
    // (-mm, else $SLURM_MEM_PER_NODE, else unlimited) for the duration of the call.
    cache::MemoryBudget* memoryBudget = nullptr;
    // When not null, receives the tiles rendered with each one's cost (tile_plan.h tileCost, also
    // for fixed tiles, whose maxTileCost is then +infinity), for --tile-pattern.
    TilePlan* tilePlan = nullptr;
    // Objects that nearer opaque geometry hides in a whole tile are neither tessellated nor
    // rasterized there. The image is the same either way; false does all the work (for checks).
    bool skipOccluded = true;
    // Under a cap, a tile that meets more tessellations than the budget holds at once keeps a
    // copy of the triangles it rasterized from each and lets the tessellation go (stats:
    // tileCopies). The image is the same either way; false stops such a tile instead (for checks).
    bool copyPinnedTriangles = true;
};

// The buffers of one render whose size is known before it starts, in bytes, by the category
// renderFrame charges them to. Upper bounds where the exact size depends on clipping.
struct FrameMemory {
    // framebuffer: rgba (16 B/pixel), depth (4 B/pixel when kept), the adaptive mask (1 B/pixel
    // when asked for) and the image writer's conversion buffer (imageOutputBytes()).
    uint64_t framebufferBytes = 0;
    // fragments: the tile list and bins, and one set of tile buffers (the tile plus its contrast apron:
    // surface indices, nearest depths, contrast colours, shading batch and results) per thread.
    uint64_t tileBytes = 0;
    uint64_t perThreadBytes = 0;  // of tileBytes, one thread's share (a worker's buffers beyond it are
                                  // charged as they grow, to "fragments")
    // tessellation: each object's view (matrices, lights per material slot) and its entries in
    // every thread's tile tables.
    uint64_t geometryBytes = 0;
    // geometry: the sources tessellations are made from that stay resident, every kept mesh and
    // surface once. Making a tessellation charges "geometry" for as long as it takes: the mesh
    // evaluated again (when not kept), the working memory and the tessellation itself.
    uint64_t sourceBytes = 0;
    uint64_t totalBytes() const { return framebufferBytes + tileBytes + geometryBytes + sourceBytes; }
    // Not charged up front: the estimated bytes of the largest shape's tessellation and the most
    // any shape needs while its tessellation is made (its evaluated mesh and working memory),
    // which together must fit beside the buffers above (the tessellation cache charges what it
    // makes, tile by tile).
    uint64_t largestTessellationBytes = 0;
    uint64_t largestTransientBytes = 0;
};

// What renderFrame will charge for this scene, camera and settings with `threads` threads.
// Pure; thread-safe.
FrameMemory frameMemory(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        const RenderOptions& options, int threads);

// The tile plan under a memory cap (tile_plan.h, DESIGN.md step 5). A tile's buffers grow with
// its triangle crossings — a triangle meeting one pixel row — each leaving about
// tileBytesPerCrossing(settings) bytes: its fragment as the rasterizer, the tile and the resolver
// hold it (4 × 48 B), its surface group, shade and contribution, one shading result per sample it
// may take (the adaptive maximum at Highest), and with a multi-pixel filter the surface it keeps
// for the pixels filtered at the end (filter_borders.h).
uint64_t tileBytesPerCrossing(const RenderSettings& settings);
// maxTileCost, triangles per tile scanline: a tile of `tallestTile` rows whose every row costs
// that much fills `bytesPerTile`, i.e. bytesPerTile / tileBytesPerCrossing / tallestTile (at
// least 1). The renderer gives each thread half of what the budget has left after the frame's
// own charges (the other half is for tessellations) and the height of a quadrant as the tallest
// tile. Pure.
double maxTileCost(uint64_t bytesPerTile, const RenderSettings& settings, int tallestTile);

// The bytes the image writer needs to convert a width × height frame to the file's channels,
// counted as 5 floats per pixel (colour, alpha and depth). Charged by renderFrame with the frame.
uint64_t imageOutputBytes(int width, int height);

// Charges the loaded scene's stored values (scene::Graph::storedBytes) to `budget` as "scene",
// for as long as the returned charge lives: the renders that share the budget then plan around
// them. Throws pushpin::MemoryCapError when they do not fit, e.g. "the scene's stored values need
// 243.0 MB, over the memory cap of 128 MB (-mm)" (the cap's source as memoryCap(settings) names it).
cache::MemoryCharge chargeScene(cache::MemoryBudget& budget, uint64_t storedBytes, const RenderSettings& settings);

// Renders `camera`'s view. The framebuffer has the camera's size; pixels outside the render
// region (settings.useRenderRegion) stay 0. Depth is kept when settings.depth is set.
// Uses settings.numCpusToUse threads (0: all). Inputs come checked from buildFrameScene and
// makeRenderCamera (numbers at the door); every pixel written is then finite for finite shading.
// Memory: charges frameMemory() to the budget (see the top of this file) before allocating and
// releases it before returning. Throws pushpin::MemoryCapError, with nothing large allocated,
// when the budget cannot take it, e.g. "the 32768x32768 frame needs 36.0 GB of buffers, over the
// memory cap of 2048 MB (-mm)". std::bad_alloc passes through.
Framebuffer renderFrame(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        RenderStats& stats, const RenderOptions& options = {});

// Writes the stats as one JSON object value (the --stats file holds one per rendered image).
void writeRenderStats(util::JsonWriter& json, const RenderStats& stats);

}  // namespace pushpin::render
