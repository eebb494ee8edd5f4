// tests/texture/texture_sampler_test.cpp: wrap modes, bilinear exactness, level selection,
// anisotropy and the kernel filters' properties.
#include "texture/texture_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "texture_test_support.h"

namespace pushpin::texture {
namespace {

float sample1(TextureCache::PerThread& pt, TextureHandle h, const LookupOptions& o, float s,
              float t, float dsdx = 0, float dsdy = 0, float dtdx = 0, float dtdy = 0) {
    float v = -1;
    EXPECT_TRUE(sampleTexture(pt, h, o, s, t, dsdx, dsdy, dtdx, dtdy, nullptr, 1, &v));
    return v;
}

TEST(TextureSampler, WrapTexelModes) {
    EXPECT_EQ(wrapTexel(-1, 5, WrapMode::Periodic), 4);
    EXPECT_EQ(wrapTexel(12, 5, WrapMode::Periodic), 2);
    EXPECT_EQ(wrapTexel(-11, 5, WrapMode::Periodic), 4);
    EXPECT_EQ(wrapTexel(-3, 5, WrapMode::Clamp), 0);
    EXPECT_EQ(wrapTexel(9, 5, WrapMode::Clamp), 4);
    EXPECT_EQ(wrapTexel(5, 5, WrapMode::Mirror), 4);
    EXPECT_EQ(wrapTexel(9, 5, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapTexel(10, 5, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapTexel(-1, 5, WrapMode::Mirror), 0);
    EXPECT_EQ(wrapTexel(-2, 5, WrapMode::Mirror), 1);
    EXPECT_EQ(wrapTexel(-1, 5, WrapMode::Black), -1);
    EXPECT_EQ(wrapTexel(5, 5, WrapMode::Black), -1);
    EXPECT_EQ(wrapTexel(3, 5, WrapMode::Black), 3);
}

TEST(TextureSampler, BilinearOfLinearRampIsExact) {
    TextureCache cache;
    const uint32_t W = 40, H = 24;
    const auto f = [](float x, float y) { return 0.5f * x - 0.25f * y + 3.0f; };
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "ramp", W, H, 1, [&](uint32_t x, uint32_t y, uint32_t) { return f(float(x), float(y)); },
        WrapMode::Clamp));
    TextureCache::PerThread pt(cache);
    LookupOptions o;
    o.filter = FilterMode::Bilinear;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> us(0.5f / W, (W - 0.5f) / W), vs(0.5f / H, (H - 0.5f) / H);
    for (int i = 0; i < 2000; ++i) {
        const float s = us(rng), t = vs(rng);
        EXPECT_NEAR(sample1(pt, h, o, s, t), f(s * W - 0.5f, t * H - 0.5f), 2e-5f) << s << " " << t;
    }
}

TEST(TextureSampler, WrapModesAtTheBorder) {
    TextureCache cache;
    const uint32_t W = 16;
    const auto tex = testing::memoryTexture("strip", W, W, 1, [](uint32_t x, uint32_t y, uint32_t) {
        return float(x) + 100.0f * float(y);
    });
    const TextureHandle h = cache.registerSource(tex);
    TextureCache::PerThread pt(cache);
    LookupOptions o;
    o.filter = FilterMode::Point;
    o.overrideWrap = true;
    const float t = 2.5f / W;  // row 2
    auto texel = [](float x) { return (x + 0.5f) / 16.0f; };

    o.wrapS = o.wrapT = WrapMode::Periodic;
    EXPECT_EQ(sample1(pt, h, o, texel(3) + 1.0f, t), 203.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(-2), t), 214.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(3) - 7.0f, t), 203.0f);

