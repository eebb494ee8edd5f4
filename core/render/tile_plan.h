// core/render/tile_plan.h: how the image is cut into tiles rendered in parallel (DESIGN.md step 5).
// For now a fixed tile size (Maya's forceTileSize/tileWidth/tileHeight, 64×64 by default); the
// memory-driven plan (maxTileCost) replaces planTiles() behind the same call.
// Pure functions; thread-safe.
#pragma once

#include "core/render/fragment.h"

#include <vector>

namespace pushpin::render {

// Tiles of `region` in row-major order, each at most tileWidth × tileHeight (sizes below 1 are
// taken as 1). Together they cover the region exactly once.
std::vector<PixelRect> planTiles(const PixelRect& region, int tileWidth, int tileHeight);

}  // namespace pushpin::render
