// tests/texture/file_texture_test.cpp: the file node's entry point — uv orientation, channel
// layouts, filterType mapping, conversion and its fallbacks, missing files.
#include "texture/file_texture.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include "texture_test_support.h"

namespace pushpin::texture {
namespace {

using testing::TempDir;
using testing::WarningLog;

struct Rgba {
    float r, g, b, a;
};

Rgba evalOne(const FileTexture& tex, TextureCache::PerThread& pt, const FileTextureParams& p,
             float u, float v, float d = 0.0f) {
    Rgba out{-1, -1, -1, -1};
    FileTextureBatch b;
    b.count = 1;
    b.u = &u;
    b.v = &v;
    b.dudx = &d;
    b.dvdy = &d;
    b.r = &out.r;
    b.g = &out.g;
    b.b = &out.b;
    b.a = &out.a;
    tex.evaluate(pt, p, b);
    return out;
}

float texelValue(uint32_t x, uint32_t y, uint32_t c) { return float((x * 3 + y * 7 + c * 50) % 256) / 255.0f; }

std::filesystem::path writeBotImage(const std::filesystem::path& path, uint32_t w, uint32_t h,
                                    uint32_t channels) {
    const auto img = testing::makeImage(w, h, channels, texelValue);
    BotWriteOptions wo;
    wo.threads = 1;
    wo.alphaChannel = -1;
    writeBot(path, img.data(), w, h, channels, wo);
    return path;
}

std::filesystem::path writeTiff(const std::filesystem::path& path, uint32_t w, uint32_t h) {
    std::vector<uint8_t> px(size_t(w) * h * 3);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < 3; ++c)
                px[(size_t(y) * w + x) * 3 + c] = uint8_t((x * 3 + y * 7 + c * 50) % 256);
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(int(w), int(h), 3, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out && out->open(path.string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    return path;
}

TEST(FileTexture, FilterTypeMapping) {
    FileTextureParams p;
    EXPECT_EQ(fileLookupOptions(p).filter, FilterMode::Kernel);  // Maya's default is Quadratic
    EXPECT_EQ(fileLookupOptions(p).kernel, KernelShape::Quadratic);
    const std::pair<int, KernelShape> kernels[] = {{2, KernelShape::Box},
                                                   {3, KernelShape::Quadratic},
                                                   {4, KernelShape::Quartic},
                                                   {5, KernelShape::Gaussian}};
    for (auto [type, shape] : kernels) {
        p.filterType = type;
        EXPECT_EQ(fileLookupOptions(p).filter, FilterMode::Kernel);
        EXPECT_EQ(fileLookupOptions(p).kernel, shape);
    }
    p.filterType = 0;
    EXPECT_EQ(fileLookupOptions(p).filter, FilterMode::Point);
    p.filterType = 1;
    p.filter = 2.5f;
    p.filterOffset = 0.01f;
    p.maxAnisotropy = 8;
    const LookupOptions o = fileLookupOptions(p);
    EXPECT_EQ(o.filter, FilterMode::Trilinear);
    EXPECT_EQ(o.widthScale, 2.5f);
    EXPECT_EQ(o.widthOffset, 0.01f);
    EXPECT_EQ(o.maxAnisotropy, 8u);
    p.filterType = 42;
    EXPECT_EQ(fileLookupOptions(p).filter, FilterMode::Trilinear);
}

TEST(FileTexture, BotTextureUvOrientationAndChannels) {
    TempDir dir("ft-bot");
    TextureCache cache;
    TextureCache::PerThread pt(cache);
    FileTextureParams off;
    off.filterType = 0;
    const uint32_t W = 24, H = 16;
    for (uint32_t channels : {1u, 2u, 3u, 4u}) {
        const auto path = writeBotImage(dir.path() / ("c" + std::to_string(channels) + ".bot"), W, H, channels);
        FileTexture tex(cache, path);
        ASSERT_TRUE(tex.usable());
        EXPECT_EQ(tex.botPath(), path);
        for (uint32_t y : {0u, 5u, 15u})
            for (uint32_t x : {0u, 9u, 23u}) {
                // v = 0 is the bottom row of the image.
                const float u = (x + 0.5f) / W, v = 1.0f - (y + 0.5f) / H;
                const Rgba c = evalOne(tex, pt, off, u, v);
                const float c0 = texelValue(x, y, 0), c1 = texelValue(x, y, 1);
                switch (channels) {
                case 1: EXPECT_NEAR(c.r, c0, 1e-6f); EXPECT_NEAR(c.b, c0, 1e-6f); EXPECT_EQ(c.a, 1.0f); break;
                case 2: EXPECT_NEAR(c.g, c0, 1e-6f); EXPECT_NEAR(c.a, c1, 1e-6f); break;
                case 3: EXPECT_NEAR(c.g, c1, 1e-6f); EXPECT_NEAR(c.b, texelValue(x, y, 2), 1e-6f); EXPECT_EQ(c.a, 1.0f); break;
                case 4: EXPECT_NEAR(c.r, c0, 1e-6f); EXPECT_NEAR(c.a, texelValue(x, y, 3), 1e-6f); break;
                }
            }
    }
}

TEST(FileTexture, FilteredBatchMatchesSampler) {
    TempDir dir("ft-batch");
    TextureCache cache;
    TextureCache::PerThread pt(cache);
    FileTexture tex(cache, writeBotImage(dir.path() / "t.bot", 64, 64, 3));
    const size_t n = 150;  // more than one internal chunk
    std::vector<float> u(n), v(n), dudx(n), dvdy(n), dvdx(n, 0.0f), r(n), g(n), b(n), a(n);
    for (size_t i = 0; i < n; ++i) {
        u[i] = 0.01f * float(i);
        v[i] = 0.3f + 0.004f * float(i);
        dudx[i] = 0.001f * float(i % 13);
        dvdy[i] = 0.002f * float(i % 7);
    }
    FileTextureParams p;
    p.filterType = 1;
    FileTextureBatch batch{n, u.data(), v.data(), dudx.data(), nullptr, dvdx.data(), dvdy.data(),
                           r.data(), g.data(), b.data(), a.data()};
    tex.evaluate(pt, p, batch);
    for (size_t i = 0; i < n; ++i) {
        float expect[3];
        sampleTexture(pt, tex.handle(), fileLookupOptions(p), u[i], 1.0f - v[i], dudx[i], 0, 0,
                      -dvdy[i], nullptr, 3, expect);
        EXPECT_EQ(r[i], expect[0]);
        EXPECT_EQ(g[i], expect[1]);
        EXPECT_EQ(b[i], expect[2]);
        EXPECT_EQ(a[i], 1.0f);
    }
}

TEST(FileTexture, NonFiniteUvGetsTheDefaultColour) {
    TempDir dir("ft-nan");
    TextureCache cache;
    TextureCache::PerThread pt(cache);
    FileTexture tex(cache, writeBotImage(dir.path() / "g.bot", 16, 16, 1));
    FileTextureParams p;
    p.defaultColor[0] = 0.1f;
    p.defaultColor[1] = 0.2f;
    p.defaultColor[2] = 0.3f;
    p.defaultAlpha = 0.4f;
    const Rgba c = evalOne(tex, pt, p, NAN, 0.5f);
    EXPECT_EQ(c.r, 0.1f);
    EXPECT_EQ(c.g, 0.2f);
    EXPECT_EQ(c.b, 0.3f);
    EXPECT_EQ(c.a, 0.4f);
    const Rgba ok = evalOne(tex, pt, p, 0.5f, 0.5f);
    EXPECT_EQ(ok.r, ok.g);
    EXPECT_EQ(ok.a, 1.0f);
}

TEST(FileTexture, MissingFileWarnsOnceAndGivesDefaultColour) {
    WarningLog log;
    TextureCacheOptions o;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    TextureCache::PerThread pt(cache);
    FileTexture tex(cache, "/no/such/place/brick.tif");
    EXPECT_FALSE(tex.usable());
    FileTextureParams p;
    p.defaultColor[0] = 0.1f;
    p.defaultColor[1] = 0.2f;
    p.defaultColor[2] = 0.3f;
    p.defaultAlpha = 0.4f;
    for (int i = 0; i < 3; ++i) {
        const Rgba c = evalOne(tex, pt, p, 0.5f, 0.5f);
        EXPECT_EQ(c.r, 0.1f);
        EXPECT_EQ(c.g, 0.2f);
        EXPECT_EQ(c.b, 0.3f);
        EXPECT_EQ(c.a, 0.4f);
    }
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find("/no/such/place/brick.tif"), std::string::npos) << log.messages[0];
}

TEST(FileTexture, NonBotImageIsConvertedOrReadIntoMemory) {
    TempDir dir("ft-conv"), tmp("ft-tmp");
    const auto tif = writeTiff(dir.path() / "wall.tif", 40, 30);
    FileTextureParams off;
    off.filterType = 0;
    auto check = [&](const FileTexture& tex, TextureCache::PerThread& pt) {
        for (uint32_t y : {0u, 13u, 29u})
            for (uint32_t x : {0u, 21u, 39u}) {
                const Rgba c = evalOne(tex, pt, off, (x + 0.5f) / 40, 1.0f - (y + 0.5f) / 30);
                EXPECT_NEAR(c.r, texelValue(x, y, 0), 1e-6f);
                EXPECT_NEAR(c.g, texelValue(x, y, 1), 1e-6f);
                EXPECT_NEAR(c.b, texelValue(x, y, 2), 1e-6f);
                EXPECT_EQ(c.a, 1.0f);
            }
    };
    WarningLog log;
    TextureCacheOptions co;
    co.warningHandler = log.handler();
    TextureCache cache(co);
    TextureCache::PerThread pt(cache);

    FileTextureOptions convert;
    convert.convert.tmpDir = tmp.path();
    FileTexture converted(cache, tif, convert);
    EXPECT_TRUE(converted.usable());
    EXPECT_EQ(converted.botPath().parent_path(), conversionDir(convert.convert));
    check(converted, pt);

    FileTextureOptions memory;
    memory.useTextureCache = false;
    FileTexture inMemory(cache, tif, memory);
    EXPECT_TRUE(inMemory.usable());
    EXPECT_TRUE(inMemory.botPath().empty());
    check(inMemory, pt);
    EXPECT_EQ(log.count(), 0u);

    // TMPDIR that cannot be written: one warning, then the image is read into memory.
    FileTextureOptions blocked;
    blocked.convert.tmpDir = "/proc/self/no-tmp-here";
    FileTexture fallback(cache, tif, blocked);
    EXPECT_TRUE(fallback.usable());
    EXPECT_TRUE(fallback.botPath().empty());
    check(fallback, pt);
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find("wall.tif"), std::string::npos) << log.messages[0];
    EXPECT_NE(log.messages[0].find("into memory"), std::string::npos) << log.messages[0];
}

}  // namespace
}  // namespace pushpin::texture
