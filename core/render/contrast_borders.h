// core/render/contrast_borders.h: what neighbouring tiles share for the contrast test of adaptive
// shading (adaptive_shading.h), so that a tile whose neighbours are done renders no apron for it.
//
// The contrast test of a pixel reads the base colours of its neighbours W, WW, NW, N and NE: past
// a tile's edges, two columns left, one column right and one row above. A done tile has kept the
// base colours its neighbours' tests read (keep): its left column, its two right columns and its
// bottom row. A tile about to render takes the smallest region to render (baseFor): itself, widened
// to the left, above or to the right only where a margin has pixels in tiles not done yet. It reads
// the rest of its margins from what was kept (colorAt). Both give the same base colours, so the
// image is the same either way, whatever the tile order and the thread count.
//
// Thread safety: keep(), markDone(), baseFor() and colorAt() may be called by any number of
// threads at once for different tiles; colorAt() only for pixels of tiles marked done, whose kept
// colours never change again. keep() may be called again for a tile until it is marked done.
// Memory: 12 bytes per kept pixel (three columns and a row of each tile); bytesFor() says what a
// keep() holds, for the caller to charge first.
#pragma once

#include "core/render/fragment.h"
#include "core/render/tile_index.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace pushpin::render {

class ContrastBorders {
public:
    // The margins of a tile the contrast test reads: left, right, top (none below).
    static constexpr int kLeft = 2, kRight = 1, kTop = 1;

    // For the tiles of `index`, which must outlive this.
    explicit ContrastBorders(const TileIndex& index);

    // `tile` widened by the margins, within the region.
    PixelRect withMargins(const PixelRect& tile) const;
    // The smallest region tile `index` renders: the tile, widened by its left, top or right
    // margin where that margin has pixels in tiles not marked done (every pixel of withMargins()
    // outside it lies in a done tile).
    PixelRect baseFor(size_t index) const;
    // Bytes keep() holds for tile `index`.
    uint64_t bytesFor(size_t index) const { return uint64_t(keptCount(m_index.tiles()[index])) * sizeof(glm::vec3); }
    // Keeps the base colours of tile `index`'s pixels that neighbours read: colorOf(x, y) for
    // each, its left column, two right columns and bottom row.
    template <class ColorOf>
    void keep(size_t index, ColorOf&& colorOf) {
        const PixelRect& t = m_index.tiles()[index];
        std::vector<glm::vec3>& k = m_kept[index];
        k.assign(keptCount(t), glm::vec3(0.0f));
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x)
                if (isKept(t, x, y)) k[slot(t, x, y)] = colorOf(x, y);
    }
    // Tile `index` is done: what it kept may be read.
    void markDone(size_t index) { m_done[index].store(1, std::memory_order_release); }
    // The base colour kept of pixel (x, y), a margin pixel of a tile whose neighbours are done.
    const glm::vec3& colorAt(int x, int y) const;

private:
    static bool isKept(const PixelRect& t, int x, int y) { return x == t.x0 || x >= t.x1 - 2 || y == t.y1 - 1; }
    // Three per row above the bottom one (left column, two right columns), then the bottom row.
    static size_t keptCount(const PixelRect& t) { return size_t(t.height() - 1) * 3 + size_t(t.width()); }
    static size_t slot(const PixelRect& t, int x, int y) {
        if (y == t.y1 - 1) return size_t(t.height() - 1) * 3 + size_t(x - t.x0);
        const size_t k = x == t.x0 ? 0 : x == t.x1 - 2 ? 1 : 2;
        return size_t(y - t.y0) * 3 + k;
    }

    const TileIndex& m_index;
    std::vector<std::vector<glm::vec3>> m_kept;
    std::unique_ptr<std::atomic<uint8_t>[]> m_done;
};

}  // namespace pushpin::render
