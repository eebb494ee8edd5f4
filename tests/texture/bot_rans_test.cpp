// Tests of texture/detail/bot_rans.h: the version-3 page coder codes every page it was fitted to
// and decodes it exactly, its stored tables round-trip, and malformed tables or coded bytes are
// refused instead of decoded.
#include "texture/detail/bot_rans.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "texture/detail/bot_page.h"

namespace pushpin::texture::detail {
namespace {

// Packed pages of random-walk samples (smooth with occasional jumps), `pages` of them.
std::vector<uint8_t> packedPages(uint32_t pages, uint32_t channels, PixelType type, PageFilter filter, uint32_t seed) {
    std::mt19937 rng(seed);
    const uint32_t raw = pageRawBytes(channels, type), bytes = bytesPerSample(type);
    std::vector<uint8_t> out(size_t(pages) * raw);
    std::vector<uint8_t> samples(raw);
    for (uint32_t p = 0; p < pages; ++p) {
        for (uint32_t c = 0; c < channels; ++c) {
            uint32_t v = rng();
            for (uint32_t t = 0; t < kPageTexels; ++t) {
                if (rng() % 16 == 0) v = rng();
                else v += uint32_t(int(rng() % 5) - 2) * (p % 3 == 0 ? 1u : 1u + p % 200);
                if (p % 7 == 0) v = 12345;  // some constant pages
                const size_t i = size_t(t) * channels + c;
                if (bytes == 1) samples[i] = uint8_t(v);
                else if (bytes == 2) reinterpret_cast<uint16_t*>(samples.data())[i] = uint16_t(v);
                else reinterpret_cast<uint32_t*>(samples.data())[i] = v;
            }
        }
        packPage(samples.data(), channels, type, filter, out.data() + size_t(p) * raw);
    }
    return out;
}

struct Case {
    uint32_t channels;
    PixelType type;
};

TEST(RansTableSet, FittedTablesCodeEveryPageAndStoredTablesDecodeIt) {
    for (const Case c : {Case{1, PixelType::U8}, Case{3, PixelType::U8}, Case{4, PixelType::U16}, Case{2, PixelType::Half},
                         Case{3, PixelType::Float}, Case{64, PixelType::U8}}) {
        const uint32_t pages = 50, raw = pageRawBytes(c.channels, c.type);
        const std::vector<uint8_t> packed = packedPages(pages, c.channels, c.type, PageFilter::Med, c.channels * 7 + raw);
        RansHistogram histogram(ransContextCount(c.type));
        for (uint32_t p = 0; p < pages; ++p) ransCount(packed.data() + size_t(p) * raw, c.channels, c.type, histogram);
        const auto fitted = RansTableSet::fit(histogram);
        std::vector<uint8_t> stored;
        fitted->serialize(stored);
        const uint8_t* at = stored.data();
        const auto parsed = RansTableSet::parse(at, stored.data() + stored.size(), ransContextCount(c.type));
        ASSERT_NE(parsed, nullptr);
        EXPECT_EQ(at, stored.data() + stored.size());
        std::vector<uint8_t> again;
        parsed->serialize(again);
        EXPECT_EQ(again, stored);
        std::vector<uint8_t> coded(2 * raw + 16), back(raw);
        uint64_t total = 0;
        for (uint32_t p = 0; p < pages; ++p) {
            const uint8_t* page = packed.data() + size_t(p) * raw;
            const size_t n = fitted->encode(page, c.channels, c.type, coded.data(), coded.size());
            ASSERT_GT(n, 0u) << "page " << p;
            total += n;
            ASSERT_TRUE(parsed->decode(coded.data(), n, c.channels, c.type, back.data())) << "page " << p;
            ASSERT_EQ(0, std::memcmp(back.data(), page, raw)) << "page " << p << ", " << c.channels << " channels";
            // One byte more or less is not a valid coding.
            EXPECT_FALSE(parsed->decode(coded.data(), n - 1, c.channels, c.type, back.data()));
            coded[n] = 0;
            EXPECT_FALSE(parsed->decode(coded.data(), n + 1, c.channels, c.type, back.data()));
        }
        // The estimate the writer chooses filters by is close to what the coder stores (besides the
        // tables: 4 bytes of final state and the prefix bytes it does not carry a page, and rounding).
        const double estimate = histogram.codedBits() / 8.0;
        const uint32_t prefix = pagePrefixBytes(c.channels, c.type);
        const double perPage = kRansStateBytes + prefix - ransPrefixInState(prefix);
        EXPECT_NEAR(double(total) + double(stored.size()), estimate + perPage * pages, 0.02 * estimate + 2.0 * pages)
            << c.channels << " channels of " << pixelTypeName(c.type);
    }
}

// A symbol that occurs once in a thousand still gets a frequency, and a context that never occurs
// stores one byte.
TEST(RansTableSet, RareSymbolsKeepAFrequencyAndUnusedContextsCostOneByte) {
    RansHistogram histogram(3);
    histogram.counts[0 * 256 + 0] = 100000;
    histogram.counts[0 * 256 + 255] = 1;
    histogram.counts[2 * 256 + 7] = 5;
    const auto set = RansTableSet::fit(histogram);
    std::vector<uint8_t> stored;
    set->serialize(stored);
    // context 0: 2 symbols (0 with 2047, 255 with 1); context 1: none; context 2: symbol 7 alone.
    const std::vector<uint8_t> expected = {2, 0, 0xfe, 0x0f, 0xfe, 0x01, 0, 0, 1, 7, 0xff, 0x0f};
    EXPECT_EQ(stored, expected);
}

TEST(RansTableSet, MalformedTablesAreRefused) {
    auto parses = [](std::vector<uint8_t> bytes, uint32_t contexts) {
        const uint8_t* at = bytes.data();
        return RansTableSet::parse(at, bytes.data() + bytes.size(), contexts) != nullptr;
    };
    EXPECT_TRUE(parses({1, 7, 0xff, 0x0f}, 1));        // symbol 7 with frequency 2048
    EXPECT_FALSE(parses({1, 7, 0xfe, 0x0f}, 1));       // 2047: does not sum to 2048
    EXPECT_FALSE(parses({1, 7, 0xff, 0x1f}, 1));       // 4096: more than 2048
    EXPECT_FALSE(parses({1, 7, 0xff}, 1));             // truncated varint
    EXPECT_FALSE(parses({1, 7, 0xff, 0x0f}, 2));       // second context missing
    EXPECT_FALSE(parses({2, 200, 0, 60, 0}, 1));       // second symbol past 255
    EXPECT_TRUE(parses({2, 0, 0xff, 0x07, 0, 0xff, 0x07}, 1));   // symbols 0 and 1, 1024 each
    EXPECT_FALSE(parses({0xff, 0xff, 0xff, 0xff, 0x7f}, 1));  // more than 256 symbols
    EXPECT_FALSE(parses({1, 0, 0xff, 0xff, 0xff, 0xff, 0x7f}, 1));  // frequency past 32 bits
}

}  // namespace
}  // namespace pushpin::texture::detail