    o.wrapS = o.wrapT = WrapMode::Clamp;
    EXPECT_EQ(sample1(pt, h, o, texel(-5), t), 200.0f);
    EXPECT_EQ(sample1(pt, h, o, 1e9f, t), 215.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(3), -4.0f), 3.0f);

    o.wrapS = o.wrapT = WrapMode::Mirror;
    EXPECT_EQ(sample1(pt, h, o, texel(-1), t), 200.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(-3), t), 202.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(17), t), 214.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(33), t), 201.0f);

    o.wrapS = o.wrapT = WrapMode::Black;
    EXPECT_EQ(sample1(pt, h, o, texel(-1), t), 0.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(16), t), 0.0f);
    EXPECT_EQ(sample1(pt, h, o, texel(15), t), 215.0f);
    // Bilinear half a texel outside the edge blends the edge texel with black.
    o.filter = FilterMode::Bilinear;
    EXPECT_NEAR(sample1(pt, h, o, 0.0f, t), 0.5f * 200.0f, 1e-4f);

    // The texture's own wrap mode applies without the override.
    o.overrideWrap = false;
    o.filter = FilterMode::Point;
    EXPECT_EQ(sample1(pt, h, o, texel(-2), t), 214.0f);
}

// A texture whose level l is the constant l: lookups return the (fractional) level they used.
TextureHandle levelProbe(TextureCache& cache, uint32_t size) {
    BotHeader header;
    header.width = header.height = size;
    header.channels = 1;
    header.pixelType = PixelType::Float;
    std::vector<std::vector<float>> levels;
    for (uint32_t w = size, l = 0;; w = std::max(1u, w / 2), ++l) {
        BotLevel lv;
        lv.width = lv.height = w;
        lv.pagesX = lv.pagesY = (w + 7) / 8;
        header.levels.push_back(lv);
        levels.emplace_back(size_t(w) * w, float(l));
        if (w == 1) break;
    }
    return cache.registerSource(detail::makeMemoryPageSource("levels", header, std::move(levels)));
}

TEST(TextureSampler, TrilinearPicksTheLevelsOfTheFootprint) {
    TextureCache cache;
    const TextureHandle h = levelProbe(cache, 256);  // levels 0..8
    TextureCache::PerThread pt(cache);
    LookupOptions o;
    for (int k = 0; k <= 8; ++k) {
        const float d = std::exp2(float(k)) / 256.0f;
        EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, d, 0, 0, d), float(k), 1e-4f) << k;
        // The larger of the two axes decides.
        EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, d, 0, 0, d * 0.25f), float(k), 1e-4f) << k;
        if (k < 8) {
            const float dm = std::exp2(float(k) + 0.25f) / 256.0f;
            EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 0, dm, dm, 0), float(k) + 0.25f, 1e-4f) << k;
        }
    }
    EXPECT_EQ(sample1(pt, h, o, 0.3f, 0.6f, 0.001f / 256, 0, 0, 0), 0.0f);  // magnified
    EXPECT_EQ(sample1(pt, h, o, 0.3f, 0.6f, 50.0f, 0, 0, 50.0f), 8.0f);     // beyond the last level
    // widthScale and widthOffset widen the footprint.
    o.widthScale = 4.0f;
    EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 2.0f / 256, 0, 0, 2.0f / 256), 3.0f, 1e-4f);
    o.widthScale = 1.0f;
    o.widthOffset = 6.0f / 256;
    EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 2.0f / 256, 0, 0, 2.0f / 256), 3.0f, 1e-4f);
    EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 0, 0, 0, 0), std::log2(6.0f), 1e-4f);
    // Anisotropic: a footprint 16 long and 2 wide with up to 8 probes filters at width 2.
    o.widthOffset = 0;
    o.maxAnisotropy = 8;
    EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 16.0f / 256, 0, 0, 2.0f / 256), 1.0f, 1e-4f);
    o.maxAnisotropy = 4;  // capped: width 16 / 4 = 4
    EXPECT_NEAR(sample1(pt, h, o, 0.3f, 0.6f, 16.0f / 256, 0, 0, 2.0f / 256), 2.0f, 1e-4f);
}

