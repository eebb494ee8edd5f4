// Tests for core/render/tile_plan.h: tileCost on hand-worked cost maps (fractions of a box's
// width, rows partly covered, zero-width and zero-height boxes, bad entries), the adaptive plan
// (which tiles split, the 16×16 floor and overCost, odd and small regions, unlimited limits,
// exact cover, determinism) and the --tile-pattern picture and its file.
#include "core/render/tile_plan.h"

#include "cache/error.h"
#include "tests/support/image_read.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() / ("pushpin_tile_plan_" + std::to_string(rd()) + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& e : fs::recursive_directory_iterator(path)) names.push_back(fs::relative(e.path(), path).string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

// How many tiles of the plan hold each pixel of `region` (row-major), plus how many tile pixels
// fall outside it.
struct Cover {
    std::vector<int> count;
    long outside = 0;
};
Cover coverOf(const TilePlan& plan, const PixelRect& region) {
    Cover c;
    c.count.assign(size_t(region.width()) * size_t(region.height()), 0);
    for (const PixelRect& t : plan.tiles)
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (!region.contains(x, y)) ++c.outside;
                else ++c.count[size_t(y - region.y0) * size_t(region.width()) + size_t(x - region.x0)];
            }
    return c;
}

void expectExactCover(const TilePlan& plan, const PixelRect& region) {
    const Cover c = coverOf(plan, region);
    EXPECT_EQ(c.outside, 0);
    EXPECT_TRUE(std::all_of(c.count.begin(), c.count.end(), [](int n) { return n == 1; }))
        << "some pixel of " << region << " is in no tile or in two";
}

size_t tilesOfSize(const TilePlan& plan, int w, int h) {
    return size_t(std::count_if(plan.tiles.begin(), plan.tiles.end(),
                                [&](const PixelRect& t) { return t.width() == w && t.height() == h; }));
}

// ------------------------------------------------------------------------------------ tileCost

TEST(TilePlanCost, EmptyTileAndNoObjectsCostNothing) {
    const std::vector<ScreenCost> one = {{0, 0, 10, 10, 5}};
    EXPECT_EQ(tileCost({0, 0, 16, 16}, {}), 0.0);
    EXPECT_EQ(tileCost({4, 4, 4, 20}, one), 0.0);
    EXPECT_EQ(tileCost({20, 0, 36, 16}, one), 0.0);  // beside the box
}

TEST(TilePlanCost, WholeBoxInsideCountsItsFullCost) {
    const std::vector<ScreenCost> one = {{3.25, 1.5, 9.75, 6.5, 7}};
    EXPECT_EQ(tileCost({0, 0, 16, 16}, one), 7.0);
}

TEST(TilePlanCost, FractionOfWidthInsideTheTileColumns) {
    // Box x in [10, 30]: the tile's columns [0, 20) hold half of it, [20, 40) the other half.
    const std::vector<ScreenCost> one = {{10, 0, 30, 4, 8}};
    EXPECT_DOUBLE_EQ(tileCost({0, 0, 20, 16}, one), 4.0);
    EXPECT_DOUBLE_EQ(tileCost({20, 0, 40, 16}, one), 4.0);
    EXPECT_DOUBLE_EQ(tileCost({12, 0, 17, 16}, one), 8.0 * 5.0 / 20.0);
    // Reaching off screen: [-100, 100] of which [0, 50) is a quarter.
    const std::vector<ScreenCost> wide = {{-100, -5, 100, 5, 12}};
    EXPECT_DOUBLE_EQ(tileCost({0, 0, 50, 16}, wide), 3.0);
}

TEST(TilePlanCost, MostExpensiveRowWithRowsPartlyCovered) {
    // A: x [10, 30] y [2.5, 4.2], 8/scanline → 4 in columns [0, 20), on rows 2, 3, 4.
    // B: x [15, 25] y [4, 6],     6/scanline → 3 in columns [0, 20), on rows 4, 5.
    // Row 4 holds both: 7. Rows 5..7 only B: 3. Rows 0..3 only A at most: 4.
    const std::vector<ScreenCost> objects = {{10, 2.5, 30, 4.2, 8}, {15, 4, 25, 6, 6}};
    EXPECT_DOUBLE_EQ(tileCost({0, 0, 20, 8}, objects), 7.0);
    EXPECT_DOUBLE_EQ(tileCost({0, 5, 20, 8}, objects), 3.0);
    EXPECT_DOUBLE_EQ(tileCost({0, 0, 20, 4}, objects), 4.0);
    EXPECT_DOUBLE_EQ(tileCost({0, 4, 20, 5}, objects), 7.0);
    // Columns [20, 40): A gives 4, B gives 3, still both on row 4.
    EXPECT_DOUBLE_EQ(tileCost({20, 0, 40, 8}, objects), 7.0);
    // Columns [16, 24): A 8·8/20 = 3.2, B 6·8/10 = 4.8: row 4 costs 8.
    EXPECT_DOUBLE_EQ(tileCost({16, 0, 24, 8}, objects), 8.0);
}

