// core/render/render_options.h: what a caller of renderFrame may ask beyond the render settings.
#pragma once

#include "core/render/tile_plan.h"

#include "cache/memory_budget.h"

#include <cstdint>
#include <vector>

namespace pushpin::render {

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

}  // namespace pushpin::render
