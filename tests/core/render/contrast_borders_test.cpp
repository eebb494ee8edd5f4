#include "core/render/contrast_borders.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace pushpin::render {
namespace {

glm::vec3 colourOf(int x, int y) { return glm::vec3(float(x), float(y), float(x * 100 + y)); }

// A 3 × 2 grid of 8 × 8 tiles: a tile renders its margins only where they lie in tiles not done,
// and reads the rest from what the done tiles kept.
TEST(ContrastBorders, RendersOnlyTheMarginsOfTilesNotDone) {
    const PixelRect region{0, 0, 24, 16};
    std::vector<PixelRect> tiles;
    for (int ty = 0; ty < 2; ++ty)
        for (int tx = 0; tx < 3; ++tx) tiles.push_back({8 * tx, 8 * ty, 8 * tx + 8, 8 * ty + 8});
    const TileIndex index(region, tiles);
    ContrastBorders b(index);
    EXPECT_EQ(b.withMargins(tiles[0]), (PixelRect{0, 0, 9, 8})) << "the region's edges cut the margins";
    EXPECT_EQ(b.withMargins(tiles[4]), (PixelRect{6, 7, 17, 16}));
    // Nothing done: every margin is rendered.
    EXPECT_EQ(b.baseFor(4), (PixelRect{6, 7, 17, 16}));
    EXPECT_EQ(b.baseFor(0), (PixelRect{0, 0, 9, 8}));
    auto finish = [&](size_t i) {
        b.keep(i, colourOf);
        b.markDone(i);
    };
    // Row by row: the top row done, and the tile to the left: only the right margin is rendered.
    for (size_t i : {size_t(0), size_t(1), size_t(2), size_t(3)}) finish(i);
    EXPECT_EQ(b.baseFor(4), (PixelRect{8, 8, 17, 16}));
    for (int y = 7; y < 16; ++y)
        for (int x = 6; x < 8; ++x) EXPECT_EQ(b.colorAt(x, y), colourOf(x, y)) << x << "," << y;
    for (int x = 6; x < 17; ++x) EXPECT_EQ(b.colorAt(x, 7), colourOf(x, 7)) << x;
    EXPECT_THROW((void)b.colorAt(16, 9), std::logic_error) << "tile 5 is not done";
    finish(5);
    EXPECT_EQ(b.baseFor(4), tiles[4]) << "every neighbour done: no apron";
    EXPECT_EQ(b.colorAt(16, 9), colourOf(16, 9));
    EXPECT_EQ(b.bytesFor(4), (7u * 3u + 8u) * sizeof(glm::vec3));
}

}  // namespace
}  // namespace pushpin::render
