// tests/texture/page_map_test.cpp: the shard map against std::unordered_map as a model.
#include "texture/detail/page_map.h"

#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

namespace pushpin::texture::detail {
namespace {

TEST(PageMap, MatchesAModelUnderRandomInsertsAndErases) {
    PageMap<uint32_t> map;
    std::unordered_map<uint64_t, uint32_t> model;
    std::mt19937_64 rng(9);
    for (int i = 0; i < 200000; ++i) {
        // Few distinct keys with clustered hashes, so probe runs collide and wrap.
        const uint64_t key = (rng() % 600) << (rng() % 2 ? 19 : 38);
        const int op = int(rng() % 3);
        uint32_t* found = map.find(key);
        auto it = model.find(key);
        ASSERT_EQ(found != nullptr, it != model.end()) << "step " << i;
        if (found) {
            ASSERT_EQ(*found, it->second);
        }
        if (op == 0 && !found) {
            map.insert(key) = uint32_t(i);
            model[key] = uint32_t(i);
        } else if (op == 1) {
            EXPECT_EQ(map.erase(key), it != model.end());
            model.erase(key);
        }
        ASSERT_EQ(map.size(), model.size());
    }
    for (const auto& [k, v] : model) {
        ASSERT_NE(map.find(k), nullptr);
        EXPECT_EQ(*map.find(k), v);
    }
}

TEST(PageMap, InsertedEntriesStartValueInitialised) {
    PageMap<uint64_t> map;
    map.insert(5) = 77;
    map.erase(5);
    EXPECT_EQ(map.insert(5), 0u);
    EXPECT_FALSE(map.erase(6));
}

}  // namespace
}  // namespace pushpin::texture::detail