TEST(TilePlanCost, RowsTouchedOnlyAtAnEndAreNotCovered) {
    const std::vector<ScreenCost> one = {{0, 0, 10, 4, 5}};  // rows 0..3
    EXPECT_EQ(tileCost({0, 4, 16, 8}, one), 0.0);
    EXPECT_EQ(tileCost({0, 3, 16, 4}, one), 5.0);
    // Columns touched only at an end count nothing either.
    EXPECT_EQ(tileCost({10, 0, 20, 4}, one), 0.0);
}

TEST(TilePlanCost, ZeroWidthBoxCountsWholeInTheColumnThatHoldsIt) {
    const std::vector<ScreenCost> line = {{20, 0, 20, 8, 9}};
    EXPECT_EQ(tileCost({0, 0, 20, 8}, line), 0.0);
    EXPECT_EQ(tileCost({20, 0, 40, 8}, line), 9.0);
    EXPECT_EQ(tileCost({19, 0, 21, 8}, line), 9.0);
    // Zero height: only the row that holds y = 5.
    const std::vector<ScreenCost> flat = {{0, 5, 10, 5, 6}};
    EXPECT_EQ(tileCost({0, 0, 16, 5}, flat), 0.0);
    EXPECT_EQ(tileCost({0, 5, 16, 6}, flat), 6.0);
    // A point counts whole in the one pixel holding it.
    const std::vector<ScreenCost> point = {{3.5, 7.5, 3.5, 7.5, 2}};
    EXPECT_EQ(tileCost({3, 7, 4, 8}, point), 2.0);
    EXPECT_EQ(tileCost({4, 7, 5, 8}, point), 0.0);
}

TEST(TilePlanCost, BadEntriesAreIgnored) {
    const ScreenCost good = {2, 2, 12, 12, 10};
    const std::vector<ScreenCost> bad = {
        {kNaN, 0, 10, 10, 5},    {0, kNaN, 10, 10, 5},     {0, 0, kInf, 10, 5},   {-kInf, 0, 10, 10, 5},
        {0, 0, 10, 10, kNaN},    {0, 0, 10, 10, kInf},     {0, 0, 10, 10, -3},    {10, 0, 0, 10, 5},
        {0, 10, 10, 0, 5},       {-1e308, 0, 1e308, 10, 5}, {0, -1e308, 10, 1e308, 5},
    };
    for (const ScreenCost& b : bad) {
        const std::vector<ScreenCost> objects = {b, good, b};
        EXPECT_EQ(tileCost({0, 0, 16, 16}, objects), 10.0) << b;
    }
}

TEST(TilePlanCost, SameBitsForAnyOrderOfTheObjects) {
    std::mt19937 rng(20240611u);
    std::uniform_real_distribution<double> pos(-20.0, 80.0), size(0.0, 40.0), cost(0.0, 1000.0);
    std::vector<ScreenCost> objects;
    for (int i = 0; i < 300; ++i) {
        const double x = pos(rng), y = pos(rng);
        objects.push_back({x, y, x + size(rng), y + size(rng), cost(rng) / 3.0});
    }
    const PixelRect tiles[] = {{0, 0, 64, 64}, {7, 3, 29, 50}, {32, 32, 48, 40}};
    for (const PixelRect& tile : tiles) {
        const double reference = tileCost(tile, objects);
        EXPECT_GT(reference, 0.0);
        std::vector<ScreenCost> shuffled = objects;
        for (int round = 0; round < 6; ++round) {
            std::shuffle(shuffled.begin(), shuffled.end(), rng);
            EXPECT_EQ(tileCost(tile, shuffled), reference) << tile << " round " << round;
        }
        std::reverse(shuffled.begin(), shuffled.end());
        EXPECT_EQ(tileCost(tile, shuffled), reference) << tile;
    }
}

