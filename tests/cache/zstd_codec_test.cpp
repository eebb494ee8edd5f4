// Tests of cache/zstd_codec.h: compact frames round trip, dictionaries help small blocks, and
// corrupt or mismatched input fails cleanly.
#include "cache/zstd_codec.h"

#include <gtest/gtest.h>

#include <cmath>
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

// Zigzagged residuals of smooth data with noise: small values, about 3.5 bits each, no repeats.
std::vector<uint8_t> residualBlock(uint32_t seed, size_t n, int spread = 9) {
    std::mt19937 rng(seed);
    std::vector<uint8_t> b(n);
    for (auto& v : b) {
        const int r = int(rng() % uint32_t(spread)) + int(rng() % uint32_t(spread)) - spread + 1;  // triangular
        v = uint8_t(r >= 0 ? 2 * r : -2 * r - 1);
    }
    return b;
}

struct Samples {
    std::vector<uint8_t> bytes;
    std::vector<size_t> sizes;
};

Samples residualSamples(size_t count, size_t blockBytes) {
    Samples s;
    for (uint32_t i = 0; i < count; ++i) {
        const auto b = residualBlock(i, blockBytes);
        s.bytes.insert(s.bytes.end(), b.begin(), b.end());
        s.sizes.push_back(blockBytes);
    }
    return s;
}

// Compresses src compactly, checks the form decodes back, and returns the stored size.
size_t compactRoundTrip(ZstdCompressor& c, ZstdDecompressor& d, const std::vector<uint8_t>& src, ZstdForm* formOut) {
    std::vector<uint8_t> stored(zstdCompressBound(src.size())), back(src.size());
    ZstdForm form = ZstdForm::Frame;
    const size_t n = c.compressCompact(src.data(), src.size(), stored.data(), stored.size(), form);
    EXPECT_GT(n, 0u);
    EXPECT_TRUE(d.decompress(form, stored.data(), n, back.data(), back.size())) << zstdFormName(form);
    EXPECT_EQ(back, src) << zstdFormName(form);
    if (formOut) *formOut = form;
    return n;
}

// A literal dictionary for 189-byte residual blocks, built from `count` samples (null on failure).
std::shared_ptr<ZstdDictionary> literalDictionary(size_t count) {
    const Samples s = residualSamples(count, 189);
    const auto bytes = buildZstdLiteralDictionary(s.bytes.data(), s.sizes.data(), s.sizes.size(), 189, 1);
    return bytes.empty() ? nullptr : std::make_shared<ZstdDictionary>(bytes.data(), bytes.size(), 1);
}

TEST(ZstdCodec, CompactFormsDropOnlyTheHeadersTheDecompressorRebuilds) {
    const auto dict = literalDictionary(3000);
    ASSERT_TRUE(dict);
    ZstdCompressor c(1, dict);
    c.tune({-7, 7, true});
    ZstdDecompressor d(dict);
    int forms[3] = {};
    for (uint32_t i = 10000; i < 10200; ++i) {
        const auto src = residualBlock(i, 189);
        std::vector<uint8_t> frame(zstdCompressBound(src.size()));
        const size_t whole = c.compress(src.data(), src.size(), frame.data(), frame.size());
        ZstdForm form;
        const size_t n = compactRoundTrip(c, d, src, &form);
        ++forms[int(form)];
        // What is stored plus the rebuilt headers is the whole frame zstd wrote.
        EXPECT_EQ(n + zstdFormOverheadBytes(form, src.size()), whole) << zstdFormName(form);
    }
    // Literals coded with the dictionary's table, without sequences, are the common case here.
    EXPECT_GT(forms[int(ZstdForm::Literals)], 150);
    // A block of runs has sequences: a block body. Larger blocks are blocks too.
    ZstdForm form;
    compactRoundTrip(c, d, std::vector<uint8_t>(189, 0), &form);
    EXPECT_EQ(form, ZstdForm::Block);
    ZstdCompressor plain(1);
    ZstdDecompressor plainD;
    compactRoundTrip(plain, plainD, structuredBlock(3, 5000), &form);
    EXPECT_EQ(form, ZstdForm::Block);
    compactRoundTrip(plain, plainD, structuredBlock(3, 100000), &form);
    EXPECT_EQ(form, ZstdForm::Block);
}

