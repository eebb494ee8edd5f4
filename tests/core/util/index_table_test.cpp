#include "core/util/index_table.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using pushpin::util::IndexTable;
using pushpin::util::hashBytes;

// Keys live beside the table, as they do in its users: entry i has key keys[i].
struct Keyed {
    std::vector<std::string> keys;
    IndexTable table;
    uint32_t find(const std::string& k) const {
        return table.find(hashBytes(k), [&](uint32_t e) { return keys[e] == k; });
    }
    uint32_t add(const std::string& k) {
        const uint32_t e = uint32_t(keys.size());
        keys.push_back(k);
        table.insert(hashBytes(k), e);
        return e;
    }
    uint32_t erase(const std::string& k) {
        return table.erase(hashBytes(k), [&](uint32_t e) { return keys[e] == k; });
    }
};

TEST(IndexTable, EmptyFindsNothing) {
    IndexTable t;
    EXPECT_EQ(t.find(hashBytes("a"), [](uint32_t) { return true; }), IndexTable::kNone);
    EXPECT_EQ(t.erase(hashBytes("a"), [](uint32_t) { return true; }), IndexTable::kNone);
    EXPECT_TRUE(t.empty());
}

TEST(IndexTable, FindsWhatWasInsertedAcrossGrowth) {
    Keyed k;
    for (int i = 0; i < 100000; ++i) ASSERT_EQ(k.add("n" + std::to_string(i)), uint32_t(i));
    EXPECT_EQ(k.table.size(), 100000u);
    for (int i = 0; i < 100000; ++i) ASSERT_EQ(k.find("n" + std::to_string(i)), uint32_t(i)) << i;
    EXPECT_EQ(k.find("n100000"), IndexTable::kNone);
    EXPECT_EQ(k.find(""), IndexTable::kNone);
    // At most half full: 8 bytes a slot, at most 32 bytes an entry.
    EXPECT_LE(k.table.memoryBytes(), 100000u * 32);
}

// Every hash the same: lookups still compare keys, and erasing from the middle of one long run
// keeps the rest reachable.
TEST(IndexTable, CollidingHashesStayCorrect) {
    std::vector<std::string> keys;
    IndexTable t;
    auto matches = [&](const std::string& s) { return [&keys, s](uint32_t e) { return keys[e] == s; }; };
    for (int i = 0; i < 200; ++i) {
        keys.push_back("k" + std::to_string(i));
        t.insert(42, uint32_t(i));
    }
    for (int i = 0; i < 200; i += 3) EXPECT_EQ(t.erase(42, matches("k" + std::to_string(i))), uint32_t(i));
    for (int i = 0; i < 200; ++i) {
        const uint32_t want = i % 3 == 0 ? IndexTable::kNone : uint32_t(i);
        EXPECT_EQ(t.find(42, matches("k" + std::to_string(i))), want) << i;
    }
}

TEST(IndexTable, ReplaceKeepsTheKeyAndChangesTheEntry) {
    IndexTable t;
    t.insert(7, 1);
    EXPECT_TRUE(t.replace(7, [](uint32_t e) { return e == 1; }, 5));
    EXPECT_EQ(t.find(7, [](uint32_t e) { return e == 5; }), 5u);
    EXPECT_EQ(t.find(7, [](uint32_t e) { return e == 1; }), IndexTable::kNone);
    EXPECT_FALSE(t.replace(8, [](uint32_t) { return true; }, 9));
}

// Random inserts and erases against std::map: the table agrees after every step, including
// runs that wrap around the end of the slot array (backward-shift deletion).
TEST(IndexTable, AgreesWithAMapUnderRandomInsertsAndErases) {
    std::mt19937 rng(12345);
    std::vector<std::string> keys;
    std::map<std::string, uint32_t> live;
    IndexTable t;
    auto matches = [&](const std::string& s) { return [&keys, s](uint32_t e) { return keys[e] == s; }; };
    for (int step = 0; step < 60000; ++step) {
        const std::string key = "k" + std::to_string(rng() % 3000);
        const uint64_t h = hashBytes(key);
        if (rng() % 3 != 0) {
            if (!live.count(key)) {
                keys.push_back(key);
                t.insert(h, uint32_t(keys.size() - 1));
                live[key] = uint32_t(keys.size() - 1);
            }
        } else {
            const uint32_t removed = t.erase(h, matches(key));
            auto it = live.find(key);
            ASSERT_EQ(removed, it == live.end() ? IndexTable::kNone : it->second) << step;
            if (it != live.end()) live.erase(it);
        }
        ASSERT_EQ(t.size(), live.size());
        if (step % 1000 == 0) {
            for (const auto& [k, e] : live) {
                ASSERT_EQ(t.find(hashBytes(k), matches(k)), e) << step << " " << k;
            }
        }
    }
}

}  // namespace