TEST(TilePlanCost, MatchesARowByRowSum) {
    // The sweep against the definition, summed row by row, on random boxes.
    std::mt19937 rng(7u);
    std::uniform_real_distribution<double> pos(-10.0, 50.0), size(0.0, 30.0), cost(0.5, 50.0);
    for (int trial = 0; trial < 40; ++trial) {
        std::vector<ScreenCost> objects;
        for (int i = 0; i < 25; ++i) {
            const double x = pos(rng), y = pos(rng);
            const double w = trial % 5 == 0 && i % 3 == 0 ? 0.0 : size(rng);
            objects.push_back({x, y, x + w, y + size(rng), cost(rng)});
        }
        const PixelRect tile = {int(pos(rng)), int(pos(rng)), 0, 0};
        const PixelRect t = {tile.x0, tile.y0, tile.x0 + 1 + int(rng() % 40), tile.y0 + 1 + int(rng() % 40)};
        double most = 0.0;
        for (int y = t.y0; y < t.y1; ++y) {
            double row = 0.0;
            for (const ScreenCost& o : objects) {
                const bool onRow = o.y1 > o.y0 ? (o.y0 < y + 1 && o.y1 > y) : (o.y0 >= y && o.y0 < y + 1);
                if (!onRow) continue;
                if (o.x1 == o.x0) {
                    if (o.x0 >= t.x0 && o.x0 < t.x1) row += o.trianglesPerScanline;
                } else {
                    const double inside = std::min(o.x1, double(t.x1)) - std::max(o.x0, double(t.x0));
                    if (inside > 0) row += o.trianglesPerScanline * inside / (o.x1 - o.x0);
                }
            }
            most = std::max(most, row);
        }
        EXPECT_NEAR(tileCost(t, objects), most, 1e-9 * std::max(1.0, most)) << t << " trial " << trial;
    }
}

// ------------------------------------------------------------------------------ planAdaptiveTiles

TEST(TilePlan, UnlimitedPlanIsTheFourQuadrants) {
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> heavy = {{0, 0, 256, 256, 1e9}};
    for (double limit : {0.0, -5.0, kInf, -kInf, kNaN}) {
        const TilePlan plan = planAdaptiveTiles(region, heavy, limit);
        ASSERT_EQ(plan.tiles.size(), 4u) << limit;
        EXPECT_EQ(plan.tiles[0], (PixelRect{0, 0, 128, 128}));
        EXPECT_EQ(plan.tiles[1], (PixelRect{128, 0, 256, 128}));
        EXPECT_EQ(plan.tiles[2], (PixelRect{0, 128, 128, 256}));
        EXPECT_EQ(plan.tiles[3], (PixelRect{128, 128, 256, 256}));
        EXPECT_EQ(plan.maxTileCost, kInf);
        EXPECT_EQ(plan.overCost, 0u);
        ASSERT_EQ(plan.cost.size(), 4u);
        EXPECT_DOUBLE_EQ(plan.cost[0], 0.5e9);
        EXPECT_EQ(plan.minSize, 128);
        EXPECT_EQ(plan.maxSize, 128);
    }
}

TEST(TilePlan, DenseQuadrantSplitsDownTo16AndTheRestStaysWhole) {
    // 128 triangles a scanline across the top-left quadrant: a tile w pixels wide inside it costs
    // w. Limit 20: 128 → 64 → 32 → 16 (16 <= 20 stops).
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> objects = {{0, 0, 128, 128, 128}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 20.0);
    EXPECT_EQ(plan.tiles.size(), 64u + 3u);
    EXPECT_EQ(tilesOfSize(plan, 16, 16), 64u);
    EXPECT_EQ(tilesOfSize(plan, 128, 128), 3u);
    EXPECT_EQ(plan.overCost, 0u);
    EXPECT_EQ(plan.minSize, 16);
    EXPECT_EQ(plan.maxSize, 128);
    for (size_t i = 0; i < plan.tiles.size(); ++i) {
        const PixelRect& t = plan.tiles[i];
        if (t.width() == 16) {
            EXPECT_LT(t.x1, 129);
            EXPECT_LT(t.y1, 129);
            EXPECT_DOUBLE_EQ(plan.cost[i], 16.0) << t;
        } else {
            EXPECT_EQ(plan.cost[i], 0.0) << t;
        }
    }
    expectExactCover(plan, region);
}

TEST(TilePlan, SmallDenseCornerSplitsOnlyAlongItsPath) {
    // One dense object in the top-left 8×8: only the tiles holding it split, down to the floor,
    // where the last one is still over and counted.
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> objects = {{0, 0, 8, 8, 100}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 10.0);
    // 3 quadrants + 3 of 64 + 3 of 32 + 4 of 16.
    EXPECT_EQ(plan.tiles.size(), 13u);
    EXPECT_EQ(tilesOfSize(plan, 128, 128), 3u);
    EXPECT_EQ(tilesOfSize(plan, 64, 64), 3u);
    EXPECT_EQ(tilesOfSize(plan, 32, 32), 3u);
    EXPECT_EQ(tilesOfSize(plan, 16, 16), 4u);
    ASSERT_EQ(plan.tiles[0], (PixelRect{0, 0, 16, 16}));
    EXPECT_EQ(plan.cost[0], 100.0);
    EXPECT_EQ(plan.overCost, 1u);
    expectExactCover(plan, region);
}

