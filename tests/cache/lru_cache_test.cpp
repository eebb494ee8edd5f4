// Tests for cache/lru_cache.h: values made once and shared, pins that keep values resident,
// least-recently-used eviction under the budget, refusals, recomputes, and every charge released.
#include "cache/lru_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace pushpin::cache {
namespace {

using Cache = LruCache<int, std::string>;

// A value of `bytes` bytes for key k, counting how often it is made.
struct Maker {
    std::atomic<int> calls{0};
    auto make(int k, size_t bytes) {
        return [this, k, bytes] {
            ++calls;
            return std::string(bytes, char('a' + k));
        };
    }
};
auto sizeOf = [](const std::string& s) { return uint64_t(s.size()); };

TEST(LruCache, MakesOnceAndSharesTheValue) {
    MemoryBudget budget;
    Maker m;
    Cache cache(&budget, MemoryCategory::Tessellation);
    auto a = cache.tryAcquire(1, m.make(1, 100), sizeOf);
    auto b = cache.tryAcquire(1, m.make(1, 100), sizeOf);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->get(), b->get());
    EXPECT_EQ(m.calls, 1);
    EXPECT_EQ(budget.usedBytes(MemoryCategory::Tessellation), 100u);
    EXPECT_EQ(cache.stats().made, 1u);
    EXPECT_EQ(cache.stats().hits, 1u);
}

TEST(LruCache, TryPinFindsOnlyResidentValuesAndNeverMakes) {
    MemoryBudget budget(250);
    Maker m;
    Cache cache(&budget, MemoryCategory::Tessellation);
    EXPECT_FALSE(cache.tryPin(1));
    EXPECT_EQ(cache.keyCount(), 0u) << "asking makes no entry";
    {
        auto a = cache.tryAcquire(1, m.make(1, 100), sizeOf);
        ASSERT_TRUE(a);
        auto b = cache.tryPin(1);
        ASSERT_TRUE(b);
        EXPECT_EQ(b->get(), a->get());
        EXPECT_EQ(cache.stats().hits, 1u);
    }
    // Unpinned and resident: found (and pinned again: it is not the one dropped next).
    auto again = cache.tryPin(1);
    ASSERT_TRUE(again);
    auto other = cache.tryAcquire(2, m.make(2, 100), sizeOf);
    ASSERT_TRUE(other);
    other.reset();
    auto third = cache.tryAcquire(3, m.make(3, 100), sizeOf);  // 1 is pinned: 2 goes
    ASSERT_TRUE(third);
    EXPECT_TRUE(cache.tryPin(1));
    EXPECT_FALSE(cache.tryPin(2));
    EXPECT_EQ(m.calls, 3);
}

TEST(LruCache, TryPinWaitsForTheCallerMakingTheValue) {
    MemoryBudget budget;
    Cache cache(&budget, MemoryCategory::Tessellation);
    std::atomic<bool> making{false}, finish{false};
    std::thread maker([&] {
        auto pin = cache.tryAcquire(
            4,
            [&] {
                making = true;
                while (!finish) std::this_thread::yield();
                return std::string(10, 'x');
            },
            sizeOf);
        EXPECT_TRUE(pin);
    });
    while (!making) std::this_thread::yield();
    std::thread finisher([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        finish = true;
    });
    auto found = cache.tryPin(4);  // waits for the maker instead of answering "not resident"
    ASSERT_TRUE(found);
    EXPECT_EQ(**found, std::string(10, 'x'));
    maker.join();
    finisher.join();
    EXPECT_EQ(cache.stats().made, 1u);
}

