#include "core/render/contrast_borders.h"

#include <algorithm>
#include <stdexcept>

namespace pushpin::render {

ContrastBorders::ContrastBorders(const TileIndex& index)
    : m_index(index), m_kept(index.tiles().size()), m_done(std::make_unique<std::atomic<uint8_t>[]>(index.tiles().size())) {
    for (size_t i = 0; i < m_kept.size(); ++i) m_done[i].store(0, std::memory_order_relaxed);
}

PixelRect ContrastBorders::withMargins(const PixelRect& tile) const {
    const PixelRect& r = m_index.region();
    return {std::max(r.x0, tile.x0 - kLeft), std::max(r.y0, tile.y0 - kTop), std::min(r.x1, tile.x1 + kRight), tile.y1};
}

PixelRect ContrastBorders::baseFor(size_t index) const {
    const PixelRect& t = m_index.tiles()[index];
    const PixelRect wide = withMargins(t);
    // Whether every pixel of `wide` outside `base` lies in a done tile.
    auto outsideDone = [&](const PixelRect& base) {
        for (int y = wide.y0; y < wide.y1; ++y)
            for (int x = wide.x0; x < wide.x1; ++x) {
                if (base.contains(x, y)) {
                    x = base.x1 - 1;  // on past the base's row
                    continue;
                }
                if (!m_done[m_index.tileAt(x, y)].load(std::memory_order_acquire)) return false;
            }
        return true;
    };
    PixelRect best = wide;
    uint64_t bestArea = uint64_t(wide.width()) * uint64_t(wide.height());
    for (int widen = 0; widen < 8; ++widen) {
        const PixelRect base{widen & 1 ? wide.x0 : t.x0, widen & 2 ? wide.y0 : t.y0, widen & 4 ? wide.x1 : t.x1, t.y1};
        const uint64_t area = uint64_t(base.width()) * uint64_t(base.height());
        if (area < bestArea && outsideDone(base)) {
            best = base;
            bestArea = area;
        }
    }
    return best;
}

const glm::vec3& ContrastBorders::colorAt(int x, int y) const {
    const uint32_t i = m_index.tileAt(x, y);
    const PixelRect& t = m_index.tiles()[i];
    if (!m_done[i].load(std::memory_order_acquire) || !isKept(t, x, y) || m_kept[i].size() != keptCount(t))
        throw std::logic_error("ContrastBorders: a colour read that no done tile kept");
    return m_kept[i][slot(t, x, y)];
}

}  // namespace pushpin::render
