#include "core/render/filter_borders.h"

#include "core/util/release.h"

#include <oneapi/tbb/parallel_for.h>

#include <stdexcept>

namespace pushpin::render {

FilterBorders::FilterBorders(const PixelFilter& filter, const PixelRect& region, std::span<const PixelRect> tiles)
    : m_filter(filter), m_region(region), m_tiles(tiles.begin(), tiles.end()), m_kept(tiles.size()) {
    int smallest = 64;
    for (const PixelRect& t : m_tiles) smallest = std::min({smallest, std::max(1, t.width()), std::max(1, t.height())});
    m_cell = smallest;
    m_cellsX = (region.width() + m_cell - 1) / m_cell;
    const int cellsY = (region.height() + m_cell - 1) / m_cell;
    // The cells each tile overlaps, counted, then listed.
    auto forEachCell = [&](const PixelRect& t, auto&& visit) {
        if (t.empty()) return;
        const int cx0 = (t.x0 - region.x0) / m_cell, cx1 = (t.x1 - 1 - region.x0) / m_cell;
        const int cy0 = (t.y0 - region.y0) / m_cell, cy1 = (t.y1 - 1 - region.y0) / m_cell;
        for (int cy = std::max(cy0, 0); cy <= std::min(cy1, cellsY - 1); ++cy)
            for (int cx = std::max(cx0, 0); cx <= std::min(cx1, m_cellsX - 1); ++cx) visit(size_t(cy) * m_cellsX + cx);
    };
    m_cellStart.assign(size_t(m_cellsX) * size_t(cellsY) + 1, 0);
    for (const PixelRect& t : m_tiles) forEachCell(t, [&](size_t c) { ++m_cellStart[c + 1]; });
    for (size_t c = 1; c < m_cellStart.size(); ++c) m_cellStart[c] += m_cellStart[c - 1];
    m_cellTiles.resize(m_cellStart.back());
    std::vector<uint32_t> next(m_cellStart.begin(), m_cellStart.end() - 1);
    for (uint32_t i = 0; i < m_tiles.size(); ++i) forEachCell(m_tiles[i], [&](size_t c) { m_cellTiles[next[c]++] = i; });
}

uint32_t FilterBorders::tileAt(int x, int y) const {
    const size_t c = size_t((y - m_region.y0) / m_cell) * m_cellsX + size_t((x - m_region.x0) / m_cell);
    for (uint32_t k = m_cellStart[c]; k < m_cellStart[c + 1]; ++k)
        if (m_tiles[m_cellTiles[k]].contains(x, y)) return m_cellTiles[k];
    throw std::logic_error("FilterBorders: a pixel of the region in no tile");
}

std::span<const FilterSurface> FilterBorders::surfacesAt(int x, int y) const {
    const uint32_t t = tileAt(x, y);
    const PixelRect& r = m_tiles[t];
    const Kept& k = m_kept[t];
    const size_t i = size_t(y - r.y0) * size_t(r.width()) + size_t(x - r.x0);
    if (i + 1 >= k.start.size()) throw std::logic_error("FilterBorders: a tile's surfaces were not kept");
    return {k.surfaces.data() + k.start[i], k.start[i + 1] - k.start[i]};
}

void FilterBorders::filterAll(const Write& write) const {
    tbb::parallel_for(size_t(0), m_tiles.size(), [&](size_t index) {
        const PixelRect& t = m_tiles[index];
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (completeIn(t, x, y)) continue;
                double c[3] = {0, 0, 0}, a = 0.0;
                gatherFiltered(
                    m_filter, m_region, x, y,
                    [&](int sx, int sy, auto&& visit) {
                        for (const FilterSurface& s : surfacesAt(sx, sy)) visit(s.contribution, s.norm);
                    },
                    c, a);
                write(x, y, c, a);
            }
    });
}

void FilterBorders::release() {
    for (Kept& k : m_kept) {
        util::release(k.start);
        util::release(k.surfaces);
    }
}

}  // namespace pushpin::render
