#include "core/render/filter_borders.h"

#include "core/util/release.h"

#include <stdexcept>

namespace pushpin::render {

FilterBorders::FilterBorders(const PixelFilter& filter, const TileIndex& index)
    : m_filter(filter), m_index(index), m_kept(index.tiles().size()) {
    const std::vector<PixelRect>& tiles = m_index.tiles();
    // Each tile's near tiles: those meeting it widened by the reach (a relation both ways).
    const int r = filter.reach;
    m_nearStart.assign(tiles.size() + 1, 0);
    m_waiting = std::make_unique<std::atomic<uint32_t>[]>(tiles.size());
    m_readers = std::make_unique<std::atomic<uint32_t>[]>(tiles.size());
    std::vector<uint32_t> found;
    for (uint32_t i = 0; i < tiles.size(); ++i) {
        const PixelRect& t = tiles[i];
        m_index.tilesMeeting({t.x0 - r, t.y0 - r, t.x1 + r, t.y1 + r}, found);
        m_near.insert(m_near.end(), found.begin(), found.end());
        m_nearStart[i + 1] = uint32_t(m_near.size());
        m_waiting[i].store(uint32_t(found.size()), std::memory_order_relaxed);
        m_readers[i].store(uint32_t(found.size()), std::memory_order_relaxed);
    }
}

std::span<const FilterSurface> FilterBorders::surfacesAt(int x, int y) const {
    const uint32_t t = m_index.tileAt(x, y);
    const PixelRect& r = m_index.tiles()[t];
    const Kept& k = m_kept[t];
    const size_t i = size_t(y - r.y0) * size_t(r.width()) + size_t(x - r.x0);
    if (i + 1 >= k.start.size()) throw std::logic_error("FilterBorders: a tile's surfaces were not kept");
    return {k.surfaces.data() + k.start[i], k.start[i + 1] - k.start[i]};
}

void FilterBorders::filterBorders(size_t index, const Write& write) const {
    const PixelRect& t = m_index.tiles()[index];
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            if (completeIn(t, x, y)) continue;
            double c[3] = {0, 0, 0}, a = 0.0;
            gatherFiltered(
                m_filter, m_index.region(), x, y,
                [&](int sx, int sy, auto&& visit) {
                    for (const FilterSurface& s : surfacesAt(sx, sy)) visit(s.contribution, s.norm);
                },
                c, a);
            write(x, y, c, a);
        }
}

void FilterBorders::tileDone(size_t index, const Write& write, const Released& released) {
    for (uint32_t k = m_nearStart[index]; k < m_nearStart[index + 1]; ++k) {
        const uint32_t n = m_near[k];
        if (m_waiting[n].fetch_sub(1, std::memory_order_acq_rel) != 1) continue;
        // Every tile near n is done: its border pixels can be filtered, and the tiles near it
        // have one reader fewer.
        filterBorders(n, write);
        for (uint32_t j = m_nearStart[n]; j < m_nearStart[n + 1]; ++j) {
            const uint32_t m = m_near[j];
            if (m_readers[m].fetch_sub(1, std::memory_order_acq_rel) != 1) continue;
            util::release(m_kept[m].start);
            util::release(m_kept[m].surfaces);
            released(m);
        }
    }
}

bool FilterBorders::allFiltered() const {
    for (size_t i = 0; i < m_index.tiles().size(); ++i)
        if (m_readers[i].load(std::memory_order_acquire) != 0) return false;
    return true;
}

}  // namespace pushpin::render