TEST(TilePlan, CostExactlyAtTheLimitDoesNotSplit) {
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> objects = {{0, 0, 128, 128, 128}};
    const TilePlan atLimit = planAdaptiveTiles(region, objects, 128.0);
    EXPECT_EQ(atLimit.tiles.size(), 4u);
    EXPECT_EQ(atLimit.cost[0], 128.0);
    EXPECT_EQ(atLimit.overCost, 0u);
    const TilePlan below = planAdaptiveTiles(region, objects, 127.999);
    EXPECT_EQ(below.tiles.size(), 7u);  // the quadrant into four 64s, each costing 64
    EXPECT_EQ(tilesOfSize(below, 64, 64), 4u);
}

TEST(TilePlan, FloorStopsSplittingAndCountsTilesStillOver) {
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> objects = {{0, 0, 256, 256, 1e6}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 1.0);
    EXPECT_EQ(plan.tiles.size(), 256u);
    EXPECT_EQ(tilesOfSize(plan, 16, 16), 256u);
    EXPECT_EQ(plan.overCost, 256u);
    EXPECT_EQ(plan.minSize, 16);
    EXPECT_EQ(plan.maxSize, 16);
    for (double c : plan.cost) EXPECT_DOUBLE_EQ(c, 1e6 * 16.0 / 256.0);
    // A larger floor gives larger tiles.
    const TilePlan coarse = planAdaptiveTiles(region, objects, 1.0, 32);
    EXPECT_EQ(coarse.tiles.size(), 64u);
    EXPECT_EQ(coarse.overCost, 64u);
    EXPECT_EQ(coarse.minSize, 32);
    // A floor below 1 is taken as 1: a 4×4 region ends as 16 single pixels.
    const TilePlan pixels = planAdaptiveTiles({0, 0, 4, 4}, objects, 1e-3, 0);
    EXPECT_EQ(pixels.tiles.size(), 16u);
    EXPECT_EQ(pixels.maxSize, 1);
}

TEST(TilePlan, OddSizedRegionWithAnOffset) {
    // 97 × 61 at (10, 5): quadrants split at x = 10 + 48, y = 5 + 30. Everything over the limit:
    // the columns 48 and 49 halve once more (24 | 24, 24 | 25), the rows 30 and 31 cannot
    // (15 < 16), so the quadrants split in two, not four.
    const PixelRect region = {10, 5, 107, 66};
    const std::vector<ScreenCost> objects = {{0, 0, 200, 200, 1e4}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 1.0);
    const std::vector<PixelRect> expected = {
        {10, 5, 34, 35},  {34, 5, 58, 35},  {58, 5, 82, 35},  {82, 5, 107, 35},
        {10, 35, 34, 66}, {34, 35, 58, 66}, {58, 35, 82, 66}, {82, 35, 107, 66},
    };
    EXPECT_EQ(plan.tiles, expected);
    EXPECT_EQ(plan.overCost, 8u);
    EXPECT_EQ(plan.minSize, 24);
    EXPECT_EQ(plan.maxSize, 31);
    expectExactCover(plan, region);
    // Unlimited: the quadrants of the odd region.
    const TilePlan quadrants = planAdaptiveTiles(region, objects, 0.0);
    const std::vector<PixelRect> four = {{10, 5, 58, 35}, {58, 5, 107, 35}, {10, 35, 58, 66}, {58, 35, 107, 66}};
    EXPECT_EQ(quadrants.tiles, four);
}

TEST(TilePlan, RegionNarrowerThan32StaysWholeAcross) {
    // 31 wide: halves would be 15 and 16, under the floor; 200 tall: 100, 50, 25, then 12 < 16.
    const PixelRect region = {0, 0, 31, 200};
    const std::vector<ScreenCost> objects = {{0, 0, 31, 200, 1e4}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 1.0);
    EXPECT_EQ(plan.tiles.size(), 8u);
    EXPECT_EQ(tilesOfSize(plan, 31, 25), 8u);
    for (size_t i = 0; i < plan.tiles.size(); ++i) EXPECT_EQ(plan.tiles[i].y0, int(i) * 25);
    EXPECT_EQ(plan.overCost, 8u);
    expectExactCover(plan, region);
    const TilePlan quadrants = planAdaptiveTiles(region, objects, 0.0);
    const std::vector<PixelRect> two = {{0, 0, 31, 100}, {0, 100, 31, 200}};
    EXPECT_EQ(quadrants.tiles, two);
    // Smaller than the floor both ways: one tile, over and counted.
    const TilePlan tiny = planAdaptiveTiles({0, 0, 10, 12}, objects, 1.0);
    ASSERT_EQ(tiny.tiles.size(), 1u);
    EXPECT_EQ(tiny.tiles[0], (PixelRect{0, 0, 10, 12}));
    EXPECT_EQ(tiny.overCost, 1u);
    EXPECT_EQ(tiny.minSize, 10);
    EXPECT_EQ(tiny.maxSize, 12);
}

