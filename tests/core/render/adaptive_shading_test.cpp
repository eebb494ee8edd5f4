// Tests for core/render/adaptive_shading.h: the contrast test on hand-worked colour grids (which
// neighbours it reads, the region's edge, clamping at 0, the excess formula per channel) and the
// number of samples an excess asks for.
#include "core/render/adaptive_shading.h"

#include <gtest/gtest.h>

#include <vector>

namespace pushpin::render {
namespace {

// A 5×4 grid of grey pixels at (10, 20)..(15, 24) with one pixel set apart.
struct Grid {
    PixelRect rect{10, 20, 15, 24};
    std::vector<glm::vec3> colors = std::vector<glm::vec3>(20, glm::vec3(0.5f));
    glm::vec3& at(int x, int y) { return colors[size_t(y - rect.y0) * 5 + size_t(x - rect.x0)]; }
};

const double kThresholds[3] = {0.4, 0.4, 0.4};

TEST(AdaptiveShading, UniformColoursNeedNoExtraSamples) {
    Grid g;
    for (int y = g.rect.y0; y < g.rect.y1; ++y)
        for (int x = g.rect.x0; x < g.rect.x1; ++x) EXPECT_EQ(contrastExcess(g.colors, g.rect, g.rect, x, y, kThresholds), 0.0);
}

// Only the neighbours shaded before the pixel in scanline order count: W, WW, NW, N, NE.
TEST(AdaptiveShading, ReadsTheFiveNeighboursShadedBefore) {
    const int x = 12, y = 22;
    const std::pair<int, int> before[] = {{-1, 0}, {-2, 0}, {-1, -1}, {0, -1}, {1, -1}};
    const std::pair<int, int> after[] = {{1, 0}, {2, 0}, {-1, 1}, {0, 1}, {1, 1}, {-2, -1}, {2, -1}, {0, -2}};
    // Red 0.9 against 0.1: contrast 0.8, excess (0.8 − 0.4) / 0.6 = 2/3.
    for (auto [dx, dy] : before) {
        Grid g;
        for (auto& c : g.colors) c = glm::vec3(0.1f, 0.5f, 0.5f);
        g.at(x + dx, y + dy).r = 0.9f;
        const double contrast = (double(0.9f) - double(0.1f)) / (double(0.9f) + double(0.1f));
        EXPECT_NEAR(contrastExcess(g.colors, g.rect, g.rect, x, y, kThresholds), (contrast - 0.4) / 0.6, 1e-12)
            << dx << "," << dy;
    }
    for (auto [dx, dy] : after) {
        Grid g;
        g.at(x + dx, y + dy) = glm::vec3(1.0f, 0.0f, 0.0f);
        EXPECT_EQ(contrastExcess(g.colors, g.rect, g.rect, x, y, kThresholds), 0.0) << dx << "," << dy;
    }
}

TEST(AdaptiveShading, NeighboursOutsideTheRegionAreNotRead) {
    Grid g;
    g.at(10, 21) = glm::vec3(1.0f, 0.0f, 0.0f);  // west of (11, 21)
    EXPECT_GT(contrastExcess(g.colors, g.rect, g.rect, 11, 21, kThresholds), 0.0);
    // The rendered region starts at x = 11: the pixel to the west is not part of the image.
    const PixelRect region{11, 20, 15, 24};
    EXPECT_EQ(contrastExcess(g.colors, g.rect, region, 11, 21, kThresholds), 0.0);
}

// Colours below 0 count as 0; the worst channel sets the excess; a channel at 0 in the pixel and
// its neighbours has no contrast.
TEST(AdaptiveShading, ClampsAtZeroAndTakesTheWorstChannel) {
    Grid g;
    for (auto& c : g.colors) c = glm::vec3(-0.5f, 0.0f, 0.3f);
    EXPECT_EQ(contrastExcess(g.colors, g.rect, g.rect, 13, 22, kThresholds), 0.0);
    g.at(12, 22) = glm::vec3(0.2f, 0.0f, 0.1f);  // red: 0.2 against 0 → contrast 1; blue 0.3 vs 0.1: 0.5
    const double thresholds[3] = {0.5, 0.1, 0.2};
    const double blue = (double(0.3f) - double(0.1f)) / (double(0.3f) + double(0.1f));
    EXPECT_NEAR(contrastExcess(g.colors, g.rect, g.rect, 13, 22, thresholds), std::max(1.0, (blue - 0.2) / 0.8), 1e-12);
    const double loose[3] = {1.0, 1.0, 0.45};
    EXPECT_NEAR(contrastExcess(g.colors, g.rect, g.rect, 13, 22, loose), (blue - 0.45) / 0.55, 1e-12);
}

TEST(AdaptiveShading, SampleCountRisesWithTheExcessUpToTheVisibleSubsamples) {
    EXPECT_EQ(adaptiveSampleCount(1, 8, 0.0, 64), 1);
    EXPECT_EQ(adaptiveSampleCount(1, 8, 1e-6, 64), 2);  // any excess adds at least one
    EXPECT_EQ(adaptiveSampleCount(1, 8, 0.5, 64), 5);   // 1 + ceil(3.5)
    EXPECT_EQ(adaptiveSampleCount(2, 6, 0.25, 64), 3);  // exactly one step: no rounding up past it
    EXPECT_EQ(adaptiveSampleCount(1, 8, 1.0, 64), 8);
    EXPECT_EQ(adaptiveSampleCount(1, 8, 1.0, 3), 3);
}

}  // namespace
}  // namespace pushpin::render
