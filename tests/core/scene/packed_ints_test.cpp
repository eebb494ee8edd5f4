#include "core/scene/packed_ints.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/scene/value.h"

namespace pushpin::scene {
namespace {

std::vector<int32_t> readAll(const PackedInts& p) {
    std::vector<int32_t> out(p.size());
    p.read(0, out.size(), out.data());
    return out;
}

// The edges Maya writes for a w × h grid of quads: horizontal edges row by row, then vertical
// ones, each as (first point, second point, smooth).
std::vector<int32_t> gridEdges(int w, int h) {
    std::vector<int32_t> out;
    for (int y = 0; y <= h; ++y)
        for (int x = 0; x < w; ++x) out.insert(out.end(), {y * (w + 1) + x, y * (w + 1) + x + 1, 1});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x <= w; ++x) out.insert(out.end(), {y * (w + 1) + x, (y + 1) * (w + 1) + x, 1});
    return out;
}

TEST(PackedInts, EmptyAndOneNumber) {
    const PackedInts empty({}, 1);
    EXPECT_TRUE(empty.empty());
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_EQ(empty.heapBytes(), 0u);
    EXPECT_NO_THROW(empty.read(0, 0, nullptr));
    EXPECT_THROW(empty[0], std::out_of_range);

    const std::vector<int32_t> one{-7};
    const PackedInts p(one, 3);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0], -7);
    EXPECT_THROW(p[1], std::out_of_range);
}

TEST(PackedInts, ExtremeValuesRoundTrip) {
    constexpr int32_t lo = std::numeric_limits<int32_t>::min(), hi = std::numeric_limits<int32_t>::max();
    const std::vector<int32_t> v{lo, hi, 0, -1, hi, lo, lo, 1, hi - 1, lo + 1, 0, 0, hi, hi, lo, -1};
    for (size_t stride : {size_t(1), size_t(2), size_t(3), size_t(4), size_t(16), size_t(1000)})
        EXPECT_EQ(readAll(PackedInts(v, stride)), v) << "stride " << stride;
}

// Random numbers of every size class, at lengths around the block size, read whole and in ranges
// that start and end anywhere.
TEST(PackedInts, RandomNumbersRoundTripInAnyRange) {
    std::mt19937 rng(12345);
    for (size_t n : {size_t(2), size_t(1023), size_t(1024), size_t(1025), size_t(5000)}) {
        std::vector<int32_t> v(n);
        for (size_t i = 0; i < n; ++i) {
            const int bits = int(rng() % 32);
            v[i] = int32_t(rng() >> (31 - bits)) * ((rng() & 1) ? 1 : -1);
        }
        for (size_t stride : {size_t(1), size_t(3), size_t(4), size_t(300)}) {
            const PackedInts p(v, stride);
            ASSERT_EQ(p.size(), n);
            EXPECT_EQ(readAll(p), v) << n << " numbers, stride " << stride;
            for (int k = 0; k < 50; ++k) {
                const size_t first = rng() % n, count = rng() % (n - first + 1);
                std::vector<int32_t> part(count);
                p.read(first, count, part.data());
                EXPECT_TRUE(std::equal(part.begin(), part.end(), v.begin() + std::ptrdiff_t(first)))
                    << n << " numbers, stride " << stride << ", [" << first << ", " << first + count << ")";
            }
            EXPECT_THROW(p.read(n - 1, 2, std::vector<int32_t>(2).data()), std::out_of_range);
            EXPECT_THROW(p.read(n + 1, 0, nullptr), std::out_of_range);
        }
    }
}

// A grid's edges cost well under a byte an edge; random numbers no more than their 7-bit groups
// and the block table.
TEST(PackedInts, RegularIdsPackSmallAndNoiseDoesNotGrow) {
    const std::vector<int32_t> edges = gridEdges(300, 200);
    const PackedInts p(edges, 3);
    EXPECT_EQ(readAll(p), edges);
    EXPECT_LT(p.heapBytes(), edges.size() / 3) << "bytes for " << edges.size() / 3 << " edges";

    std::mt19937 rng(7);
    std::vector<int32_t> noise(100000);
    for (int32_t& x : noise) x = int32_t(rng());
    const PackedInts q(noise, 1);
    EXPECT_EQ(readAll(q), noise);
    const size_t blocks = (noise.size() + PackedInts::kBlockNumbers - 1) / PackedInts::kBlockNumbers;
    EXPECT_LE(q.heapBytes(), 5 * noise.size() + blocks * (2 + 8));
}

