// Tests for core/util/counting_sort.h: filing items by key, stably into a copy or in place.
#include "core/util/counting_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace pushpin::util {
namespace {

struct Item {
    uint32_t key = 0;
    uint32_t id = 0;  // the input position
};

std::vector<Item> randomItems(size_t count, uint32_t keys, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<Item> items(count);
    for (size_t i = 0; i < count; ++i) items[i] = {uint32_t(rng() % keys), uint32_t(i)};
    return items;
}

TEST(CountingSort, FileByKeyKeepsTheOrderWithinAKey) {
    const std::vector<Item> items = randomItems(5000, 37, 1);
    std::vector<uint32_t> start;
    std::vector<Item> out;
    fileByKey(
        37,
        [&](auto&& visit) {
            for (const Item& it : items) visit(it.key, it);
        },
        start, out);
    ASSERT_EQ(start.size(), 38u);
    ASSERT_EQ(out.size(), items.size());
    for (uint32_t k = 0; k < 37; ++k) {
        for (uint32_t i = start[k]; i < start[k + 1]; ++i) {
            EXPECT_EQ(out[i].key, k);
            if (i > start[k]) {
                EXPECT_LT(out[i - 1].id, out[i].id);
            }
        }
    }
}

TEST(CountingSort, InPlaceFilesEveryItemOnceUnderItsKey) {
    for (const uint32_t keys : {1u, 2u, 7u, 64u, 1000u}) {
        for (const size_t count : {size_t(0), size_t(1), size_t(5), size_t(4096)}) {
            SCOPED_TRACE(std::to_string(keys) + " keys, " + std::to_string(count) + " items");
            std::vector<Item> items = randomItems(count, keys, keys * 31 + uint32_t(count));
            std::vector<uint32_t> start, fill;
            fileByKeyInPlace(keys, items, [](const Item& it) { return it.key; }, start, fill);
            ASSERT_EQ(start.size(), keys + 1);
            EXPECT_EQ(start.front(), 0u);
            EXPECT_EQ(start.back(), count);
            std::vector<bool> seen(count, false);
            for (uint32_t k = 0; k < keys; ++k)
                for (uint32_t i = start[k]; i < start[k + 1]; ++i) {
                    EXPECT_EQ(items[i].key, k);
                    ASSERT_LT(items[i].id, count);
                    EXPECT_FALSE(seen[items[i].id]);
                    seen[items[i].id] = true;
                }
            EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](bool b) { return b; }));
        }
    }
}

TEST(CountingSort, InPlaceOrderDependsOnTheInputOnly) {
    std::vector<Item> a = randomItems(3000, 50, 9), b = a;
    std::vector<uint32_t> sa, fa, sb, fb = {7, 7, 7};  // scratch that starts different
    fileByKeyInPlace(50, a, [](const Item& it) { return it.key; }, sa, fa);
    fileByKeyInPlace(50, b, [](const Item& it) { return it.key; }, sb, fb);
    EXPECT_EQ(sa, sb);
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].id, b[i].id) << i;
}

}  // namespace
}  // namespace pushpin::util