TEST(TextureSampler, AnisotropicKeepsDetailAcrossTheMinorAxis) {
    // Stripes along s (value depends on t only); a footprint long in s and one texel in t.
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "stripes", 128, 128, 1, [](uint32_t, uint32_t y, uint32_t) { return float((y / 2) % 2); }));
    TextureCache::PerThread pt(cache);
    auto spread = [&](uint32_t maxAniso) {
        LookupOptions o;
        o.maxAnisotropy = maxAniso;
        float lo = 1, hi = 0;
        for (int i = 0; i < 64; ++i) {
            const float v = sample1(pt, h, o, 0.37f, (i + 0.5f) / 128.0f, 32.0f / 128, 0, 0, 1.0f / 128);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        return hi - lo;
    };
    EXPECT_LT(spread(1), 0.05f);   // isotropic: blurred to grey at the major axis' level
    EXPECT_GT(spread(32), 0.9f);   // anisotropic: stripes survive
}

TEST(TextureSampler, KernelWeightsSumToOneAndAreSymmetric) {
    for (KernelShape k : {KernelShape::Box, KernelShape::Quadratic, KernelShape::Quartic,
                          KernelShape::Gaussian}) {
        float w[kKernelTaps * kKernelTaps];
        kernelWeights(k, w);
        EXPECT_NEAR(std::accumulate(w, w + kKernelTaps * kKernelTaps, 0.0), 1.0, 1e-6);
        for (uint32_t j = 0; j < kKernelTaps; ++j)
            for (uint32_t i = 0; i < kKernelTaps; ++i) {
                EXPECT_GE(w[j * kKernelTaps + i], 0.0f);
                EXPECT_FLOAT_EQ(w[j * kKernelTaps + i], w[i * kKernelTaps + j]);
                EXPECT_FLOAT_EQ(w[j * kKernelTaps + i], w[(kKernelTaps - 1 - j) * kKernelTaps + i]);
            }
        if (k != KernelShape::Box) {
            EXPECT_GT(w[kKernelTaps + 1], w[0]);  // peaks in the middle
        }
    }
}

TEST(TextureSampler, ConstantTextureGivesTheConstantUnderEveryFilter) {
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "const", 50, 30, 3, [](uint32_t, uint32_t, uint32_t c) { return 0.2f + 0.3f * float(c); }));
    TextureCache::PerThread pt(cache);
    std::vector<LookupOptions> all;
    for (FilterMode f : {FilterMode::Point, FilterMode::Bilinear, FilterMode::Trilinear})
        all.push_back(LookupOptions{f});
    for (KernelShape k : {KernelShape::Box, KernelShape::Quadratic, KernelShape::Quartic,
                          KernelShape::Gaussian}) {
        LookupOptions o;
        o.filter = FilterMode::Kernel;
        o.kernel = k;
        o.widthScale = 3.0f;
        o.widthOffset = 0.01f;
        all.push_back(o);
    }
    all.push_back(LookupOptions{});
    all.back().maxAnisotropy = 16;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-2, 3), ld(-8, 1);
    for (const LookupOptions& o : all)
        for (int i = 0; i < 200; ++i) {
            float v[3];
            const float d = std::exp2(ld(rng));
            ASSERT_TRUE(sampleTexture(pt, h, o, u(rng), u(rng), d, 0.3f * d, -0.7f * d, 0.1f * d,
                                      nullptr, 3, v));
            EXPECT_NEAR(v[0], 0.2f, 1e-5f);
            EXPECT_NEAR(v[1], 0.5f, 1e-5f);
            EXPECT_NEAR(v[2], 0.8f, 1e-5f);
        }
}

