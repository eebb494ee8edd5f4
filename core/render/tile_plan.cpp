#include "core/render/tile_plan.h"

#include <algorithm>

namespace pushpin::render {

std::vector<PixelRect> planTiles(const PixelRect& region, int tileWidth, int tileHeight) {
    std::vector<PixelRect> tiles;
    if (region.empty()) return tiles;
    tileWidth = std::max(tileWidth, 1);
    tileHeight = std::max(tileHeight, 1);
    for (int y = region.y0; y < region.y1; y += tileHeight)
        for (int x = region.x0; x < region.x1; x += tileWidth)
            tiles.push_back({x, y, std::min(x + tileWidth, region.x1), std::min(y + tileHeight, region.y1)});
    return tiles;
}

}  // namespace pushpin::render
