// texture/detail/bot_rans.h: the entropy coder of BOT version 3 pages (texture/BOT_FORMAT.md,
// "Version 3"): a static rANS coder with 11-bit frequencies, one table per context, the contexts
// taken from the magnitudes of the residuals already coded around each sample (LOCO-I and CALIC
// choose their contexts from the local gradient the same way).
// A page is coded by two rANS states, one per half of each channel's grid, so that a decoder can run
// them side by side.
// A RansTableSet is immutable once built and may be read by any number of threads; the page
// functions work on caller-owned buffers and never allocate.
// Memory: a RansTableSet holds RansTableSet::memoryBytes() (a 3 KiB decoding block per context, 14
// contexts a byte of a sample, and 1 KiB per context in use; those built by fit() also 4 KiB per
// context of encoding steps).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture::detail {

constexpr uint32_t kRansScaleBits = 11;                // frequencies sum to 2048
constexpr uint32_t kRansScale = 1u << kRansScaleBits;
// A page is coded by two states. State A lies in [2^24, 2^32) between symbols and is stored in 4
// bytes, state B in [2^16, 2^24), stored in 3. Each begins at its lower bound plus a payload the
// decoder ends with: 47 bits, the page's 15-bit check value and the first prefix bytes (zeros past
// the prefix), A taking the low 24 bits and B the high 23.
constexpr uint32_t kRansLow = 1u << 24;
constexpr uint32_t kRansLowB = 1u << 16;
constexpr uint32_t kRansStateBytes = 4;   // state A
constexpr uint32_t kRansStateBytesB = 3;  // state B
constexpr uint32_t kRansCheckBits = 15;
constexpr uint32_t kRansPayloadBitsA = 24, kRansPayloadBitsB = 23;
// The first bytes of the prefix that ride in the initial states (see ransPrefixInState).
constexpr uint32_t kRansPrefixInStateMax = (kRansPayloadBitsA + kRansPayloadBitsB - kRansCheckBits) / 8;
// One context's decoding block (3 KiB): per symbol its frequency and cumulative frequency, then
// the symbol of each of the kRansScale slots. The two halves of a step are read by two loads that
// need no masking; a context without symbols has cum = kRansUnusedCum (bit 15), which marks any
// page that uses it corrupt.
struct RansDecodeBlock {
    struct Step {
        uint16_t freq, cum;
    };
    Step steps[256];
    uint8_t symbols[kRansScale];
};
constexpr uint16_t kRansUnusedCum = 1u << 15;
// ransCount's contexts carry the state that codes each symbol (0: A, 1: B) in this bit.
constexpr uint32_t kRansStateBit = 7;

// Contexts per byte of a sample: kRansActivityBuckets by the neighbours' residual magnitudes, one
// for the two texels whose only neighbour is texel 0, one for a byte whose sample already has a
// non-zero higher byte.
constexpr uint32_t kRansActivityBuckets = 12;
constexpr uint32_t kRansStartContext = kRansActivityBuckets;
constexpr uint32_t kRansHighContext = kRansActivityBuckets + 1;
constexpr uint32_t kRansContextsPerByte = kRansActivityBuckets + 2;

inline uint32_t ransContextCount(PixelType type) { return kRansContextsPerByte * bytesPerSample(type); }
inline uint32_t ransPrefixInState(uint32_t prefixBytes) {
    return prefixBytes < kRansPrefixInStateMax ? prefixBytes : kRansPrefixInStateMax;
}
// Symbols coded per page: texels 1..63 of every channel, every byte of each sample.
inline uint32_t ransSymbolsPerPage(uint32_t channels, PixelType type) {
    return (kPageSizeTexels * kPageSizeTexels - 1) * channels * bytesPerSample(type);
}

// LEB128 varints, as the version-3 tables store their numbers.
void appendVarint(std::vector<uint8_t>& out, uint32_t v);
// Reads one varint of at most 32 bits from [at, end), advancing `at`; false when it runs past `end`
// or is longer than 5 bytes.
bool readVarint(const uint8_t*& at, const uint8_t* end, uint32_t& v);

