#include "core/render/filter_borders.h"

#include <gtest/gtest.h>

#include <map>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

namespace pushpin::render {
namespace {

PixelFilter reachOf(int reach) {
    PixelFilter f;
    f.type = 2;
    f.radiusX = f.radiusY = 0.5 + reach;
    f.reach = reach;
    return f;
}

// Four 8×8 tiles over a 16×16 region, reach 1: a pixel is complete in its tile unless it touches
// an edge the tile shares; the kept band is two pixels wide along shared edges only.
TEST(FilterBorders, BorderPixelsAndTheKeptBandFollowSharedEdgesOnly) {
    const PixelRect region{0, 0, 16, 16};
    const std::vector<PixelRect> tiles{{0, 0, 8, 8}, {8, 0, 16, 8}, {0, 8, 8, 16}, {8, 8, 16, 16}};
    const TileIndex index(region, tiles);
    const FilterBorders b(reachOf(1), index);
    const PixelRect& t = tiles[0];
    EXPECT_TRUE(b.completeIn(t, 0, 0)) << "the region's corner";
    EXPECT_TRUE(b.completeIn(t, 6, 6));
    EXPECT_FALSE(b.completeIn(t, 7, 6)) << "next to the right neighbour";
    EXPECT_FALSE(b.completeIn(t, 3, 7)) << "next to the neighbour below";
    EXPECT_TRUE(b.completeIn(t, 0, 6));
    EXPECT_TRUE(b.needed(t, 6, 0)) << "within two of the right edge";
    EXPECT_FALSE(b.needed(t, 5, 0));
    EXPECT_FALSE(b.needed(t, 5, 5));
    EXPECT_TRUE(b.needed(t, 5, 6));
    EXPECT_FALSE(b.needed(t, 0, 0));
    // One tile over the region: every pixel is complete and none is kept.
    const std::vector<PixelRect> one{region};
    const TileIndex wholeIndex(region, one);
    const FilterBorders whole(reachOf(2), wholeIndex);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            EXPECT_TRUE(whole.completeIn(region, x, y));
            EXPECT_FALSE(whole.needed(region, x, y));
        }
}

// Every border pixel is filtered once, when the tiles around it are done, from the surfaces of the
// pixels around it whichever tile kept them, in the order a tile sums its own; what a tile kept
// is let go once.
TEST(FilterBorders, FiltersEachBorderPixelOnceFromItsNeighboursSurfaces) {
    const PixelRect region{0, 0, 13, 11};
    const std::vector<PixelRect> tiles{{0, 0, 5, 4}, {5, 0, 13, 4}, {0, 4, 9, 11}, {9, 4, 13, 11}};
    const PixelFilter filter = reachOf(1);
    const TileIndex index(region, tiles);
    FilterBorders b(filter, index);
    // Pixel (x, y) has (x + y) % 3 surfaces, each of its own colour.
    auto surfacesOfPixel = [&](int x, int y) {
        std::vector<FilterSurface> out;
        for (int k = 0; k < (x + y) % 3; ++k) {
            FilterSurface s;
            s.contribution.color[0] = float(x + 100 * y + k);
            s.contribution.alpha = 0.25f;
            s.contribution.cu = 0.25f + 0.25f * float(k);
            s.contribution.cv = 0.5f;
            s.norm = float(filterNorm(filter, region, x, y, s.contribution.cu, s.contribution.cv));
            out.push_back(s);
        }
        return out;
    };
    std::vector<FilterSurface> scratch;
    std::map<std::pair<int, int>, int> written;
    std::map<std::pair<int, int>, std::pair<double, double>> got;
    std::map<size_t, int> released;
    auto write = [&](int x, int y, const double* c, double a) {
        ++written[std::make_pair(x, y)];
        got[std::make_pair(x, y)] = {c[0], a};
    };
    // Tiles done in an order that is not the tiles' own; a pixel is filtered only once every tile
    // its window meets is done.
    for (size_t i : {size_t(2), size_t(0), size_t(3), size_t(1)}) {
        b.keep(i, [&](int x, int y) {
            scratch = surfacesOfPixel(x, y);
            return std::span<const FilterSurface>(scratch);
        });
        EXPECT_FALSE(b.allFiltered());
        b.tileDone(i, write, [&](size_t t) { ++released[t]; });
        if (i == 2) {
            EXPECT_TRUE(written.empty()) << "tile 2 borders three tiles not done";
        }
    }
    EXPECT_TRUE(b.allFiltered());
    EXPECT_EQ(released.size(), tiles.size());
    for (const auto& [t, n] : released) EXPECT_EQ(n, 1) << "tile " << t;
    size_t borders = 0;
    for (const PixelRect& t : tiles)
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (b.completeIn(t, x, y)) {
                    EXPECT_EQ(written.count(std::make_pair(x, y)), 0u);
                    continue;
                }
                ++borders;
                ASSERT_EQ(written[std::make_pair(x, y)], 1) << x << "," << y;
                double c[3] = {0, 0, 0}, a = 0.0;
                gatherFiltered(
                    filter, region, x, y,
                    [&](int sx, int sy, auto&& visit) {
                        for (const FilterSurface& s : surfacesOfPixel(sx, sy)) visit(s.contribution, s.norm);
                    },
                    c, a);
                EXPECT_EQ(got[std::make_pair(x, y)].first, c[0]) << x << "," << y;
                EXPECT_EQ(got[std::make_pair(x, y)].second, a) << x << "," << y;
            }
    EXPECT_EQ(written.size(), borders);
    EXPECT_GT(borders, 20u);
}

}  // namespace
}  // namespace pushpin::render