TEST(TextureSampler, LargerFilterIsBlurrier) {
    // A checkerboard of 4-texel squares; the spread of filtered values falls as the filter grows.
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "checker", 128, 128, 1,
        [](uint32_t x, uint32_t y, uint32_t) { return float(((x / 4) + (y / 4)) % 2); }));
    TextureCache::PerThread pt(cache);
    auto variance = [&](const LookupOptions& o) {
        double sum = 0, sum2 = 0;
        const int n = 400;
        for (int i = 0; i < n; ++i) {
            const float s = (float(i % 20) + 0.37f) / 20.0f, t = (float(i / 20) + 0.61f) / 20.0f;
            const double v = sample1(pt, h, o, s, t, 1.0f / 128, 0, 0, 1.0f / 128);
            sum += v;
            sum2 += v * v;
        }
        return sum2 / n - (sum / n) * (sum / n);
    };
    for (FilterMode f : {FilterMode::Trilinear, FilterMode::Kernel})
        for (KernelShape k : {KernelShape::Box, KernelShape::Quadratic, KernelShape::Quartic,
                              KernelShape::Gaussian}) {
            if (f == FilterMode::Trilinear && k != KernelShape::Box) continue;
            LookupOptions o;
            o.filter = f;
            o.kernel = k;
            double previous = 1e9;
            for (float scale : {1.0f, 2.0f, 4.0f, 8.0f}) {
                o.widthScale = scale;
                const double var = variance(o);
                // Strictly falling until the checker has averaged away to grey (what is left
                // then is tap aliasing well below 1e-3).
                if (previous > 1e-3) {
                    EXPECT_LT(var, previous) << "kernel " << int(k) << " scale " << scale;
                } else {
                    EXPECT_LT(var, 1e-3) << "kernel " << int(k) << " scale " << scale;
                }
                previous = var;
            }
            EXPECT_LT(previous, 0.01) << "kernel " << int(k);
        }
}

TEST(TextureSampler, NonFiniteCoordinatesGetTheFillColour) {
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "c", 8, 8, 1, [](uint32_t, uint32_t, uint32_t) { return 1.0f; }));
    TextureCache::PerThread pt(cache);
    const float fill[2] = {0.5f, 0.25f};
    float v[2];
    EXPECT_TRUE(sampleTexture(pt, h, LookupOptions{}, NAN, 0.5f, 0, 0, 0, 0, fill, 2, v));
    EXPECT_EQ(v[0], 0.5f);
    EXPECT_EQ(v[1], 0.25f);
    // NaN derivatives are ignored; channels the texture lacks come from fill.
    EXPECT_TRUE(sampleTexture(pt, h, LookupOptions{}, 0.5f, 0.5f, NAN, INFINITY, 0, 0, fill, 2, v));
    EXPECT_EQ(v[0], 1.0f);
    EXPECT_EQ(v[1], 0.25f);
}

TEST(TextureSampler, BatchMatchesSingleLookups) {
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "n", 64, 64, 2, [](uint32_t x, uint32_t y, uint32_t c) { return float((x * 7 + y * 13 + c) % 17); }));
    TextureCache::PerThread pt(cache);
    const size_t n = 100;
    std::vector<float> s(n), t(n), dx(n), dy(n), zero(n, 0.0f), r0(n), r1(n);
    for (size_t i = 0; i < n; ++i) {
        s[i] = float(i) * 0.013f;
        t[i] = float(i) * 0.021f - 0.3f;
        dx[i] = 0.002f * float(i % 9);
        dy[i] = 0.003f * float(i % 5);
    }
    LookupBatch b;
    b.count = n;
    b.s = s.data();
    b.t = t.data();
    b.dsdx = dx.data();
    b.dtdy = dy.data();
    float* outs[2] = {r0.data(), r1.data()};
    ASSERT_TRUE(sampleTexture(pt, h, LookupOptions{}, b, nullptr, 2, outs));
    for (size_t i = 0; i < n; ++i) {
        float v[2];
        sampleTexture(pt, h, LookupOptions{}, s[i], t[i], dx[i], 0, 0, dy[i], nullptr, 2, v);
        EXPECT_EQ(v[0], r0[i]);
        EXPECT_EQ(v[1], r1[i]);
    }
}

}  // namespace
}  // namespace pushpin::texture