// Reading many arrays in turn, more than a thread keeps decoded, gives each its own numbers; so do
// copies, and threads reading the same arrays at once.
TEST(PackedInts, ManyArraysCopiesAndThreadsReadTheirOwnNumbers) {
    std::vector<std::vector<int32_t>> plain;
    std::vector<PackedInts> packed;
    for (int a = 0; a < 3 * int(PackedInts::kCachedBlocks); ++a) {
        std::vector<int32_t> v(3000);
        for (size_t i = 0; i < v.size(); ++i) v[i] = int32_t(i) * (a + 1) - a;
        packed.emplace_back(v, 1);
        plain.push_back(std::move(v));
    }
    for (size_t i = 0; i < 3000; i += 7)
        for (size_t a = 0; a < packed.size(); ++a) ASSERT_EQ(packed[a][i], plain[a][i]) << a << " " << i;
    const PackedInts copy = packed[2];
    EXPECT_EQ(readAll(copy), plain[2]);

    std::vector<std::thread> threads;
    std::vector<int> wrong(4, 0);
    for (size_t t = 0; t < wrong.size(); ++t)
        threads.emplace_back([&, t] {
            for (int round = 0; round < 20; ++round)
                for (size_t a = t; a < packed.size(); a += 2)
                    for (size_t i = (round * 131) % 3000; i < 3000; i += 97)
                        if (packed[a][i] != plain[a][i]) ++wrong[t];
        });
    for (std::thread& th : threads) th.join();
    for (int w : wrong) EXPECT_EQ(w, 0);
}

// Stored integer runs of a multi attribute are packed and read back through Numbers.
TEST(PackedInts, NumbersKeepIntegerRunsPacked) {
    const std::vector<int32_t> edges = gridEdges(40, 30);
    Numbers n{Numbers::Kind::Plain, 1, std::vector<double>(edges.begin(), edges.end())};
    compactNumbers(n, edges.size() / 3, false, true);
    ASSERT_EQ(n.storage(), Numbers::Storage::Ints);
    EXPECT_TRUE(n.values.empty());
    ASSERT_EQ(n.size(), edges.size());
    std::vector<double> back(edges.size());
    n.copyTo(0, back.size(), back.data());
    for (size_t i = 0; i < edges.size(); ++i) ASSERT_EQ(back[i], double(edges[i])) << i;
    EXPECT_EQ(n.at(edges.size() - 2), double(edges[edges.size() - 2]));
    const Numbers part = n.slice(30, 9);
    ASSERT_EQ(part.size(), 9u);
    for (size_t i = 0; i < 9; ++i) EXPECT_EQ(part.at(i), double(edges[30 + i]));
    // Packed runs take no more numbers: a later run starts a run of its own.
    Numbers more{Numbers::Kind::Plain, 1, {1, 2, 3}};
    EXPECT_FALSE(n.append(more));
    EXPECT_TRUE(n.append(Numbers{}));
    EXPECT_EQ(n.size(), edges.size());
}

// A polyFaces record keeps its ids packed and gives them back loop by loop.
TEST(PackedInts, FaceRecordsReadBackLoopByLoop) {
    PolyFaces::Builder b;
    std::vector<std::vector<int32_t>> loops;
    std::mt19937 rng(3);
    for (int f = 0; f < 3000; ++f) {
        const int n = 3 + int(rng() % 3);
        std::vector<int32_t> e(static_cast<size_t>(n));
        for (int32_t& x : e) x = int32_t(rng() % 100000) - 50000;
        b.addFace(e);
        std::vector<int32_t> uv(static_cast<size_t>(n));
        for (int32_t& x : uv) x = int32_t(rng() % 9000);
        b.addUvs(0, 0, uv);
        loops.push_back(e);
        loops.push_back(uv);
    }
    const PolyFaces pf = b.finish();
    ASSERT_EQ(pf.faceCount(), 3000u);
    std::vector<int32_t> scratch;
    for (size_t f = 0; f < 3000; ++f) {
        ASSERT_EQ(pf.edgeCount(f), loops[2 * f].size());
        const std::span<const int32_t> e = pf.edges(f, scratch);
        ASSERT_TRUE(std::equal(e.begin(), e.end(), loops[2 * f].begin(), loops[2 * f].end())) << f;
        ASSERT_EQ(pf.uvCount(f), 1u);
        const PolyFaces::Uv uv = pf.uv(f, 0, scratch);
        ASSERT_TRUE(std::equal(uv.ids.begin(), uv.ids.end(), loops[2 * f + 1].begin(), loops[2 * f + 1].end())) << f;
        EXPECT_TRUE(pf.colors(f).empty());
    }
}

}  // namespace
}  // namespace pushpin::scene
