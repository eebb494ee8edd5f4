// Tests of cache/memory_budget.h: per-category accounting, the cap, peaks, the RAII charge, and
// what many threads charging at once add up to.
#include "cache/memory_budget.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace pushpin::cache {
namespace {

TEST(MemoryBudget, ChargesAndReleasesPerCategory) {
    MemoryBudget b;
    EXPECT_EQ(b.capBytes(), 0u);
    b.charge(MemoryCategory::Textures, 1000);
    b.charge(MemoryCategory::Tessellation, 300);
    b.charge(MemoryCategory::Textures, 24);
    EXPECT_EQ(b.usedBytes(), 1324u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Textures), 1024u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Tessellation), 300u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::RayTracing), 0u);
    b.release(MemoryCategory::Textures, 1024);
    EXPECT_EQ(b.usedBytes(), 300u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Textures), 0u);
    EXPECT_EQ(b.peakBytes(), 1324u);
    EXPECT_EQ(b.peakBytes(MemoryCategory::Textures), 1024u);
    EXPECT_EQ(b.peakBytes(MemoryCategory::Tessellation), 300u);
}

TEST(MemoryBudget, TryChargeRefusesPastTheCapAndCountsRefusals) {
    MemoryBudget b(1000);
    EXPECT_TRUE(b.tryCharge(MemoryCategory::Fragments, 600));
    EXPECT_EQ(b.availableBytes(), 400u);
    EXPECT_FALSE(b.tryCharge(MemoryCategory::Shading, 401));
    EXPECT_EQ(b.usedBytes(), 600u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Shading), 0u);
    EXPECT_TRUE(b.tryCharge(MemoryCategory::Shading, 400));  // exactly up to the cap
    EXPECT_EQ(b.availableBytes(), 0u);
    EXPECT_FALSE(b.overCap());
    EXPECT_FALSE(b.tryCharge(MemoryCategory::Other, 1));
    // Sizes that would overflow a naive used + bytes comparison are refused too.
    EXPECT_FALSE(b.tryCharge(MemoryCategory::Other, std::numeric_limits<uint64_t>::max()));
    EXPECT_EQ(b.snapshot().refusedCharges, 3u);
    b.release(MemoryCategory::Fragments, 600);
    EXPECT_TRUE(b.tryCharge(MemoryCategory::Other, 600));
}

TEST(MemoryBudget, UnconditionalChargeMayExceedTheCapAndSaysSo) {
    MemoryBudget b(100);
    b.charge(MemoryCategory::Textures, 150);
    EXPECT_TRUE(b.overCap());
    EXPECT_EQ(b.availableBytes(), 0u);
    EXPECT_FALSE(b.tryCharge(MemoryCategory::Other, 1));
    b.release(MemoryCategory::Textures, 100);
    EXPECT_FALSE(b.overCap());
    EXPECT_EQ(b.availableBytes(), 50u);
}

TEST(MemoryBudget, ZeroCapIsUnlimited) {
    MemoryBudget b(0);
    EXPECT_EQ(b.availableBytes(), std::numeric_limits<uint64_t>::max());
    EXPECT_TRUE(b.tryCharge(MemoryCategory::RayTracing, uint64_t(1) << 50));
    EXPECT_FALSE(b.overCap());
    EXPECT_EQ(b.usedBytes(MemoryCategory::RayTracing), uint64_t(1) << 50);
}

TEST(MemoryBudget, ConcurrentChargesAndReleasesAddUp) {
    MemoryBudget b;
    constexpr int kThreads = 4;
    constexpr int kRounds = 20000;
    std::vector<std::thread> threads;
    std::vector<uint64_t> kept(kThreads, 0);
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            std::mt19937 rng(uint32_t(t) + 1);
            const auto cat = MemoryCategory(size_t(t) % kMemoryCategoryCount);
            for (int i = 0; i < kRounds; ++i) {
                const uint64_t n = 1 + rng() % 4096;
                b.charge(cat, n);
                if (i % 3 == 0)
                    kept[size_t(t)] += n;  // keep every third charge
                else
                    b.release(cat, n);
            }
        });
    for (auto& th : threads) th.join();
    uint64_t total = 0;
    for (int t = 0; t < kThreads; ++t) {
        EXPECT_EQ(b.usedBytes(MemoryCategory(size_t(t) % kMemoryCategoryCount)), kept[size_t(t)]);
        total += kept[size_t(t)];
    }
    EXPECT_EQ(b.usedBytes(), total);
    const MemoryBudgetSnapshot s = b.snapshot();
    uint64_t sum = 0;
    for (uint64_t c : s.categoryBytes) sum += c;
    EXPECT_EQ(sum, s.usedBytes) << s;
    EXPECT_GE(s.peakBytes, total);
    for (size_t c = 0; c < kMemoryCategoryCount; ++c) EXPECT_GE(s.categoryPeakBytes[c], s.categoryBytes[c]);
}

TEST(MemoryBudget, ThreadsRacingForTheCapNeverExceedIt) {
    constexpr uint64_t kCap = 10000;
    constexpr uint64_t kChunk = 7;
    MemoryBudget b(kCap);
    constexpr int kThreads = 4;
    std::vector<uint64_t> granted(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 5000; ++i)
                if (b.tryCharge(MemoryCategory::Tessellation, kChunk)) granted[size_t(t)] += kChunk;
        });
    for (auto& th : threads) th.join();
    uint64_t sum = 0;
    for (uint64_t g : granted) sum += g;
    // Nothing is released, so exactly as many chunks as fit are granted, and no more.
    EXPECT_EQ(sum, kCap / kChunk * kChunk);
    EXPECT_EQ(b.usedBytes(), sum);
    EXPECT_EQ(b.peakBytes(), sum);
    EXPECT_EQ(b.snapshot().refusedCharges, uint64_t(kThreads) * 5000 - kCap / kChunk);
}

