// core/render/filter_borders.h: what neighbouring tiles share for the multi-pixel filter (DESIGN.md
// step 6d), so that no tile renders its neighbours' pixels for it.
//
// A tile filters a pixel itself when the pixel's whole filter window (its pixels within the
// filter's reach, inside the rendered region) lies in the tile. The other pixels, those near an
// edge the tile shares with another tile, are filtered from the surfaces the tiles keep of their
// pixels near such edges: a tile keeps (keep) every pixel within twice the reach of a shared edge,
// which is every pixel a border pixel's window can reach. When a tile is done (tileDone), every
// tile near it (within the reach, itself included) whose near tiles are now all done has its
// border pixels filtered, and what a tile kept is let go once every tile near it is filtered. So
// what is kept at any time is the band along the edge between done and not-done tiles.
// The sum runs over the window's pixels row by row, then over each pixel's surfaces in order
// (gatherFiltered), wherever it is done, so that the image is the same for any tile plan.
//
// Thread safety: keep() and tileDone() may be called by any number of threads at once for
// different tiles; keep() may be called again for a tile until its tileDone(), which is called
// once per tile.
// Memory: the kept surfaces (28 bytes each) and a 4-byte start per pixel of each tile's kept
// band; bytesFor() says what a keep() will hold, for the caller to charge first; the Release
// callback of tileDone says when it is let go.
#pragma once

#include "core/render/fragment.h"
#include "core/render/pixel_filter.h"
#include "core/render/tile_index.h"
#include "core/render/visibility.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace pushpin::render {

// One surface of a pixel as the filter reads it: its contribution and its norm (filterNorm).
struct FilterSurface {
    SurfaceContribution contribution;
    float norm = 0.0f;
};

// The filtered colour (c, premultiplied) and alpha (a, not clamped) of pixel (x, y): the share
// (filterShare) of every surface of the pixels of `sources` within the filter's reach, row by
// row, column by column, surface by surface as forEachSurface(sx, sy, visit) hands them to
// visit(contribution, norm).
template <class ForEachSurface>
void gatherFiltered(const PixelFilter& filter, const PixelRect& sources, int x, int y, ForEachSurface&& forEachSurface,
                    double c[3], double& a) {
    const int reach = filter.reach;
    for (int sy = std::max(sources.y0, y - reach); sy <= std::min(sources.y1 - 1, y + reach); ++sy)
        for (int sx = std::max(sources.x0, x - reach); sx <= std::min(sources.x1 - 1, x + reach); ++sx)
            forEachSurface(sx, sy, [&](const SurfaceContribution& s, float norm) {
                const double wgt = filterShare(filter, norm, sx, sy, s.cu, s.cv, x, y);
                if (wgt == 0.0) return;
                c[0] += wgt * s.color[0], c[1] += wgt * s.color[1], c[2] += wgt * s.color[2];
                a += wgt * s.alpha;
            });
}

class FilterBorders {
public:
    // For the tiles of `index` (which must outlive this) under `filter` (reach > 0).
    FilterBorders(const PixelFilter& filter, const TileIndex& index);

    // Whether pixel (x, y) of `tile` has its whole filter window inside the tile (within the region).
    bool completeIn(const PixelRect& tile, int x, int y) const { return within(tile, x, y, m_filter.reach); }
    // Whether a pixel filtered at the end may read pixel (x, y) of `tile`.
    bool needed(const PixelRect& tile, int x, int y) const { return !within(tile, x, y, 2 * m_filter.reach); }

    // Bytes keep() holds for a tile whose needed pixels have `surfaces` surfaces in all.
    static uint64_t bytesFor(const PixelRect& tile, uint64_t surfaces) {
        return (uint64_t(tile.width()) * uint64_t(tile.height()) + 1) * sizeof(uint32_t) + surfaces * sizeof(FilterSurface);
    }
    // Keeps the surfaces of the needed pixels of tile `index`: surfacesOf(x, y) gives a pixel's
    // surfaces as a span of FilterSurface (asked once per needed pixel, row by row).
    template <class SurfacesOf>
    void keep(size_t index, SurfacesOf&& surfacesOf) {
        Kept& k = m_kept.at(index);
        const PixelRect& t = m_index.tiles()[index];
        k.start.assign(size_t(t.width()) * size_t(t.height()) + 1, 0);
        k.surfaces.clear();
        size_t i = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x, ++i) {
                k.start[i] = uint32_t(k.surfaces.size());
                if (!needed(t, x, y)) continue;
                const std::span<const FilterSurface> s = surfacesOf(x, y);
                k.surfaces.insert(k.surfaces.end(), s.begin(), s.end());
            }
        k.start[i] = uint32_t(k.surfaces.size());
    }
    // Tile `index`, kept, is done: the border pixels of every tile near it whose near tiles are
    // now all done are filtered, write(x, y, c, a) with gatherFiltered's sums, each pixel once;
    // then released(t) for every tile t whose kept surfaces are let go.
    using Write = std::function<void(int x, int y, const double* c, double a)>;
    using Released = std::function<void(size_t tile)>;
    void tileDone(size_t index, const Write& write, const Released& released);
    // Whether every tile is done and filtered.
    bool allFiltered() const;

private:
    struct Kept {
        std::vector<uint32_t> start;  // per pixel of the tile, row by row, then the end
        std::vector<FilterSurface> surfaces;
    };
    // Whether the pixels within `r` of (x, y), inside the region, all lie in `tile`.
    bool within(const PixelRect& tile, int x, int y, int r) const {
        const PixelRect& region = m_index.region();
        return std::max(x - r, region.x0) >= tile.x0 && std::min(x + r, region.x1 - 1) < tile.x1 &&
               std::max(y - r, region.y0) >= tile.y0 && std::min(y + r, region.y1 - 1) < tile.y1;
    }
    // Filters the pixels of tile `index` that are not complete in it.
    void filterBorders(size_t index, const Write& write) const;
    // The surfaces kept of pixel (x, y).
    std::span<const FilterSurface> surfacesAt(int x, int y) const;

    PixelFilter m_filter;
    const TileIndex& m_index;
    std::vector<Kept> m_kept;
    // The tiles near tile t (within the reach of it, t included): m_near[m_nearStart[t] ..
    // m_nearStart[t + 1]). m_waiting[t]: near tiles not done yet; m_readers[t]: near tiles whose
    // border pixels are not filtered yet.
    std::vector<uint32_t> m_nearStart, m_near;
    std::unique_ptr<std::atomic<uint32_t>[]> m_waiting, m_readers;
};

}  // namespace pushpin::render
