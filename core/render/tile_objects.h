// core/render/tile_objects.h: which objects a tile rasterizes, and which it can leave out (DESIGN.md
// step 5a). A tile lists the units (objects, or pieces of a shape) whose screen boxes reach it,
// nearest first. NearOccluders tells whether a unit further back could be hidden by the nearer,
// possibly opaque ones rasterized before it (it then waits); OcclusionMap, built from the pixels'
// occluding depths once those are rasterized, tells whether a waiting unit lies behind them in
// every pixel it reaches, in which case it adds nothing to the image and is neither tessellated
// nor rasterized.
// Thread safety: plain values; one per thread.
// Memory: NearOccluders is a fixed array; OcclusionMap holds 4 bytes a pixel of the tile region
// and 4 bytes per 8×8 block.
#pragma once

#include "core/render/fragment.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pushpin::render {

// A unit's box on screen (continuous raster coordinates, edges included) and its depth keys.
struct ScreenBox {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    double nearKey = 0, farKey = 0;
};

// Whether `box` reaches `base` (touching its edges counts).
inline bool reaches(const ScreenBox& box, const PixelRect& base) {
    return !(box.x1 < base.x0 || box.x0 > base.x1 || box.y1 < base.y0 || box.y0 > base.y1);
}

// The pixels of `base` a box that reaches it covers, whole pixels from the floor of its edges.
PixelRect reachOf(const ScreenBox& box, const PixelRect& base);

// The pixels two rectangles share.
uint64_t overlapArea(const PixelRect& a, const PixelRect& b);

// Sorts unit indices nearest first: by `nearKey(i)`, then by index.
template <class NearKey>
void sortNearestFirst(std::vector<uint32_t>& units, NearKey&& nearKey) {
    std::sort(units.begin(), units.end(), [&](uint32_t a, uint32_t b) {
        const double ka = nearKey(a), kb = nearKey(b);
        return ka != kb ? ka < kb : a < b;
    });
}

// The nearer units of a tile that may hide the ones behind them: the kCount largest reaches met
// so far, so that the test stays linear in the tile's units.
class NearOccluders {
public:
    static constexpr size_t kCount = 32;
    void clear() { m_count = 0; }
    // Whether the occluders whose far ends lie before `nearKey` could cover `reach` between them:
    // their overlaps with it add up to its area at least. A conservative first test: only the
    // per-pixel depths (OcclusionMap) decide.
    bool mayHide(const PixelRect& reach, double nearKey) const;
    // A unit rasterized in the tile that may be opaque over `reach` as far as `farKey`; kept when
    // there is room or it is larger than the smallest kept.
    void add(const PixelRect& reach, double farKey);
    size_t size() const { return m_count; }

private:
    struct Occluder {
        PixelRect reach;
        uint64_t area = 0;
        double farKey = 0;
    };
    std::array<Occluder, kCount> m_occluders{};
    size_t m_count = 0;
};

// The occluding depth of each pixel of a tile region (PixelResolver::occludingDepth: behind it
// the fragments rasterized so far hide everything; +infinity where they do not), and the farthest
// of them per 8×8 block.
class OcclusionMap {
public:
    static constexpr int kBlock = 8;
    // Every pixel of `region` occluding nothing.
    void reset(const PixelRect& region);
    void set(int x, int y, float occludingDepth) { m_depth[index(x, y)] = occludingDepth; }
    float at(int x, int y) const { return m_depth[index(x, y)]; }
    // Computes the blocks' farthest depths; call after the last set().
    void finish();
    // Whether a unit whose depth keys are all at least `nearKey` lies behind the occluding depth
    // (occludedBehind) of every pixel of `reach` (within the region). The blocks answer first: a
    // unit behind the farthest depth of the blocks its reach meets is behind every pixel of them.
    bool hides(const PixelRect& reach, double nearKey) const;
    uint64_t bytes() const;
    void release();

private:
    size_t index(int x, int y) const { return size_t(y - m_region.y0) * size_t(m_region.width()) + size_t(x - m_region.x0); }
    PixelRect m_region;
    int m_blocksX = 0;
    std::vector<float> m_depth;
    std::vector<float> m_blockSeal;
};

}  // namespace pushpin::render
