// tests/texture/lookup_trace_test.cpp: trace files round-trip, record from the cache, and reject
// damaged input.
#include "texture/lookup_trace.h"

#include <gtest/gtest.h>

#include <fstream>

#include "texture_test_support.h"

namespace pushpin::texture {
namespace {

using testing::TempDir;

TEST(LookupTrace, RoundTrip) {
    TempDir dir("trace");
    const auto path = dir.path() / "t.trace";
    std::vector<float> s = {0.1f, 0.2f, -3.5f}, t = {0.9f, 0.8f, 7.25f}, d1 = {1e-3f, 2e-3f, 0},
                       d2 = {0, -1e-4f, 5.0f};
    LookupBatch b;
    b.count = 3;
    b.s = s.data();
    b.t = t.data();
    b.dsdx = d1.data();
    b.dtdy = d2.data();
    LookupOptions o;
    o.filter = FilterMode::Kernel;
    o.kernel = KernelShape::Gaussian;
    o.widthScale = 2.0f;
    o.widthOffset = 0.125f;
    o.maxAnisotropy = 4;
    o.overrideWrap = true;
    o.wrapS = WrapMode::Mirror;
    o.wrapT = WrapMode::Black;
    {
        LookupTraceWriter w(path);
        w.record(7, "/textures/a.bot", o, b);
        w.record(2, "/textures/b.bot", LookupOptions{}, b);
        w.record(7, "/textures/a.bot", LookupOptions{}, b);
        EXPECT_EQ(w.recordedLookups(), 9u);
        w.close();
    }
    const LookupTrace trace = readLookupTrace(path);
    ASSERT_EQ(trace.batches.size(), 3u);
    EXPECT_EQ(trace.lookupCount(), 9u);
    ASSERT_EQ(trace.textures.size(), 8u);
    EXPECT_EQ(trace.textures[7], "/textures/a.bot");
    EXPECT_EQ(trace.textures[2], "/textures/b.bot");
    const TraceBatch& first = trace.batches[0];
    EXPECT_EQ(first.texture, 7u);
    EXPECT_EQ(first.options.filter, FilterMode::Kernel);
    EXPECT_EQ(first.options.kernel, KernelShape::Gaussian);
    EXPECT_EQ(first.options.widthScale, 2.0f);
    EXPECT_EQ(first.options.widthOffset, 0.125f);
    EXPECT_EQ(first.options.maxAnisotropy, 4u);
    EXPECT_TRUE(first.options.overrideWrap);
    EXPECT_EQ(first.options.wrapS, WrapMode::Mirror);
    EXPECT_EQ(first.options.wrapT, WrapMode::Black);
    EXPECT_EQ(first.s, s);
    EXPECT_EQ(first.t, t);
    EXPECT_EQ(first.dsdx, d1);
    EXPECT_EQ(first.dtdy, d2);
    EXPECT_EQ(first.dsdy, std::vector<float>(3, 0.0f));  // null arrays were recorded as zero
    EXPECT_EQ(trace.batches[1].texture, 2u);
    EXPECT_EQ(trace.batches[1].options.filter, FilterMode::Trilinear);
}

TEST(LookupTrace, RecordedFromTheCacheAndReplayedGivesTheSameValues) {
    TempDir dir("trace-cache");
    const auto path = dir.path() / "render.trace";
    TextureCache cache;
    const TextureHandle h = cache.registerSource(testing::memoryTexture(
        "mem", 32, 32, 2, [](uint32_t x, uint32_t y, uint32_t c) { return float(x * 2 + y + c); }));
    std::vector<float> original;
    {
        LookupTraceWriter writer(path);
        cache.setTraceWriter(&writer);
        TextureCache::PerThread pt(cache);
        for (int i = 0; i < 50; ++i) {
            float v[2];
            sampleTexture(pt, h, LookupOptions{}, 0.02f * i, 0.013f * i, 0.01f, 0, 0, 0.02f, nullptr, 2, v);
            original.insert(original.end(), v, v + 2);
        }
        cache.setTraceWriter(nullptr);
        writer.close();
    }
    const LookupTrace trace = readLookupTrace(path);
    ASSERT_EQ(trace.lookupCount(), 50u);
    EXPECT_EQ(trace.textures.at(h.id), "mem");
    TextureCache fresh;
    const TextureHandle h2 = fresh.registerSource(testing::memoryTexture(
        "mem", 32, 32, 2, [](uint32_t x, uint32_t y, uint32_t c) { return float(x * 2 + y + c); }));
    TextureCache::PerThread pt(fresh);
    std::vector<float> replayed;
    for (const TraceBatch& b : trace.batches) {
        std::vector<float> c0(b.s.size()), c1(b.s.size());
        float* outs[2] = {c0.data(), c1.data()};
        sampleTexture(pt, h2, b.options, b.view(), nullptr, 2, outs);
        for (size_t i = 0; i < c0.size(); ++i) {
            replayed.push_back(c0[i]);
            replayed.push_back(c1[i]);
        }
    }
    EXPECT_EQ(replayed, original);
}

TEST(LookupTrace, DamagedFilesAreFormatErrors) {
    TempDir dir("trace-bad");
    EXPECT_THROW(readLookupTrace(dir.path() / "absent.trace"), IoError);
    std::ofstream(dir.path() / "junk.trace") << "definitely not a trace";
    EXPECT_THROW(readLookupTrace(dir.path() / "junk.trace"), FormatError);
    const auto good = dir.path() / "good.trace";
    {
        LookupTraceWriter w(good);
        float s[4] = {0, 1, 2, 3};
        LookupBatch b;
        b.count = 4;
        b.s = s;
        b.t = s;
        w.record(0, "x.bot", LookupOptions{}, b);
    }
    const auto size = std::filesystem::file_size(good);
    std::filesystem::copy_file(good, dir.path() / "cut.trace");
    std::filesystem::resize_file(dir.path() / "cut.trace", size - 5);
    try {
        readLookupTrace(dir.path() / "cut.trace");
        FAIL() << "truncated trace accepted";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("cut.trace"), std::string::npos) << e.what();
    }
    EXPECT_THROW(LookupTraceWriter("/proc/self/no/such/dir/t.trace"), IoError);
}

}  // namespace
}  // namespace pushpin::texture