TEST(TilePlan, EmptyRegionGivesAnEmptyPlan) {
    const std::vector<ScreenCost> objects = {{0, 0, 10, 10, 5}};
    const TilePlan plan = planAdaptiveTiles({5, 5, 5, 40}, objects, 1.0);
    EXPECT_TRUE(plan.tiles.empty());
    EXPECT_TRUE(plan.cost.empty());
    EXPECT_EQ(plan.minSize, 0);
    EXPECT_EQ(plan.maxSize, 0);
    EXPECT_EQ(plan.maxTileCost, 1.0);
}

TEST(TilePlan, BadEntriesDoNotChangeThePlan) {
    const PixelRect region = {0, 0, 256, 256};
    const std::vector<ScreenCost> good = {{0, 0, 100, 60, 300}, {150, 150, 160, 250, 40}};
    std::vector<ScreenCost> withBad = good;
    for (const ScreenCost& b : std::vector<ScreenCost>{{kNaN, 0, 256, 256, 1e9},
                                                       {0, 0, 256, kInf, 1e9},
                                                       {0, 0, 256, 256, kInf},
                                                       {0, 0, 256, 256, kNaN},
                                                       {0, 0, 256, 256, -1e9},
                                                       {256, 256, 0, 0, 1e9}})
        withBad.insert(withBad.begin() + 1, b);
    const TilePlan expected = planAdaptiveTiles(region, good, 25.0);
    const TilePlan plan = planAdaptiveTiles(region, withBad, 25.0);
    EXPECT_GT(expected.tiles.size(), 4u);
    EXPECT_EQ(plan.tiles, expected.tiles);
    EXPECT_EQ(plan.cost, expected.cost);
    EXPECT_EQ(plan.overCost, expected.overCost);
    for (double c : plan.cost) EXPECT_TRUE(std::isfinite(c));
}

// The properties every plan has, checked on seeded random regions, objects and limits.
TEST(TilePlan, RandomPlansCoverEveryPixelOnceAndKeepTheirPromises) {
    std::mt19937 rng(12345u);
    for (int trial = 0; trial < 60; ++trial) {
        const int x0 = int(rng() % 41) - 20, y0 = int(rng() % 41) - 20;
        const PixelRect region = {x0, y0, x0 + 1 + int(rng() % 400), y0 + 1 + int(rng() % 300)};
        const int minSize = trial % 4 == 0 ? int(1 + rng() % 40) : 16;
        std::uniform_real_distribution<double> px(region.x0 - 50.0, region.x1 + 50.0), py(region.y0 - 50.0, region.y1 + 50.0);
        std::uniform_real_distribution<double> size(0.0, 120.0), cost(0.0, 200.0);
        std::vector<ScreenCost> objects;
        const int count = int(rng() % 200);
        for (int i = 0; i < count; ++i) {
            const double x = px(rng), y = py(rng);
            objects.push_back({x, y, x + (i % 7 == 0 ? 0.0 : size(rng)), y + size(rng), cost(rng)});
        }
        const double limit = trial % 10 == 9 ? 0.0 : std::uniform_real_distribution<double>(1.0, 400.0)(rng);
        const TilePlan plan = planAdaptiveTiles(region, objects, limit, minSize);
        SCOPED_TRACE("trial " + std::to_string(trial));

        expectExactCover(plan, region);
        ASSERT_EQ(plan.cost.size(), plan.tiles.size());
        // Every side is at least min(minSize, the region's side), which bounds the count by area.
        const size_t smallestW = size_t(std::min(minSize, region.width()));
        const size_t smallestH = size_t(std::min(minSize, region.height()));
        EXPECT_LE(plan.tiles.size(), size_t(region.width()) * size_t(region.height()) / (smallestW * smallestH));
        size_t over = 0;
        int smallest = std::numeric_limits<int>::max(), largest = 0;
        for (size_t i = 0; i < plan.tiles.size(); ++i) {
            const PixelRect& t = plan.tiles[i];
            if (i > 0) {
                const PixelRect& p = plan.tiles[i - 1];
                EXPECT_TRUE(p.y0 < t.y0 || (p.y0 == t.y0 && p.x0 < t.x0)) << p << " before " << t;
            }
            EXPECT_GE(t.width(), std::min(minSize, region.width())) << t;
            EXPECT_GE(t.height(), std::min(minSize, region.height())) << t;
            // Each tile's cost is tileCost over all objects, to the bit.
            EXPECT_EQ(plan.cost[i], tileCost(t, objects)) << t;
            if (plan.cost[i] > plan.maxTileCost) {
                ++over;
                EXPECT_LT(t.width() / 2, minSize) << t;
                EXPECT_LT(t.height() / 2, minSize) << t;
            }
            smallest = std::min({smallest, t.width(), t.height()});
            largest = std::max({largest, t.width(), t.height()});
        }
        EXPECT_EQ(plan.overCost, over);
        EXPECT_EQ(plan.minSize, smallest);
        EXPECT_EQ(plan.maxSize, largest);
    }
}

