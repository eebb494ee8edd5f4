// Tests for core/util/page_array.h: values kept across growth, whole pages, moves and release.
#include "core/util/page_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>

namespace pushpin::util {
namespace {

struct Value {
    uint64_t a = 0;
    uint32_t b = 0;
};

TEST(PageArray, GrowsInWholePagesKeepingItsValues) {
    PageArray<Value> v;
    EXPECT_EQ(v.capacity(), 0u);
    EXPECT_EQ(v.bytes(), 0u);
    const uint64_t page = PageArray<Value>::bytesFor(1);
    EXPECT_GT(page, 0u);
    EXPECT_EQ(PageArray<Value>::bytesFor(0), 0u);
    for (uint32_t i = 0; i < 300000; ++i) {
        if (v.size() == v.capacity()) {
            const size_t before = v.capacity();
            v.reserve(before + before / 2 + 1);
            EXPECT_GE(v.capacity(), before + before / 2 + 1);
            EXPECT_EQ(v.bytes() % page, 0u);
            EXPECT_EQ(v.bytes(), PageArray<Value>::bytesFor(v.capacity()));
        }
        v.pushWithinCapacity({uint64_t(i) * 3, i});
    }
    ASSERT_EQ(v.size(), 300000u);
    for (uint32_t i = 0; i < 300000; ++i) {
        ASSERT_EQ(v[i].a, uint64_t(i) * 3);
        ASSERT_EQ(v[i].b, i);
    }
    const size_t capacity = v.capacity();
    v.reserve(10);  // never shrinks
    EXPECT_EQ(v.capacity(), capacity);
    v.clear();
    EXPECT_TRUE(v.empty());
    EXPECT_EQ(v.capacity(), capacity);

    PageArray<Value> w = std::move(v);
    EXPECT_EQ(w.capacity(), capacity);
    EXPECT_EQ(v.capacity(), 0u);
    EXPECT_EQ(v.data(), nullptr);
    w.release();
    EXPECT_EQ(w.capacity(), 0u);
    EXPECT_EQ(w.bytes(), 0u);
    w.reserve(1);
    w.pushWithinCapacity({7, 8});
    EXPECT_EQ(w[0].b, 8u);
}

}  // namespace
}  // namespace pushpin::util