TEST(MemoryBudget, PeakIsTheHighestTotalNotTheSumOfCategoryPeaks) {
    MemoryBudget b;
    b.charge(MemoryCategory::Textures, 500);
    b.release(MemoryCategory::Textures, 500);
    b.charge(MemoryCategory::ShadowMaps, 300);
    EXPECT_EQ(b.peakBytes(), 500u);
    EXPECT_EQ(b.peakBytes(MemoryCategory::Textures), 500u);
    EXPECT_EQ(b.peakBytes(MemoryCategory::ShadowMaps), 300u);
    b.charge(MemoryCategory::Textures, 250);
    EXPECT_EQ(b.peakBytes(), 550u);
    EXPECT_EQ(b.peakBytes(MemoryCategory::Textures), 500u);
}

TEST(MemoryCharge, ReleasesOnDestructionAndFollowsMoves) {
    MemoryBudget b(1000);
    {
        MemoryCharge c(&b, MemoryCategory::Textures, 400);
        EXPECT_EQ(b.usedBytes(MemoryCategory::Textures), 400u);
        MemoryCharge moved(std::move(c));
        EXPECT_EQ(c.bytes(), 0u);
        EXPECT_EQ(moved.bytes(), 400u);
        EXPECT_EQ(b.usedBytes(), 400u);
        MemoryCharge other(&b, MemoryCategory::Other, 100);
        other = std::move(moved);  // releases other's 100
        EXPECT_EQ(b.usedBytes(), 400u);
        EXPECT_EQ(b.usedBytes(MemoryCategory::Other), 0u);
        other.resize(700);
        EXPECT_EQ(b.usedBytes(MemoryCategory::Textures), 700u);
        other.resize(50);
        EXPECT_EQ(b.usedBytes(MemoryCategory::Textures), 50u);
    }
    EXPECT_EQ(b.usedBytes(), 0u);
    EXPECT_EQ(b.peakBytes(), 700u);  // the resize to 700 was the most held at once
}

TEST(MemoryCharge, TryChargeGivesNothingWhenRefusedAndNullBudgetIsEmpty) {
    MemoryBudget b(100);
    std::optional<MemoryCharge> ok = MemoryCharge::tryCharge(b, MemoryCategory::Shading, 80);
    ASSERT_TRUE(ok);
    EXPECT_FALSE(MemoryCharge::tryCharge(b, MemoryCategory::Shading, 21));
    EXPECT_EQ(b.usedBytes(), 80u);
    ok.reset();
    EXPECT_EQ(b.usedBytes(), 0u);
    MemoryCharge none(nullptr, MemoryCategory::Textures, 5000);
    EXPECT_EQ(none.bytes(), 0u);
    none.resize(10);
    EXPECT_EQ(none.bytes(), 0u);
    EXPECT_EQ(b.usedBytes(), 0u);
}

TEST(MemoryCharge, TryResizeGrowsOnlyWithinTheCap) {
    MemoryBudget b(100);
    MemoryCharge c(&b, MemoryCategory::Fragments, 30);
    MemoryCharge other(&b, MemoryCategory::Shading, 50);
    EXPECT_TRUE(c.tryResize(50));
    EXPECT_EQ(c.bytes(), 50u);
    EXPECT_FALSE(c.tryResize(51));  // 101 > 100: nothing changes
    EXPECT_EQ(c.bytes(), 50u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Fragments), 50u);
    EXPECT_TRUE(c.tryResize(10));  // shrinking always succeeds
    EXPECT_EQ(b.usedBytes(), 60u);
    EXPECT_EQ(b.peakBytes(), 100u);
    MemoryCharge none;
    EXPECT_TRUE(none.tryResize(1000));
    EXPECT_EQ(none.bytes(), 0u);
}

TEST(MemoryBudgetDeathTest, ReleasingMoreThanACategoryHoldsAborts) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_DEATH(
        {
            MemoryBudget b;
            b.charge(MemoryCategory::Fragments, 10);
            b.release(MemoryCategory::Fragments, 11);
        },
        "releasing 11 bytes of 'fragments', which holds only 10");
}

TEST(MemoryBudget, SnapshotPrintsEveryCategoryByName) {
    MemoryBudget b(4096);
    b.charge(MemoryCategory::RayTracing, 7);
    std::ostringstream os;
    os << b.snapshot();
    for (size_t c = 0; c < kMemoryCategoryCount; ++c)
        EXPECT_NE(os.str().find(memoryCategoryName(MemoryCategory(c))), std::string::npos) << os.str();
    EXPECT_NE(os.str().find("rayTracing 7"), std::string::npos) << os.str();
    EXPECT_NE(os.str().find("cap 4096"), std::string::npos) << os.str();
}

TEST(MemoryBudget, CategoryNamesAreDistinctAndTheFramebufferHasItsOwn) {
    std::set<std::string> names;
    for (size_t c = 0; c < kMemoryCategoryCount; ++c) names.insert(memoryCategoryName(MemoryCategory(c)));
    EXPECT_EQ(names.size(), kMemoryCategoryCount);
    EXPECT_EQ(names.count("?"), 0u);
    EXPECT_STREQ(memoryCategoryName(MemoryCategory::Framebuffer), "framebuffer");
    MemoryBudget b;
    b.charge(MemoryCategory::Framebuffer, 64);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Framebuffer), 64u);
    EXPECT_EQ(b.usedBytes(MemoryCategory::Other), 0u);
    b.release(MemoryCategory::Framebuffer, 64);
    EXPECT_EQ(b.usedBytes(), 0u);
}

}  // namespace
}  // namespace pushpin::cache
