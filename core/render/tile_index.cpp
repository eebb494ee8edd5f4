#include "core/render/tile_index.h"

#include <algorithm>
#include <stdexcept>

namespace pushpin::render {

template <class Visit>
void TileIndex::forEachCell(const PixelRect& r, Visit&& visit) const {
    const int x0 = std::max(r.x0, m_region.x0), x1 = std::min(r.x1, m_region.x1);
    const int y0 = std::max(r.y0, m_region.y0), y1 = std::min(r.y1, m_region.y1);
    if (x0 >= x1 || y0 >= y1) return;
    const int cx0 = (x0 - m_region.x0) / m_cell, cx1 = (x1 - 1 - m_region.x0) / m_cell;
    const int cy0 = (y0 - m_region.y0) / m_cell, cy1 = (y1 - 1 - m_region.y0) / m_cell;
    for (int cy = cy0; cy <= std::min(cy1, m_cellsY - 1); ++cy)
        for (int cx = cx0; cx <= std::min(cx1, m_cellsX - 1); ++cx) visit(size_t(cy) * size_t(m_cellsX) + size_t(cx));
}

TileIndex::TileIndex(const PixelRect& region, std::span<const PixelRect> tiles)
    : m_region(region), m_tiles(tiles.begin(), tiles.end()) {
    int smallest = 64;
    for (const PixelRect& t : m_tiles) smallest = std::min({smallest, std::max(1, t.width()), std::max(1, t.height())});
    m_cell = smallest;
    m_cellsX = (region.width() + m_cell - 1) / m_cell;
    m_cellsY = (region.height() + m_cell - 1) / m_cell;
    m_cellStart.assign(size_t(m_cellsX) * size_t(m_cellsY) + 1, 0);
    for (const PixelRect& t : m_tiles) forEachCell(t, [&](size_t c) { ++m_cellStart[c + 1]; });
    for (size_t c = 1; c < m_cellStart.size(); ++c) m_cellStart[c] += m_cellStart[c - 1];
    m_cellTiles.resize(m_cellStart.back());
    std::vector<uint32_t> next(m_cellStart.begin(), m_cellStart.end() - 1);
    for (uint32_t i = 0; i < m_tiles.size(); ++i) forEachCell(m_tiles[i], [&](size_t c) { m_cellTiles[next[c]++] = i; });
}

uint32_t TileIndex::tileAt(int x, int y) const {
    if (m_region.contains(x, y)) {
        const size_t c = size_t((y - m_region.y0) / m_cell) * size_t(m_cellsX) + size_t((x - m_region.x0) / m_cell);
        for (uint32_t k = m_cellStart[c]; k < m_cellStart[c + 1]; ++k)
            if (m_tiles[m_cellTiles[k]].contains(x, y)) return m_cellTiles[k];
    }
    throw std::logic_error("TileIndex: a pixel in no tile");
}

void TileIndex::tilesMeeting(const PixelRect& rect, std::vector<uint32_t>& out) const {
    out.clear();
    forEachCell(rect, [&](size_t c) {
        for (uint32_t k = m_cellStart[c]; k < m_cellStart[c + 1]; ++k) {
            const PixelRect& o = m_tiles[m_cellTiles[k]];
            if (o.x0 < rect.x1 && rect.x0 < o.x1 && o.y0 < rect.y1 && rect.y0 < o.y1) out.push_back(m_cellTiles[k]);
        }
    });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace pushpin::render
