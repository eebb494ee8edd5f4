// Tests of texture/mipmap.h: level sizes, filter properties and the streaming cascade.
#include "texture/mipmap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace pushpin::texture {
namespace {

TEST(MipLevelSizes, FloorRuleDownToOneByOne) {
    const auto s = mipLevelSizes(13, 7);
    const std::vector<std::pair<uint32_t, uint32_t>> expected = {{13, 7}, {6, 3}, {3, 1}, {1, 1}};
    EXPECT_EQ(s, expected);
    EXPECT_EQ(mipLevelSizes(1, 9).size(), 4u);  // 1x9, 1x4, 1x2, 1x1
    EXPECT_EQ(mipLevelSizes(1, 1).size(), 1u);
    EXPECT_EQ(mipLevelSizes(4096, 4096).size(), 13u);
    EXPECT_TRUE(mipLevelSizes(0, 5).empty());
}

TEST(MipFilter, ParsesNamesAndRejectsOthers) {
    EXPECT_EQ(parseMipFilter("box"), MipFilter::Box);
    EXPECT_EQ(parseMipFilter("triangle"), MipFilter::Triangle);
    EXPECT_EQ(parseMipFilter("lanczos3"), MipFilter::Lanczos3);
    EXPECT_FALSE(parseMipFilter("Box"));
    EXPECT_FALSE(parseMipFilter(""));
    EXPECT_STREQ(mipFilterName(MipFilter::Lanczos3), "lanczos3");
}

TEST(MipFilter, KernelsAreZeroPastTheirRadius) {
    for (MipFilter f : {MipFilter::Box, MipFilter::Triangle, MipFilter::Lanczos3}) {
        const float r = mipFilterRadius(f);
        EXPECT_EQ(mipFilterKernel(f, r + 0.01f), 0.0f);
        EXPECT_EQ(mipFilterKernel(f, -r - 0.01f), 0.0f);
        EXPECT_FLOAT_EQ(mipFilterKernel(f, 0.0f), 1.0f);
    }
    EXPECT_NEAR(mipFilterKernel(MipFilter::Lanczos3, 1.0f), 0.0f, 1e-7f);
    EXPECT_LT(mipFilterKernel(MipFilter::Lanczos3, 1.5f), 0.0f);  // negative lobe
}

TEST(FilterTaps, WeightsSumToOneAndStayInside) {
    for (MipFilter f : {MipFilter::Box, MipFilter::Triangle, MipFilter::Lanczos3}) {
        for (auto [n, m] : {std::pair<uint32_t, uint32_t>{13, 6}, {16, 8}, {9, 4}, {1, 1}, {7, 7}, {3, 1}, {1000, 500}}) {
            const FilterTaps t = computeFilterTaps(n, m, f);
            ASSERT_EQ(t.first.size(), m);
            for (uint32_t i = 0; i < m; ++i) {
                double sum = 0.0;
                for (uint32_t k = 0; k < t.count[i]; ++k) sum += t.weights[t.offsets[i] + k];
                EXPECT_NEAR(sum, 1.0, 1e-6) << mipFilterName(f) << " " << n << "->" << m << " texel " << i;
                EXPECT_LE(t.first[i] + t.count[i], n);
                EXPECT_LE(t.count[i], t.maxCount);
            }
        }
    }
}

TEST(FilterTaps, BoxOnOddSizesWeighsByCoverage) {
    // 13 -> 6: each destination texel covers 13/6 source texels; texel 0 covers [0, 2.1667).
    const FilterTaps t = computeFilterTaps(13, 6, MipFilter::Box);
    ASSERT_EQ(t.first[0], 0u);
    ASSERT_EQ(t.count[0], 3u);
    EXPECT_NEAR(t.weights[0], 6.0 / 13.0, 1e-6);
    EXPECT_NEAR(t.weights[1], 6.0 / 13.0, 1e-6);
    EXPECT_NEAR(t.weights[2], (13.0 / 6.0 - 2.0) * 6.0 / 13.0, 1e-6);
    // Every source texel contributes a total weight of dst/src over all destination texels.
    std::vector<double> total(13, 0.0);
    for (uint32_t i = 0; i < 6; ++i)
        for (uint32_t k = 0; k < t.count[i]; ++k) total[t.first[i] + k] += t.weights[t.offsets[i] + k];
    for (double v : total) EXPECT_NEAR(v, 6.0 / 13.0, 1e-6);
    // Exact halving is a plain 2-texel average.
    const FilterTaps h = computeFilterTaps(8, 4, MipFilter::Box);
    for (uint32_t i = 0; i < 4; ++i) {
        EXPECT_EQ(h.first[i], 2 * i);
        EXPECT_EQ(h.count[i], 2u);
        EXPECT_FLOAT_EQ(h.weights[h.offsets[i]], 0.5f);
    }
}

TEST(FilterTaps, UnscaledAxisIsIdentity) {
    for (MipFilter f : {MipFilter::Box, MipFilter::Triangle, MipFilter::Lanczos3}) {
        const FilterTaps t = computeFilterTaps(5, 5, f);
        for (uint32_t i = 0; i < 5; ++i) {
            ASSERT_EQ(t.count[i], 1u) << mipFilterName(f);
            EXPECT_EQ(t.first[i], i);
            EXPECT_FLOAT_EQ(t.weights[t.offsets[i]], 1.0f);
        }
    }
    EXPECT_THROW(computeFilterTaps(4, 5, MipFilter::Box), std::invalid_argument);
}

// Collects everything a cascade emits.
struct Collected {
    std::map<uint32_t, std::vector<float>> levels;
    std::map<uint32_t, uint32_t> nextRow;
    size_t maxBandRows = 0;
};

Collected runCascade(const std::vector<float>& src, uint32_t w, uint32_t h, uint32_t ch, MipFilter f, uint32_t band) {
    Collected c;
    MipCascade cascade(w, h, ch, f, ColorSpace::Linear, -1,
                       [&](uint32_t level, uint32_t first, uint32_t count, const float* rows, bool linear) {
                           EXPECT_EQ(linear, level > 0);
                           EXPECT_EQ(first, c.nextRow[level]) << "rows out of order at level " << level;
                           c.nextRow[level] = first + count;
                           c.maxBandRows = std::max<size_t>(c.maxBandRows, count);
                           const auto sizes = mipLevelSizes(w, h);
                           auto& v = c.levels[level];
                           v.insert(v.end(), rows, rows + size_t(count) * sizes[level].first * ch);
                       });
    for (uint32_t y = 0; y < h; y += band) cascade.pushRows(src.data() + size_t(y) * w * ch, std::min(band, h - y));
    EXPECT_TRUE(cascade.done());
    return c;
}

TEST(MipCascade, ResultDoesNotDependOnBandHeight) {
    const uint32_t w = 45, h = 37, ch = 3;
    std::vector<float> src(size_t(w) * h * ch);
    std::mt19937 rng(1);
    for (float& v : src) v = float(rng() % 1000) / 1000.0f;
    for (MipFilter f : {MipFilter::Box, MipFilter::Triangle, MipFilter::Lanczos3}) {
        const Collected a = runCascade(src, w, h, ch, f, 1);
        const Collected b = runCascade(src, w, h, ch, f, 64);
        const Collected c = runCascade(src, w, h, ch, f, 5);
        ASSERT_EQ(a.levels.size(), mipLevelSizes(w, h).size());
        EXPECT_EQ(a.levels, b.levels);
        EXPECT_EQ(a.levels, c.levels);
        EXPECT_EQ(a.levels.at(0), src);
    }
}

TEST(MipCascade, EachBoxLevelAveragesItsParentOnPowerOfTwoSizes) {
    const uint32_t w = 32, h = 16, ch = 1;
    std::vector<float> src(size_t(w) * h);
    for (size_t i = 0; i < src.size(); ++i) src[i] = float(i % 17) / 16.0f;
    const Collected c = runCascade(src, w, h, ch, MipFilter::Box, 8);
    const auto sizes = mipLevelSizes(w, h);
    for (uint32_t l = 1; l < sizes.size(); ++l) {
        const auto& parent = c.levels.at(l - 1);
        const auto& level = c.levels.at(l);
        const uint32_t pw = sizes[l - 1].first, lw = sizes[l].first, lh = sizes[l].second;
        const bool halveY = sizes[l - 1].second > 1;
        for (uint32_t y = 0; y < lh; ++y)
            for (uint32_t x = 0; x < lw; ++x) {
                const uint32_t y0 = halveY ? 2 * y : y, y1 = halveY ? 2 * y + 1 : y;
                const float expect =
                    0.25f * (parent[y0 * pw + 2 * x] + parent[y0 * pw + 2 * x + 1] + parent[y1 * pw + 2 * x] +
                             parent[y1 * pw + 2 * x + 1]);
                EXPECT_NEAR(level[y * lw + x], expect, 1e-6f) << "level " << l;
            }
    }
}

TEST(MipCascade, RejectsEmptyImagesAndExtraRows) {
    EXPECT_THROW(MipCascade(0, 4, 1, MipFilter::Box, ColorSpace::Linear, -1, nullptr), std::invalid_argument);
    std::vector<float> rows(4 * 5, 0.0f);
    MipCascade c(4, 4, 1, MipFilter::Box, ColorSpace::Linear, -1, [](uint32_t, uint32_t, uint32_t, const float*, bool) {});
    EXPECT_THROW(c.pushRows(rows.data(), 5), std::logic_error);
    c.pushRows(rows.data(), 4);
    EXPECT_TRUE(c.done());
}

}  // namespace
}  // namespace pushpin::texture
