#include "core/render/tile_objects.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace pushpin::render {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(TileObjects, ReachIsTheWholePixelsOfTheBoxWithinTheTile) {
    const PixelRect base{16, 32, 48, 64};
    EXPECT_EQ(reachOf(ScreenBox{0, 0, 100, 100, 1, 2}, base), base);
    EXPECT_EQ(reachOf(ScreenBox{20.5, 40.0, 22.25, 40.0, 1, 2}, base), (PixelRect{20, 40, 23, 41}));
    EXPECT_EQ(reachOf(ScreenBox{47.9, 63.5, 60, 70, 1, 2}, base), (PixelRect{47, 63, 48, 64}));
    EXPECT_TRUE(reaches(ScreenBox{48, 64, 50, 70, 1, 2}, base));  // touching the corner
    EXPECT_FALSE(reaches(ScreenBox{48.01, 10, 50, 70, 1, 2}, base));
    EXPECT_EQ(overlapArea(PixelRect{0, 0, 10, 10}, PixelRect{5, 8, 20, 20}), 10u);
    EXPECT_EQ(overlapArea(PixelRect{0, 0, 10, 10}, PixelRect{10, 0, 20, 10}), 0u);
}

TEST(TileObjects, NearestFirstThenByIndex) {
    const std::vector<double> keys = {3.0, 1.0, 2.0, 1.0, -kInf};
    std::vector<uint32_t> units = {0, 1, 2, 3, 4};
    sortNearestFirst(units, [&](uint32_t i) { return keys[i]; });
    EXPECT_EQ(units, (std::vector<uint32_t>{4, 1, 3, 2, 0}));
}

TEST(NearOccluders, MayHideOnlyWhatNearerBoxesCoverBetweenThem) {
    NearOccluders o;
    const PixelRect reach{0, 0, 10, 10};
    EXPECT_FALSE(o.mayHide(reach, 5.0));
    o.add({0, 0, 10, 6}, 2.0);  // 60 pixels, ending at depth 2
    EXPECT_FALSE(o.mayHide(reach, 5.0));
    o.add({0, 6, 10, 10}, 4.0);  // the other 40
    EXPECT_TRUE(o.mayHide(reach, 5.0));
    EXPECT_FALSE(o.mayHide(reach, 3.0));  // the second ends behind it
    EXPECT_FALSE(o.mayHide(reach, kInf));  // reaching the near plane: never waits
    EXPECT_FALSE(o.mayHide(PixelRect{3, 3, 3, 9}, 5.0));  // empty reach
    o.add({0, 0, 10, 10}, kInf);  // a far end that is not finite hides nothing
    EXPECT_EQ(o.size(), 2u);
}

TEST(NearOccluders, KeepsTheLargestBoxesWhenFull) {
    NearOccluders o;
    for (size_t k = 0; k < NearOccluders::kCount; ++k) o.add({int(k), 0, int(k) + 1, 1}, 1.0);
    EXPECT_FALSE(o.mayHide(PixelRect{100, 0, 110, 10}, 5.0));
    o.add({100, 0, 110, 10}, 1.0);  // larger than every one kept: replaces one of them
    EXPECT_EQ(o.size(), NearOccluders::kCount);
    EXPECT_TRUE(o.mayHide(PixelRect{100, 0, 110, 10}, 5.0));
    o.add({200, 0, 201, 1}, 1.0);  // no larger than any kept: dropped
    EXPECT_FALSE(o.mayHide(PixelRect{200, 0, 201, 1}, 5.0));
}

TEST(OcclusionMap, HidesOnlyWhatLiesBehindEveryPixelItReaches) {
    OcclusionMap m;
    const PixelRect region{8, 8, 28, 25};  // 20 × 17: partial blocks at the right and bottom
    m.reset(region);
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) m.set(x, y, 1.0f);
    m.set(27, 24, 3.0f);  // the last pixel is closed only at depth 3
    m.finish();
    EXPECT_TRUE(m.hides(region, 4.0));
    EXPECT_FALSE(m.hides(region, 2.0));
    EXPECT_TRUE(m.hides(PixelRect{8, 8, 27, 24}, 2.0));  // every pixel but the last
    EXPECT_FALSE(m.hides(PixelRect{26, 23, 28, 25}, 2.0));
    EXPECT_FALSE(m.hides(PixelRect{8, 8, 8, 20}, 4.0));  // empty
    EXPECT_FALSE(m.hides(region, kInf));
    // A pixel nothing closes hides nothing behind it.
    m.reset(region);
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x)
            if (x != 12 || y != 20) m.set(x, y, 1.0f);
    m.finish();
    EXPECT_FALSE(m.hides(region, 100.0));
    EXPECT_TRUE(m.hides(PixelRect{13, 8, 28, 25}, 100.0));
    EXPECT_GT(m.bytes(), 0u);
    m.release();
    EXPECT_EQ(m.bytes(), 0u);
}

}  // namespace
}  // namespace pushpin::render