// Symbol counts per context, gathered from packed pages (the layout of detail::packPage).
struct RansHistogram {
    // contexts * 256 counts in two lanes of the same size, summed wherever they are used: counting
    // one-byte symbols alternates between them, so that runs of one symbol (the zero residuals of
    // smooth pages) are not one chain of increments of one counter.
    std::vector<uint32_t> counts, lane1;
    explicit RansHistogram(uint32_t contexts = 0)
        : counts(size_t(contexts) * 256, 0), lane1(size_t(contexts) * 256, 0) {}
    uint32_t contexts() const { return uint32_t(counts.size() / 256); }
    // Context c's 256 counts, both lanes summed (in `scratch` when needed).
    const uint32_t* contextCounts(uint32_t c, uint32_t* scratch) const;
    void add(const RansHistogram& other);
    // Bits the counts would take coded with tables fitted to them, plus the tables' stored bytes.
    double codedBits() const;
};
// Adds the symbols of one packed page, each under its context. With `contexts`, also writes each
// symbol's context and state (context | state << kRansStateBit) there, in the order of walking the
// page (ransSymbolsPerPage bytes), for RansTableSet::encode.
void ransCount(const uint8_t* packed, uint32_t channels, PixelType type, RansHistogram& histogram,
               uint8_t* contexts = nullptr);

// The coding tables of one band: per context, 256 frequencies summing to kRansScale (all zero for a
// context that never occurs), with what encoding and decoding need.
class RansTableSet {
public:
    // Tables fitted to `histogram`: every symbol that occurs gets a frequency of at least 1.
    static std::shared_ptr<const RansTableSet> fit(const RansHistogram& histogram);
    // Parses `contexts` tables from bytes [at, end) (the stored form, see serialize), advancing
    // `at` past them. Returns nullptr when they are malformed (frequencies not summing to
    // kRansScale, symbols out of order or past 255, bits missing). Allocates only for tables
    // actually present.
    static std::shared_ptr<const RansTableSet> parse(const uint8_t*& at, const uint8_t* end, uint32_t contexts);
    // Appends the stored form, a stream of Elias gamma codes (floor(log2 v) zero bits, then v's bits
    // from the top; bits fill each byte from its low end; the last byte is padded with zeros): per
    // context, the number of symbols with a non-zero frequency plus one, then for each, in
    // increasing order, the symbol minus the previous one (the first: the symbol plus one) and its
    // frequency.
    void serialize(std::vector<uint8_t>& out) const;

    uint32_t contexts() const { return m_contexts; }
    size_t memoryBytes() const;

    // Codes one packed page into `out` (capacity bytes): the prefix bytes past the first
    // ransPrefixInState of them, the final states A and B (4 and 3 bytes, little-endian), state A's
    // renormalisation bytes in reading order, then state B's in reverse reading order. The low
    // kRansCheckBits of `check` ride in the states and come back out of decode. Returns the bytes written, or 0 when they
    // would not fit in `capacity`. Every symbol of the page must have a frequency in its context
    // (pages counted into the fitted histogram). `contexts`: the page's contexts as ransCount wrote
    // them, which saves finding them again.
    size_t encode(const uint8_t* packed, uint32_t channels, PixelType type, uint16_t check, uint8_t* out,
                  size_t capacity, const uint8_t* contexts = nullptr) const;
    // Inverse of encode: rebuilds the packed page from `bytes` stored bytes and returns the check
    // value encode was given in `check`. Returns false when the bytes are not a valid coding (a
    // state does not end where encode began it, bytes left over or missing, a symbol without
    // frequency). Never reads outside [stored, stored + bytes).
    bool decode(const uint8_t* stored, size_t bytes, uint32_t channels, PixelType type, uint8_t* packed,
                uint16_t& check) const;

    struct Table;  // one context's frequencies and lookup tables (bot_rans.cpp)

private:
    RansTableSet() = default;
    uint32_t m_contexts = 0;
    std::vector<int32_t> m_tableOf;  // per context: index into m_tables, or -1 when unused
    std::vector<Table> m_tables;
    // fit() only: per context and symbol, what a coding step needs (all zero for symbols and
    // contexts without a frequency).
    struct EncodeEntry {
        uint64_t rcp;  // ceil(2^44 / freq)
        uint32_t freq, cum;
    };
    std::vector<EncodeEntry> m_encode;
    // Per context, one decoding block; a context without symbols decodes symbol 0 with the
    // kRansUnusedCum mark.
    std::vector<RansDecodeBlock> m_decode;
    void index();  // fills m_decode
public:
    ~RansTableSet();
    RansTableSet(RansTableSet&&) noexcept;
};

}  // namespace pushpin::texture::detail
