// Tests of cache/zstd_codec.h: compact frames round trip, dictionaries help small blocks, and
// corrupt or mismatched input fails cleanly.
#include "cache/zstd_codec.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cache/error.h"

namespace pushpin::cache {
namespace {

std::vector<uint8_t> structuredBlock(uint32_t seed, size_t n) {
    std::mt19937 rng(seed);
    std::vector<uint8_t> b(n);
    for (size_t i = 0; i < n; ++i) b[i] = uint8_t((i % 16) * 3 + (rng() % 4) + ((i / 64) % 2) * 100);
    return b;
}

TEST(ZstdCodec, RoundTripsWithoutDictionary) {
    ZstdCompressor c(3);
    ZstdDecompressor d;
    for (size_t n : {size_t(1), size_t(64), size_t(192), size_t(4096), size_t(100000)}) {
        const std::vector<uint8_t> src = structuredBlock(uint32_t(n), n);
        std::vector<uint8_t> packed(zstdCompressBound(n));
        const size_t size = c.compress(src.data(), n, packed.data(), packed.size());
        ASSERT_GT(size, 0u);
        std::vector<uint8_t> back(n);
        ASSERT_TRUE(d.decompress(packed.data(), size, back.data(), n));
        EXPECT_EQ(back, src);
    }
}

TEST(ZstdCodec, TrainedDictionaryShrinksSmallBlocksAndRoundTrips) {
    std::vector<uint8_t> samples;
    std::vector<size_t> sizes;
    for (uint32_t i = 0; i < 2000; ++i) {
        const auto b = structuredBlock(i, 192);
        samples.insert(samples.end(), b.begin(), b.end());
        sizes.push_back(b.size());
    }
    const std::vector<uint8_t> dictBytes = trainZstdDictionary(samples.data(), sizes.data(), sizes.size(), 8192);
    ASSERT_FALSE(dictBytes.empty());
    auto dict = std::make_shared<ZstdDictionary>(dictBytes.data(), dictBytes.size(), 3);
    ZstdCompressor plain(3), withDict(3, dict);
    ZstdDecompressor d(dict);
    size_t plainTotal = 0, dictTotal = 0;
    for (uint32_t i = 5000; i < 5100; ++i) {
        const auto src = structuredBlock(i, 192);
        std::vector<uint8_t> p(zstdCompressBound(192)), q(zstdCompressBound(192)), back(192);
        plainTotal += plain.compress(src.data(), src.size(), p.data(), p.size());
        const size_t n = withDict.compress(src.data(), src.size(), q.data(), q.size());
        ASSERT_GT(n, 0u);
        dictTotal += n;
        ASSERT_TRUE(d.decompress(q.data(), n, back.data(), back.size()));
        EXPECT_EQ(back, src);
    }
    EXPECT_LT(dictTotal, plainTotal);
}

TEST(ZstdCodec, DecompressionOnlyDictionaryDecodesInLessMemory) {
    std::vector<uint8_t> samples;
    std::vector<size_t> sizes;
    for (uint32_t i = 0; i < 2000; ++i) {
        const auto b = structuredBlock(i, 192);
        samples.insert(samples.end(), b.begin(), b.end());
        sizes.push_back(b.size());
    }
    const std::vector<uint8_t> dictBytes = trainZstdDictionary(samples.data(), sizes.data(), sizes.size(), 8192);
    ASSERT_FALSE(dictBytes.empty());
    auto both = std::make_shared<ZstdDictionary>(dictBytes.data(), dictBytes.size(), 3);
    auto readOnly = std::make_shared<ZstdDictionary>(dictBytes.data(), dictBytes.size());
    EXPECT_LT(readOnly->memoryBytes(), both->memoryBytes());
    EXPECT_GE(readOnly->memoryBytes(), dictBytes.size());
    EXPECT_THROW(ZstdCompressor(3, readOnly), std::invalid_argument);
    ZstdCompressor c(3, both);
    ZstdDecompressor d(readOnly);
    const auto src = structuredBlock(9000, 192);
    std::vector<uint8_t> q(zstdCompressBound(192)), back(192);
    const size_t n = c.compress(src.data(), src.size(), q.data(), q.size());
    ASSERT_GT(n, 0u);
    ASSERT_TRUE(d.decompress(q.data(), n, back.data(), back.size()));
    EXPECT_EQ(back, src);
}

TEST(ZstdCodec, TrainingFailsGracefullyOnTooFewSamples) {
    const auto b = structuredBlock(1, 100);
    const size_t sizes[] = {50, 50};
    EXPECT_TRUE(trainZstdDictionary(b.data(), sizes, 2, 4096).empty());
}

TEST(ZstdCodec, ReportsCorruptWrongSizeAndTooSmallOutputAsFailure) {
    ZstdCompressor c(3);
    ZstdDecompressor d;
    const auto src = structuredBlock(7, 1000);
    std::vector<uint8_t> packed(zstdCompressBound(src.size()));
    const size_t n = c.compress(src.data(), src.size(), packed.data(), packed.size());
    ASSERT_GT(n, 0u);
    std::vector<uint8_t> back(2000);
    EXPECT_FALSE(d.decompress(packed.data(), n, back.data(), 999));   // expects fewer bytes than the frame holds
    EXPECT_FALSE(d.decompress(packed.data(), n, back.data(), 1001));  // expects more
    EXPECT_FALSE(d.decompress(packed.data(), n / 2, back.data(), 1000));  // truncated
    std::mt19937 rng(3);
    int failures = 0;
    for (int i = 0; i < 200; ++i) {
        std::vector<uint8_t> bad(packed.begin(), packed.begin() + std::ptrdiff_t(n));
        bad[rng() % n] ^= uint8_t(1 + rng() % 255);
        if (!d.decompress(bad.data(), bad.size(), back.data(), 1000)) ++failures;
    }
    EXPECT_GT(failures, 0);
    // Output that does not fit is reported as 0, not truncated.
    std::vector<uint8_t> tiny(8);
    EXPECT_EQ(c.compress(src.data(), src.size(), tiny.data(), tiny.size()), 0u);
}

TEST(ZstdCodec, DictionaryMismatchIsDetected) {
    std::vector<uint8_t> samples;
    std::vector<size_t> sizes;
    for (uint32_t i = 0; i < 1000; ++i) {
        const auto b = structuredBlock(i, 192);
        samples.insert(samples.end(), b.begin(), b.end());
        sizes.push_back(b.size());
    }
    const auto dictBytes = trainZstdDictionary(samples.data(), sizes.data(), sizes.size(), 4096);
    ASSERT_FALSE(dictBytes.empty());
    auto dict = std::make_shared<ZstdDictionary>(dictBytes.data(), dictBytes.size(), 3);
    ZstdCompressor c(3, dict);
    const auto src = structuredBlock(99999, 192);
    std::vector<uint8_t> packed(zstdCompressBound(192)), back(192);
    const size_t n = c.compress(src.data(), src.size(), packed.data(), packed.size());
    ASSERT_GT(n, 0u);
    ZstdDecompressor none;
    const bool ok = none.decompress(packed.data(), n, back.data(), back.size());
    EXPECT_TRUE(!ok || back != src);
    none.setDictionary(dict);
    ASSERT_TRUE(none.decompress(packed.data(), n, back.data(), back.size()));
    EXPECT_EQ(back, src);
}

TEST(ZstdCodec, RejectsGarbageDictionaryBytesOrAcceptsThemAsRawContent) {
    // zstd treats bytes without the dictionary magic as raw content; they must still round trip.
    const std::vector<uint8_t> raw = structuredBlock(4, 512);
    auto dict = std::make_shared<ZstdDictionary>(raw.data(), raw.size(), 1);
    ZstdCompressor c(1, dict);
    ZstdDecompressor d(dict);
    const auto src = structuredBlock(4, 192);
    std::vector<uint8_t> packed(zstdCompressBound(192)), back(192);
    const size_t n = c.compress(src.data(), src.size(), packed.data(), packed.size());
    ASSERT_GT(n, 0u);
    EXPECT_LT(n, 40u);  // the block repeats the dictionary content
    ASSERT_TRUE(d.decompress(packed.data(), n, back.data(), back.size()));
    EXPECT_EQ(back, src);
}

}  // namespace
}  // namespace pushpin::cache