TEST(LruCache, ConcurrentCallersOfOneKeyWaitForOneMaker) {
    MemoryBudget budget;
    Cache cache(&budget, MemoryCategory::Tessellation);
    std::atomic<int> calls{0};
    std::vector<std::thread> threads;
    std::vector<const std::string*> got(6, nullptr);
    for (size_t i = 0; i < got.size(); ++i)
        threads.emplace_back([&, i] {
            auto pin = cache.tryAcquire(
                7,
                [&] {
                    ++calls;
                    std::this_thread::sleep_for(std::chrono::milliseconds(20));
                    return std::string(64, 'x');
                },
                sizeOf);
            got[i] = pin ? pin->get() : nullptr;
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(calls, 1);
    for (const std::string* p : got) EXPECT_EQ(p, got[0]);
    EXPECT_EQ(budget.usedBytes(), 64u);
}

TEST(LruCache, EvictsTheLeastRecentlyUsedUnpinnedValueAndRecomputesIt) {
    MemoryBudget budget(300);
    Maker m;
    Cache cache(&budget, MemoryCategory::Tessellation);
    cache.tryAcquire(1, m.make(1, 100), sizeOf);  // each Pin is dropped at once: unpinned
    cache.tryAcquire(2, m.make(2, 100), sizeOf);
    cache.tryAcquire(3, m.make(3, 100), sizeOf);
    cache.tryAcquire(1, m.make(1, 100), sizeOf);  // 1 is now the most recently used
    EXPECT_EQ(m.calls, 3);
    auto four = cache.tryAcquire(4, m.make(4, 100), sizeOf);  // drops 2, the oldest
    ASSERT_TRUE(four);
    EXPECT_EQ(cache.stats().evicted, 1u);
    EXPECT_EQ(budget.usedBytes(), 300u);
    cache.tryAcquire(1, m.make(1, 100), sizeOf);
    EXPECT_EQ(m.calls, 4) << "1 stayed resident";
    cache.tryAcquire(2, m.make(2, 100), sizeOf);  // made again: drops 3
    EXPECT_EQ(m.calls, 5);
    EXPECT_EQ(cache.stats().recomputed, 1u);
    EXPECT_EQ(cache.stats().evicted, 2u);
    EXPECT_LE(budget.peakBytes(), 300u);
}

TEST(LruCache, PinnedValuesAreNeverDroppedAndAValueThatCannotFitIsRefused) {
    MemoryBudget budget(250);
    Maker m;
    Cache cache(&budget, MemoryCategory::Tessellation);
    auto a = cache.tryAcquire(1, m.make(1, 100), sizeOf);
    auto b = cache.tryAcquire(2, m.make(2, 100), sizeOf);
    ASSERT_TRUE(a && b);
    auto c = cache.tryAcquire(3, m.make(3, 100), sizeOf);
    EXPECT_FALSE(c) << "both residents are pinned";
    EXPECT_EQ(cache.stats().refused, 1u);
    EXPECT_EQ(budget.usedBytes(), 200u) << "nothing charged for the refused value";
    EXPECT_EQ(**a, std::string(100, 'b'));
    b.reset();
    auto again = cache.tryAcquire(3, m.make(3, 100), sizeOf);
    ASSERT_TRUE(again) << "room made by dropping the unpinned 2";
    EXPECT_EQ(cache.stats().evicted, 1u);
    EXPECT_FALSE(cache.tryAcquire(9, m.make(9, 1000), sizeOf)) << "larger than the cap";
}

TEST(LruCache, ReclaimDropsUnpinnedValuesForAnotherConsumer) {
    MemoryBudget budget(300);
    Maker m;
    Cache cache(&budget, MemoryCategory::Tessellation);
    auto pinned = cache.tryAcquire(1, m.make(1, 100), sizeOf);
    cache.tryAcquire(2, m.make(2, 100), sizeOf);
    cache.tryAcquire(3, m.make(3, 100), sizeOf);
    EXPECT_TRUE(cache.reclaim(100));
    EXPECT_EQ(cache.stats().evicted, 1u);
    EXPECT_EQ(budget.availableBytes(), 100u);
    EXPECT_FALSE(cache.reclaim(250)) << "the pinned value stays";
    EXPECT_EQ(budget.usedBytes(), 100u);
}

TEST(LruCache, UnlimitedBudgetNeverEvictsAndDestructionReleasesEveryCharge) {
    MemoryBudget budget;
    {
        Maker m;
        Cache cache(&budget, MemoryCategory::Tessellation);
        for (int k = 0; k < 50; ++k) ASSERT_TRUE(cache.tryAcquire(k, m.make(k % 20, 1000), sizeOf));
        EXPECT_EQ(cache.stats().evicted, 0u);
        EXPECT_EQ(cache.residentBytes(), 50000u);
        EXPECT_EQ(budget.usedBytes(), 50000u);
        cache.dropUnpinned();
        EXPECT_EQ(budget.usedBytes(), 0u);
        EXPECT_EQ(cache.stats().evicted, 50u);
        ASSERT_TRUE(cache.tryAcquire(3, m.make(3, 10), sizeOf));
    }
    EXPECT_EQ(budget.usedBytes(), 0u);
}

TEST(LruCache, AMakerThatThrowsLeavesTheKeyFreeForTheNextCaller) {
    MemoryBudget budget;
    Cache cache(&budget, MemoryCategory::Tessellation);
    EXPECT_THROW(cache.tryAcquire(1, []() -> std::string { throw std::runtime_error("no"); }, sizeOf),
                 std::runtime_error);
    auto pin = cache.tryAcquire(1, [] { return std::string("ok"); }, sizeOf);
    ASSERT_TRUE(pin);
    EXPECT_EQ(**pin, "ok");
    EXPECT_EQ(budget.usedBytes(), 2u);
}

}  // namespace
}  // namespace pushpin::cache