TEST(ZstdCodec, CompactFormsRejectWrongOrDamagedInput) {
    const auto dict = literalDictionary(2000);
    ASSERT_TRUE(dict);
    ZstdCompressor c(1, dict);
    ZstdDecompressor d(dict);
    const auto src = residualBlock(77, 189);
    std::vector<uint8_t> stored(zstdCompressBound(189)), back(189);
    ZstdForm form;
    const size_t n = c.compressCompact(src.data(), src.size(), stored.data(), stored.size(), form);
    ASSERT_GT(n, 0u);
    ASSERT_EQ(form, ZstdForm::Literals);
    // The wrong form, the wrong size, a truncated stream, no dictionary, an unknown form value.
    EXPECT_FALSE(d.decompress(ZstdForm::Block, stored.data(), n, back.data(), 189));
    EXPECT_FALSE(d.decompress(ZstdForm::Frame, stored.data(), n, back.data(), 189));
    EXPECT_FALSE(d.decompress(form, stored.data(), n, back.data(), 188) && back == src);
    EXPECT_FALSE(d.decompress(form, stored.data(), n - 1, back.data(), 189) && back == src);
    ZstdDecompressor none;
    EXPECT_FALSE(none.decompress(form, stored.data(), n, back.data(), 189));
    EXPECT_FALSE(d.decompress(ZstdForm(7), stored.data(), n, back.data(), 189));
    // Literals longer than 10-bit sizes allow cannot have been written that way.
    std::vector<uint8_t> big(2000, 1), bigOut(2000);
    EXPECT_FALSE(d.decompress(ZstdForm::Literals, big.data(), big.size(), bigOut.data(), bigOut.size()));
    // Destination too small for the stored form: 0, nothing claimed.
    EXPECT_EQ(c.compressCompact(src.data(), src.size(), stored.data(), 10, form), 0u);
    // Random damage never crashes, and is mostly caught.
    std::mt19937 rng(5);
    int caught = 0;
    for (int i = 0; i < 300; ++i) {
        std::vector<uint8_t> bad(stored.begin(), stored.begin() + std::ptrdiff_t(n));
        bad[rng() % n] ^= uint8_t(1 + rng() % 255);
        if (!d.decompress(form, bad.data(), bad.size(), back.data(), back.size()) || back != src) ++caught;
    }
    EXPECT_EQ(caught, 300);
}

TEST(ZstdCodec, LiteralDictionaryCodesResidualsSmallerThanTrainedOne) {
    const Samples s = residualSamples(3000, 189);
    const auto literal = buildZstdLiteralDictionary(s.bytes.data(), s.sizes.data(), s.sizes.size(), 189, 1);
    const auto trained = trainZstdDictionary(s.bytes.data(), s.sizes.data(), s.sizes.size(), 16384);
    ASSERT_FALSE(literal.empty());
    ASSERT_FALSE(trained.empty());
    EXPECT_LT(literal.size(), 189u + 64u + 1024u);  // content of maxBlockBytes + 64, small tables
    auto total = [&](const std::vector<uint8_t>& bytes, const ZstdTuning& tuning) {
        auto dict = std::make_shared<ZstdDictionary>(bytes.data(), bytes.size(), 1);
        ZstdCompressor c(1, dict);
        c.tune(tuning);
        ZstdDecompressor d(dict);
        size_t sum = 0;
        for (uint32_t i = 50000; i < 50500; ++i) sum += compactRoundTrip(c, d, residualBlock(i, 189), nullptr);
        return sum;
    };
    const size_t withLiteral = total(literal, {-7, 7, true}), withTrained = total(trained, {});
    // Level 1 and the fast level with Huffman literals code residuals to the same size.
    EXPECT_LT(double(total(literal, {1, 7, false})), 1.01 * double(withLiteral));
    // At a fast level zstd stores literals raw unless told otherwise.
    EXPECT_GT(double(total(literal, {-7, 7, false})), 1.5 * double(withLiteral));
    // Order-0 entropy of the blocks, in bytes per block.
    double histogram[256] = {};
    for (uint8_t v : s.bytes) histogram[v] += 1;
    double bits = 0;
    for (double c : histogram)
        if (c > 0) bits -= c * std::log2(c / double(s.bytes.size()));
    const double entropyBytes = bits / 8.0 / double(s.sizes.size());
    // The literal table comes within a few percent of the entropy (Huffman's whole bits and the
    // last byte's padding); zstd's own tables give every byte value a code and lose more.
    EXPECT_LT(double(withLiteral), 0.97 * double(withTrained));
    EXPECT_LT(double(withLiteral) / 500.0, 1.03 * entropyBytes + 1.0) << "entropy " << entropyBytes;
}

TEST(ZstdCodec, LiteralDictionaryStillCodesBytesItHasNoCodeFor) {
    const auto dict = literalDictionary(2000);  // residual values 0..16 only
    ASSERT_TRUE(dict);
    ZstdCompressor c(1, dict);
    ZstdDecompressor d(dict);
    std::vector<uint8_t> src = residualBlock(123, 189);
    src[40] = 200;  // never seen
    src[100] = 255;
    ZstdForm form;
    compactRoundTrip(c, d, src, &form);
    EXPECT_NE(form, ZstdForm::Literals);  // a table of its own, so not the dictionary's
    compactRoundTrip(c, d, structuredBlock(8, 189), &form);
}

TEST(ZstdCodec, LiteralDictionaryNeedsSamples) {
    const Samples s = residualSamples(4, 189);
    EXPECT_TRUE(buildZstdLiteralDictionary(s.bytes.data(), s.sizes.data(), s.sizes.size(), 189, 1).empty());
    const Samples t = residualSamples(100, 189);
    EXPECT_TRUE(buildZstdLiteralDictionary(t.bytes.data(), t.sizes.data(), t.sizes.size(), 0, 1).empty());
    EXPECT_TRUE(buildZstdLiteralDictionary(t.bytes.data(), t.sizes.data(), t.sizes.size(), 1u << 20, 1).empty());
}

}  // namespace
}  // namespace pushpin::cache
