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
        std::vector<uint8_t> coded(2 * raw + 16), back(raw), contexts(ransSymbolsPerPage(c.channels, c.type));
        uint64_t total = 0;
        for (uint32_t p = 0; p < pages; ++p) {
            const uint8_t* page = packed.data() + size_t(p) * raw;
            const uint16_t check = uint16_t(p * 977 + 13) & ((1u << kRansCheckBits) - 1);
            const size_t n = fitted->encode(page, c.channels, c.type, check, coded.data(), coded.size());
            ASSERT_GT(n, 0u) << "page " << p;
            total += n;
            // The contexts the counting pass found code the same bytes.
            RansHistogram scratch(ransContextCount(c.type));
            ransCount(page, c.channels, c.type, scratch, contexts.data());
            std::vector<uint8_t> recoded(coded.size());
            ASSERT_EQ(fitted->encode(page, c.channels, c.type, check, recoded.data(), recoded.size(), contexts.data()), n);
            EXPECT_EQ(0, std::memcmp(recoded.data(), coded.data(), n)) << "page " << p;
            uint16_t decodedCheck = 0;
            ASSERT_TRUE(parsed->decode(coded.data(), n, c.channels, c.type, back.data(), decodedCheck)) << "page " << p;
            ASSERT_EQ(0, std::memcmp(back.data(), page, raw)) << "page " << p << ", " << c.channels << " channels";
            EXPECT_EQ(decodedCheck, check);
            // One byte more or less is refused, or decodes to something else than the page with its
            // check value (the reader compares the check with the decoded page).
            auto decodesBack = [&](size_t bytes) {
                return parsed->decode(coded.data(), bytes, c.channels, c.type, back.data(), decodedCheck) &&
                       decodedCheck == check && std::memcmp(back.data(), page, raw) == 0;
            };
            EXPECT_FALSE(decodesBack(n - 1));
            coded[n] = 0;
            EXPECT_FALSE(decodesBack(n + 1));
        }
        // The estimate the writer chooses filters by is close to what the coder stores (besides the
        // tables: 7 bytes of final states and the prefix bytes they do not carry a page, and rounding).
        const double estimate = histogram.codedBits() / 8.0;
        const uint32_t prefix = pagePrefixBytes(c.channels, c.type);
        const double perPage = kRansStateBytes + kRansStateBytesB + prefix - ransPrefixInState(prefix);
        EXPECT_NEAR(double(total) + double(stored.size()), estimate + perPage * pages, 0.02 * estimate + 2.0 * pages)
            << c.channels << " channels of " << pixelTypeName(c.type);
    }
}

// Elias gamma codes as BOT_FORMAT.md describes them (floor(log2 v) zero bits, then v's bits from
// the top), bits filling each byte from its low end.
struct GammaStream {
    std::vector<uint8_t> bytes;
    uint32_t bits = 0;
    void bit(uint32_t b) {
        if (bits % 8 == 0) bytes.push_back(0);
        bytes.back() = uint8_t(bytes.back() | b << (bits % 8));
        ++bits;
    }
    GammaStream& gamma(uint32_t v) {
        const int top = 31 - __builtin_clz(v);
        for (int k = 0; k < top; ++k) bit(0);
        for (int k = top; k >= 0; --k) bit((v >> k) & 1);
        return *this;
    }
};

// A symbol that occurs once in a hundred thousand still gets a frequency, and a context that never
// occurs stores one bit.
TEST(RansTableSet, RareSymbolsKeepAFrequencyAndUnusedContextsCostOneBit) {
    RansHistogram histogram(3);
    histogram.counts[0 * 256 + 0] = 100000;
    histogram.counts[0 * 256 + 255] = 1;
    histogram.counts[2 * 256 + 7] = 5;
    const auto set = RansTableSet::fit(histogram);
    std::vector<uint8_t> stored;
    set->serialize(stored);
    // context 0: 2 symbols, 0 with 2047 and 255 with 1; context 1: none; context 2: 7 alone.
    GammaStream expected;
    expected.gamma(3).gamma(1).gamma(2047).gamma(255).gamma(1);
    expected.gamma(1);
    expected.gamma(2).gamma(8).gamma(2048);
    EXPECT_EQ(stored, expected.bytes);
}

TEST(RansTableSet, MalformedTablesAreRefused) {
    auto parses = [](const GammaStream& g, uint32_t contexts) {
        const uint8_t* at = g.bytes.data();
        const bool ok = RansTableSet::parse(at, g.bytes.data() + g.bytes.size(), contexts) != nullptr;
        if (ok) {
            EXPECT_EQ(at, g.bytes.data() + g.bytes.size());  // used up to the padded byte
        }
        return ok;
    };
    EXPECT_TRUE(parses(GammaStream().gamma(2).gamma(8).gamma(2048), 1));   // symbol 7 with frequency 2048
    EXPECT_FALSE(parses(GammaStream().gamma(2).gamma(8).gamma(2047), 1));  // does not sum to 2048
    EXPECT_FALSE(parses(GammaStream().gamma(2).gamma(8).gamma(4096), 1));  // more than 2048
    EXPECT_FALSE(parses(GammaStream().gamma(2).gamma(8), 1));              // frequency missing
    EXPECT_FALSE(parses(GammaStream().gamma(2).gamma(8).gamma(2048), 2));  // second context missing
    EXPECT_FALSE(parses(GammaStream().gamma(3).gamma(201).gamma(1).gamma(61).gamma(2047), 1));  // past 255
    EXPECT_TRUE(parses(GammaStream().gamma(3).gamma(1).gamma(1024).gamma(1).gamma(1024), 1));   // 0 and 1
    EXPECT_FALSE(parses(GammaStream().gamma(258), 1));                     // more than 256 symbols
    GammaStream longCode;
    for (int k = 0; k < 40; ++k) longCode.bit(0);
    longCode.bit(1);
    EXPECT_FALSE(parses(longCode, 1));  // a code of more than 32 bits
}

}  // namespace
}  // namespace pushpin::texture::detail