TEST(TilePlan, SameInputSamePlanAndObjectOrderDoesNotMatter) {
    std::mt19937 rng(99u);
    std::uniform_real_distribution<double> pos(-100.0, 1100.0), size(0.0, 60.0), cost(0.0, 90.0);
    std::vector<ScreenCost> objects;
    for (int i = 0; i < 3000; ++i) {
        const double x = pos(rng), y = pos(rng);
        objects.push_back({x, y, x + size(rng), y + size(rng), cost(rng) / 7.0});
    }
    const PixelRect region = {0, 0, 1024, 1000};
    const TilePlan a = planAdaptiveTiles(region, objects, 40.0);
    const TilePlan b = planAdaptiveTiles(region, objects, 40.0);
    EXPECT_GT(a.tiles.size(), 100u);
    EXPECT_EQ(a.tiles, b.tiles);
    EXPECT_EQ(a.cost, b.cost);
    std::shuffle(objects.begin(), objects.end(), rng);
    const TilePlan c = planAdaptiveTiles(region, objects, 40.0);
    EXPECT_EQ(a.tiles, c.tiles);
    EXPECT_EQ(a.cost, c.cost);
    EXPECT_EQ(a.overCost, c.overCost);
    expectExactCover(a, region);
}

TEST(TilePlan, FixedGridIsUnchanged) {
    const std::vector<PixelRect> tiles = planTiles({0, 0, 100, 70}, 64, 64);
    const std::vector<PixelRect> expected = {{0, 0, 64, 64}, {64, 0, 100, 64}, {0, 64, 64, 70}, {64, 64, 100, 70}};
    EXPECT_EQ(tiles, expected);
}

TEST(TilePlan, SplitTilesKeepsCheapTilesAndSplitsDenseOnesToTheFloor) {
    // The fixed 64×64 grid of a 128×100 region; 256 triangles a scanline over x in [0, 32), y in
    // [0, 32): a tile w pixels wide inside it costs 8·w. Limit 200: the top-left tile (cost 256)
    // splits into 32×32 tiles, whose top-left (256) splits into 16×16 ones (128 each); the others
    // stay as they are.
    const PixelRect region = {0, 0, 128, 100};
    const std::vector<PixelRect> grid = planTiles(region, 64, 64);
    const std::vector<ScreenCost> objects = {{0, 0, 32, 32, 256}};
    const TilePlan plan = splitTiles(grid, objects, 200.0);
    EXPECT_EQ(plan.tiles.size(), 4u + 3u + 3u);
    EXPECT_EQ(tilesOfSize(plan, 16, 16), 4u);
    EXPECT_EQ(tilesOfSize(plan, 32, 32), 3u);
    EXPECT_EQ(tilesOfSize(plan, 64, 64), 1u);
    EXPECT_EQ(tilesOfSize(plan, 64, 36), 2u);
    EXPECT_EQ(plan.overCost, 0u);
    EXPECT_EQ(plan.minSize, 16);
    EXPECT_EQ(plan.maxSize, 64);
    EXPECT_DOUBLE_EQ(plan.maxTileCost, 200.0);
    for (size_t i = 1; i < plan.tiles.size(); ++i) {
        const PixelRect& a = plan.tiles[i - 1];
        const PixelRect& b = plan.tiles[i];
        EXPECT_TRUE(a.y0 < b.y0 || (a.y0 == b.y0 && a.x0 < b.x0)) << "not in (y0, x0) order at " << b;
    }
    expectExactCover(plan, region);
    // Unlimited, or a limit no tile passes: the grid itself.
    for (double limit : {kInf, 0.0, kNaN, 1e9}) {
        const TilePlan same = splitTiles(grid, objects, limit);
        EXPECT_EQ(same.tiles, grid) << limit;
    }
}

TEST(TilePlan, SplitTilesStopsAtTheFloorOfASmallFrame) {
    // A 64×36 frame in one tile, far over any limit: 16×18 tiles (36 rows halve once), each still
    // over the limit and counted.
    const PixelRect region = {0, 0, 64, 36};
    const std::vector<ScreenCost> objects = {{-10, -10, 80, 50, 1e6}};
    const TilePlan plan = splitTiles(planTiles(region, 64, 64), objects, 100.0);
    EXPECT_EQ(plan.tiles.size(), 8u);
    EXPECT_EQ(tilesOfSize(plan, 16, 18), 8u);
    EXPECT_EQ(plan.overCost, 8u);
    expectExactCover(plan, region);
}

