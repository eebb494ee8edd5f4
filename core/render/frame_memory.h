// core/render/frame_memory.h: what a frame needs before its first tile (DESIGN.md "Memory"): the
// pixels it renders and the margins its tiles read, the buffers whose size is known up front, the
// maxTileCost a budget allows, and the charges that hold them in a MemoryBudget.
#pragma once

#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_options.h"
#include "core/render/render_settings.h"
#include "core/render/tile_plan.h"

#include "cache/memory_budget.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pushpin::render {

// The pixels rendered and the apron each tile needs around it for the contrast test, fixed before
// anything is allocated (frameMemory() sizes the buffers from it). The multi-pixel filter needs
// none: the pixels whose window reaches past their tile are filtered at the end (filter_borders.h).
struct FrameLayout {
    PixelRect region;   // the render region or the whole image
    bool adaptive = false;
    int marginLeft = 0, marginRight = 0, marginTop = 0, marginBottom = 0;
};

// The layout of `camera`'s frame: the render region (Maya's region rows count from the bottom),
// whether adaptive shading runs (the Highest level with more maximum than base samples, for the
// frame or some object's override) and then its contrast margins (ContrastBorders). Pure.
FrameLayout frameLayout(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings);

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

// "21.5 GB" / "310.2 MB" (binary units, as -mm and $SLURM_MEM_PER_NODE count them).
std::string formatBytes(uint64_t bytes);
// A cap as -mm gives it ("2048 MB") when it is whole MiB, else formatBytes.
std::string formatCap(uint64_t cap);

// Charges a frame's buffers (`need`, from frameMemory()), by category, all or nothing: on refusal
// the charges made so far are released and pushpin::MemoryCapError names the need, the memory
// already in use and the cap (`capSource` says where the cap came from, e.g. "-mm"). Also refuses
// a frame whose largest shape's tessellation and working memory would not fit beside the buffers.
std::vector<cache::MemoryCharge> chargeFrame(cache::MemoryBudget& budget, const FrameMemory& need,
                                             const RenderCamera& camera, const std::string& capSource);

// Charges the loaded scene's stored values (scene::Graph::storedBytes) to `budget` as "scene",
// for as long as the returned charge lives: the renders that share the budget then plan around
// them. Throws pushpin::MemoryCapError when they do not fit, e.g. "the scene's stored values need
// 243.0 MB, over the memory cap of 128 MB (-mm)" (the cap's source as memoryCap(settings) names it).
cache::MemoryCharge chargeScene(cache::MemoryBudget& budget, uint64_t storedBytes, const RenderSettings& settings);

}  // namespace pushpin::render
