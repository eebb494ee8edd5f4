#include "core/scene/detail/name_index.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using pushpin::scene::detail::NameIndex;

// Names live beside the index, as node names do: entry i is named names[i].
struct Named {
    std::vector<std::string> names;
    NameIndex index;
    uint32_t find(const std::string& name) const {
        return index.find(name, [&](uint32_t e) -> std::string_view { return names[e]; });
    }
    uint32_t add(const std::string& name) {
        const uint32_t e = uint32_t(names.size());
        names.push_back(name);
        index.insert(name, e);
        return e;
    }
};

TEST(NameIndex, SplitsOnlyCanonicalTrailingNumbers) {
    auto s = NameIndex::split("pCubeShape12");
    EXPECT_TRUE(s.numbered);
    EXPECT_EQ(s.base, "pCubeShape");
    EXPECT_EQ(s.number, 12u);
    s = NameIndex::split("x0");
    EXPECT_TRUE(s.numbered);
    EXPECT_EQ(s.number, 0u);
    EXPECT_FALSE(NameIndex::split("x").numbered);
    EXPECT_FALSE(NameIndex::split("x012").numbered);    // a leading zero: "x012" is not "x12"
    EXPECT_FALSE(NameIndex::split("x00").numbered);
    EXPECT_FALSE(NameIndex::split("x1234567890").numbered);  // ten digits
    EXPECT_TRUE(NameIndex::split("x123456789").numbered);
    s = NameIndex::split("42");
    EXPECT_TRUE(s.numbered);
    EXPECT_EQ(s.base, "");
    EXPECT_EQ(s.number, 42u);
    EXPECT_FALSE(NameIndex::split("").numbered);
}

TEST(NameIndex, NumberedAndPlainNamesAreDistinct) {
    Named n;
    const uint32_t x = n.add("x");
    const uint32_t x1 = n.add("x1");
    const uint32_t x01 = n.add("x01");
    const uint32_t far = n.add("x999999");  // far past the base's count: kept in the hash table
    const uint32_t ns = n.add("ns:x1");
    EXPECT_EQ(n.find("x"), x);
    EXPECT_EQ(n.find("x1"), x1);
    EXPECT_EQ(n.find("x01"), x01);
    EXPECT_EQ(n.find("x999999"), far);
    EXPECT_EQ(n.find("ns:x1"), ns);
    EXPECT_EQ(n.find("x2"), NameIndex::kNone);
    EXPECT_EQ(n.find("x001"), NameIndex::kNone);
    EXPECT_EQ(n.find("y1"), NameIndex::kNone);
    EXPECT_EQ(n.index.size(), 5u);
}

TEST(NameIndex, ReplaceAndEraseFindTheEntryWhereverItLives) {
    Named n;
    n.add("a5");
    n.add("a100000");
    n.add("b");
    for (const std::string name : {"a5", "a100000", "b"}) {
        const uint32_t e = n.find(name);
        ASSERT_NE(e, NameIndex::kNone) << name;
        EXPECT_FALSE(n.index.replace(name, e + 7, 9));  // not the entry stored there
        EXPECT_TRUE(n.index.replace(name, e, 9));
        EXPECT_EQ(n.index.find(name, [&](uint32_t) -> std::string_view { return name; }), 9u) << name;
        EXPECT_FALSE(n.index.erase(name, e));
        EXPECT_TRUE(n.index.erase(name, 9));
        EXPECT_EQ(n.find(name), NameIndex::kNone) << name;
    }
    EXPECT_EQ(n.index.size(), 0u);
}

// A million renames of one base stay within a few bytes a name.
TEST(NameIndex, DenseNumbersCostAFewBytesEach) {
    Named n;
    constexpr uint32_t kCount = 1000000;
    n.names.reserve(kCount);
    for (uint32_t i = 1; i <= kCount; ++i) n.add("mesh" + std::to_string(i));
    EXPECT_EQ(n.find("mesh1"), 0u);
    EXPECT_EQ(n.find("mesh" + std::to_string(kCount)), kCount - 1);
    EXPECT_LT(n.index.memoryBytes(), size_t(kCount) * 12);
}

// Widely spread numbers under one base do not make its array grow past twice its names.
TEST(NameIndex, SparseNumbersStayBounded) {
    Named n;
    for (uint32_t i = 0; i < 10000; ++i) n.add("s" + std::to_string(i * 100003u % 999999937u));
    for (uint32_t i = 0; i < 10000; ++i) EXPECT_EQ(n.find("s" + std::to_string(i * 100003u % 999999937u)), i);
    EXPECT_LT(n.index.memoryBytes(), size_t(10000) * 64);
}

// Random inserts, replaces and erases agree with a std::map at every step.
TEST(NameIndex, AgreesWithAMapUnderRandomEdits) {
    std::mt19937 rng(7);
    std::vector<std::string> pool;
    for (const char* base : {"x", "pCube", "ns:a", "", "y_"})
        for (int k = 0; k < 60; ++k) {
            pool.push_back(std::string(base) + std::to_string(k * (k % 3 == 0 ? 1 : 37)));
            pool.push_back(std::string(base) + "0" + std::to_string(k));
        }
    pool.push_back("x");
    pool.push_back("plain");
    std::vector<std::string> names;  // entry → name
    NameIndex index;
    std::map<std::string, uint32_t> expect;
    auto nameOf = [&](uint32_t e) -> std::string_view { return names[e]; };
    for (int step = 0; step < 20000; ++step) {
        const std::string& name = pool[rng() % pool.size()];
        auto it = expect.find(name);
        const int op = int(rng() % 3);
        if (it == expect.end()) {
            const uint32_t e = uint32_t(names.size());
            names.push_back(name);
            index.insert(name, e);
            expect[name] = e;
        } else if (op == 0) {
            ASSERT_TRUE(index.erase(name, it->second));
            expect.erase(it);
        } else if (op == 1) {
            const uint32_t e = uint32_t(names.size());
            names.push_back(name);
            ASSERT_TRUE(index.replace(name, it->second, e));
            it->second = e;
        }
        const std::string& probe = pool[rng() % pool.size()];
        auto want = expect.find(probe);
        ASSERT_EQ(index.find(probe, nameOf), want == expect.end() ? NameIndex::kNone : want->second) << probe;
        ASSERT_EQ(index.size(), expect.size());
    }
}

}  // namespace