// ------------------------------------------------------------------------------- tile pattern

struct Rgb {
    int r, g, b;
    bool operator==(const Rgb&) const = default;
};
std::ostream& operator<<(std::ostream& os, const Rgb& c) { return os << "(" << c.r << "," << c.g << "," << c.b << ")"; }

Rgb at(const std::vector<uint8_t>& image, int width, int x, int y) {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return {image[i], image[i + 1], image[i + 2]};
}

// Three tiles of a 16×16 region in a 20×20 picture; the bottom-right tile of the region is left
// out on purpose, so its pixels are in no tile.
TilePlan handPlan() {
    TilePlan plan;
    plan.tiles = {{0, 0, 8, 8}, {8, 0, 16, 8}, {0, 8, 8, 16}};
    plan.cost = {0.0, 10.0, 20.0};
    plan.maxTileCost = 10.0;
    return plan;
}

TEST(TilePlanPattern, ColoursOfInteriorBorderAndOutside) {
    const std::vector<uint8_t> image = tilePatternImage(handPlan(), 20, 20);
    ASSERT_EQ(image.size(), 20u * 20u * 3u);
    const Rgb blue = {13, 8, 135}, yellow = {240, 249, 33}, red = {220, 20, 20}, grey = {128, 128, 128};
    EXPECT_EQ(at(image, 20, 4, 4), blue);      // cost 0
    EXPECT_EQ(at(image, 20, 12, 4), yellow);   // cost at the limit
    EXPECT_EQ(at(image, 20, 4, 12), red);      // over the limit
    EXPECT_EQ(at(image, 20, 0, 0), (Rgb{6, 4, 67}));       // corner of the blue tile
    EXPECT_EQ(at(image, 20, 7, 3), (Rgb{6, 4, 67}));       // its right edge
    EXPECT_EQ(at(image, 20, 8, 3), (Rgb{120, 124, 16}));   // left edge of the yellow tile
    EXPECT_EQ(at(image, 20, 12, 7), (Rgb{120, 124, 16}));  // its bottom edge
    EXPECT_EQ(at(image, 20, 4, 15), (Rgb{110, 10, 10}));   // bottom edge of the red tile
    EXPECT_EQ(at(image, 20, 1, 1), blue);      // just inside the border
    EXPECT_EQ(at(image, 20, 12, 12), grey);    // in no tile
    EXPECT_EQ(at(image, 20, 18, 2), grey);     // outside the region
    EXPECT_EQ(at(image, 20, 19, 19), grey);
}

TEST(TilePlanPattern, RampMidpointsAndUnlimitedPlans) {
    TilePlan plan;
    plan.tiles = {{0, 0, 8, 8}, {8, 0, 16, 8}, {0, 8, 8, 16}, {8, 8, 16, 16}};
    plan.cost = {2.5, 5.0, 7.5, 10.0};
    plan.maxTileCost = kInf;  // unlimited: scaled by the most expensive tile, 10
    const std::vector<uint8_t> image = tilePatternImage(plan, 16, 16);
    EXPECT_EQ(at(image, 16, 4, 4), (Rgb{126, 3, 168}));     // 0.25: purple
    EXPECT_EQ(at(image, 16, 12, 4), (Rgb{204, 71, 120}));   // 0.5: pink
    EXPECT_EQ(at(image, 16, 4, 12), (Rgb{248, 149, 64}));   // 0.75: orange
    EXPECT_EQ(at(image, 16, 12, 12), (Rgb{240, 249, 33}));  // the most expensive: yellow, not red
    // An unlimited plan where nothing costs anything is all dark blue inside the tiles.
    plan.cost = {0, 0, 0, 0};
    EXPECT_EQ(at(tilePatternImage(plan, 16, 16), 16, 12, 12), (Rgb{13, 8, 135}));
}

TEST(TilePlanPattern, PictureOfAPlannedRegionAndDegenerateSizes) {
    const PixelRect region = {0, 0, 64, 48};
    const std::vector<ScreenCost> objects = {{0, 0, 32, 24, 64}};
    const TilePlan plan = planAdaptiveTiles(region, objects, 10.0);
    const std::vector<uint8_t> image = tilePatternImage(plan, 80, 48);
    // The region's pixels are never grey (no ramp colour is), the ones right of it are.
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 80; ++x)
            EXPECT_EQ(at(image, 80, x, y) == (Rgb{128, 128, 128}), x >= 64) << x << "," << y;
    EXPECT_TRUE(tilePatternImage(plan, 0, 10).empty());
    EXPECT_TRUE(tilePatternImage(plan, 10, -1).empty());
}

