// core/render/tile_index.h: which tile of a plan holds a pixel, found through a grid of cells as
// large as the smallest tile (so each cell meets at most four tiles).
// Thread safety: immutable after construction. Memory: 4 bytes per cell and per tile-cell overlap.
#pragma once

#include "core/render/fragment.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pushpin::render {

class TileIndex {
public:
    TileIndex() = default;
    // For `tiles` (disjoint, covering `region`).
    TileIndex(const PixelRect& region, std::span<const PixelRect> tiles);

    const PixelRect& region() const { return m_region; }
    const std::vector<PixelRect>& tiles() const { return m_tiles; }
    // The tile holding pixel (x, y) of the region. Throws std::logic_error for a pixel in none.
    uint32_t tileAt(int x, int y) const;
    // The tiles meeting `rect` (clipped to the region), ascending, into `out`.
    void tilesMeeting(const PixelRect& rect, std::vector<uint32_t>& out) const;

private:
    template <class Visit>
    void forEachCell(const PixelRect& r, Visit&& visit) const;

    PixelRect m_region;
    std::vector<PixelRect> m_tiles;
    // Cell c's tiles are m_cellTiles[m_cellStart[c] .. m_cellStart[c + 1]).
    int m_cell = 16, m_cellsX = 0, m_cellsY = 0;
    std::vector<uint32_t> m_cellStart, m_cellTiles;
};

}  // namespace pushpin::render