TEST(TilePlanPattern, WritesAReadablePngOfTheRightSize) {
    TempDir dir;
    const fs::path path = dir.path / "tiles.png";
    writeTilePattern(handPlan(), 20, 18, path);
    const test::ImageReadBack<uint8_t> r = test::readImage<uint8_t>(path);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.formatName, "png");
    EXPECT_EQ(r.width, 20);
    EXPECT_EQ(r.height, 18);
    ASSERT_EQ(r.channels, 3);
    EXPECT_EQ(r.pixels, tilePatternImage(handPlan(), 20, 18));
    EXPECT_EQ(dir.files(), std::vector<std::string>{"tiles.png"});
}

TEST(TilePlanPattern, UnwritablePathThrowsOutputErrorAndLeavesNoFile) {
    TempDir dir;
    // A regular file where the folder should be: no folder can be made there, whoever runs this.
    const fs::path blocker = dir.path / "blocker";
    std::ofstream(blocker) << "not a folder";
    const fs::path path = blocker / "sub" / "tiles.png";
    EXPECT_THROW(writeTilePattern(handPlan(), 20, 20, path), OutputError);
    EXPECT_EQ(dir.files(), std::vector<std::string>{"blocker"});
    // An existing file is only replaced by a whole new one: a failed write leaves it as it was.
    const fs::path ok = dir.path / "tiles.png";
    writeTilePattern(handPlan(), 20, 20, ok);
    const auto before = fs::file_size(ok);
    EXPECT_THROW(writeTilePattern(handPlan(), 0, 20, ok), IoError);
    EXPECT_EQ(fs::file_size(ok), before);
    EXPECT_THROW(writeTilePattern(handPlan(), 20, 20, dir.path / "tiles.nosuchformat"), Error);
    EXPECT_EQ(dir.files(), (std::vector<std::string>{"blocker", "tiles.png"}));
}

TEST(TileOrder, TheHilbertIndexWalksFromCellToNeighbouringCell) {
    for (int order : {1, 2, 3, 5}) {
        const uint32_t n = 1u << order;
        std::vector<std::pair<uint32_t, uint32_t>> cellAt(size_t(n) * n, {n, n});
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const uint64_t d = hilbertIndex(x, y, order);
                ASSERT_LT(d, uint64_t(n) * n);
                EXPECT_EQ(cellAt[d].first, n) << "index " << d << " given twice";
                cellAt[d] = {x, y};
            }
        EXPECT_EQ(cellAt[0], (std::pair<uint32_t, uint32_t>{0, 0}));
        for (size_t d = 1; d < cellAt.size(); ++d) {
            const int dx = int(cellAt[d].first) - int(cellAt[d - 1].first);
            const int dy = int(cellAt[d].second) - int(cellAt[d - 1].second);
            EXPECT_EQ(std::abs(dx) + std::abs(dy), 1) << "order " << order << " index " << d;
        }
    }
}

TEST(TileOrder, TilesAlongTheHilbertCurveAreTheSameTilesEachNextToTheLast) {
    // A 6 × 5 grid of 32 × 32 tiles, then an adaptive plan: the same tiles, and in the grid each
    // tile after the first shares an edge with the one before it.
    const std::vector<PixelRect> grid = planTiles(PixelRect{0, 0, 192, 160}, 32, 32);
    const std::vector<PixelRect> walked = alongHilbertCurve(grid);
    ASSERT_EQ(walked.size(), grid.size());
    EXPECT_TRUE(std::is_permutation(walked.begin(), walked.end(), grid.begin()));
    size_t apart = 0;
    for (size_t i = 1; i < walked.size(); ++i) {
        const PixelRect& a = walked[i - 1];
        const PixelRect& b = walked[i];
        const bool touch = (a.x1 == b.x0 || b.x1 == a.x0) ? a.y0 == b.y0 : (a.y1 == b.y0 || b.y1 == a.y0) && a.x0 == b.x0;
        apart += !touch;
    }
    // A 6 × 5 grid is not a power of two across, so the curve leaves it a few times.
    EXPECT_LE(apart, 4u);
    std::vector<ScreenCost> objects = {{10, 5, 90, 70, 400.0}, {120, 100, 180, 150, 2000.0}};
    const TilePlan plan = planAdaptiveTiles(PixelRect{0, 0, 192, 160}, objects, 300.0, 16);
    const std::vector<PixelRect> planned = alongHilbertCurve(plan.tiles);
    EXPECT_TRUE(std::is_permutation(planned.begin(), planned.end(), plan.tiles.begin()));
    EXPECT_EQ(alongHilbertCurve(planned), planned);
    EXPECT_TRUE(alongHilbertCurve({}).empty());
}

}  // namespace
}  // namespace pushpin::render
