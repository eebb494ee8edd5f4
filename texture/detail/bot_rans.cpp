#include "texture/detail/bot_rans.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "texture/detail/bot_page.h"

namespace pushpin::texture::detail {

// The frequencies of one context, for fitting, storing and encoding. Decoding uses one block per
// context (RansTableSet::m_decode): the symbol of each slot, then that symbol's frequency and
// cumulative frequency, two loads from 3 KiB. A step table with all three per slot takes one load,
// but from 8 KiB a context, 112 KiB for the 14 contexts of a u8 band, which mostly misses the L1
// cache: texture_cache_bench's page read took 1.07 us against 1.01 us this way, and its render-order
// lookups were 0.96 of their speed this way. A search over the cumulative frequencies costs a
// mispredicted branch on most noisy symbols.
struct RansTableSet::Table {
    uint16_t freq[256];
    uint16_t cum[256];
};

RansTableSet::~RansTableSet() = default;
RansTableSet::RansTableSet(RansTableSet&&) noexcept = default;

namespace {

constexpr uint32_t kPageResiduals = kPageSizeTexels * kPageSizeTexels - 1;  // texels 1..63

// min(bit length of v, 9): the magnitude class of a neighbour's residual seen from one byte of a
// sample (9: the neighbour's residual is larger than that byte can hold).
inline uint32_t magnitudeOf(uint32_t v) {
    if (v >= 256) return 9;
    return v == 0 ? 0 : 32 - uint32_t(__builtin_clz(v));
}

// Visits the symbols of a page in coding order (BOT_FORMAT.md "Coding a page"): each channel's 8x8
// grid is two blocks, rows 0-3 coded by state A and rows 4-7 by state B, so that a decoder can run
// the two states side by side. Per channel: texel 32 (B), then for t = 1 .. 31 texel t (A) and
// texel t + 32 (B), byte by byte in turn from the most significant. `planes` points at the packed
// page's first plane (past the prefix); step(context, byte, state) returns the byte (the encoder and
// the counter pass it through, the decoder decodes it) and the walk stores it in its plane.
//
// Context of byte b of a texel: the magnitude classes of its left and upper neighbours' residuals,
// shifted down by 8b bits, added (0..18) and capped at kRansActivityBuckets - 1; in the first row of
// its block (row 0 or 4) and in column 0, where one neighbour is missing, twice the other's. Texels
// 1 and 8, whose only neighbour is texel 0 (stored in the prefix, not predicted), and texel 32, the
// first of its block, have their own context; a byte under a non-zero higher byte of the same
// residual has its own (it is close to uniform). Neighbours never cross from one block to the other.
template <uint32_t kBytes, class Step>
inline void walkPage(uint32_t channels, uint8_t* planes, Step&& step) {
    constexpr uint32_t n = kPageSizeTexels;
    for (uint32_t c = 0; c < channels; ++c) {
        uint32_t z[kPageSizeTexels * kPageSizeTexels];
        z[0] = 0;
        uint8_t* plane = planes + size_t(c) * kBytes * kPageResiduals;
        // Both helpers are inlined: called once a symbol, they are most of the counting pass's time.
        auto context = [&](uint32_t i, uint32_t k, uint32_t v) __attribute__((always_inline)) {
            const uint32_t shift = 8 * (kBytes - 1 - k);
            if (k > 0 && (v >> (shift + 8)) != 0) return kRansHighContext;
            if (i == 1 || i == n || i == 4 * n) return kRansStartContext;
            const uint32_t x = i & (n - 1), y = i / n;
            uint32_t act;
            if (y % 4 == 0) act = 2 * magnitudeOf(z[i - 1] >> shift);
            else if (x == 0) act = 2 * magnitudeOf(z[i - n] >> shift);
            else act = magnitudeOf(z[i - 1] >> shift) + magnitudeOf(z[i - n] >> shift);
            return std::min(act, kRansActivityBuckets - 1);
        };
        auto code = [&](uint32_t i, uint32_t k, uint32_t& v, uint32_t state) __attribute__((always_inline)) {
            const uint32_t b = kBytes - 1 - k;
            uint8_t& byte = plane[b * kPageResiduals + (i - 1)];
            byte = step(b * kRansContextsPerByte + context(i, k, v), byte, state);
            v |= uint32_t(byte) << (8 * b);
        };
        uint32_t head = 0;
        for (uint32_t k = 0; k < kBytes; ++k) code(4 * n, k, head, 1);
        z[4 * n] = head;
        for (uint32_t t = 1; t < 4 * n; ++t) {
            uint32_t a = 0, b = 0;
            for (uint32_t k = 0; k < kBytes; ++k) {
                code(t, k, a, 0);
                code(t + 4 * n, k, b, 1);
            }
            z[t] = a;
            z[t + 4 * n] = b;
        }
    }
}

template <class Step>
inline void walkPageAnyType(PixelType type, uint32_t channels, uint8_t* planes, Step&& step) {
    switch (bytesPerSample(type)) {
        case 1: walkPage<1>(channels, planes, step); break;
        case 2: walkPage<2>(channels, planes, step); break;
        default: walkPage<4>(channels, planes, step); break;
    }
}

// Frequencies summing to kRansScale from counts: each symbol that occurs gets
// max(1, floor(count * scale / total)); the shortfall goes to the most frequent symbol, an excess
// is taken from the largest frequencies. Deterministic. All zero when nothing occurs.
void normalize(const uint32_t* counts, uint16_t* freq) {
    uint64_t total = 0;
    for (int s = 0; s < 256; ++s) total += counts[s];
    std::fill(freq, freq + 256, uint16_t(0));
    if (total == 0) return;
    int64_t sum = 0;
    int top = 0;
    for (int s = 0; s < 256; ++s) {
        if (!counts[s]) continue;
        freq[s] = uint16_t(std::max<uint64_t>(1, uint64_t(counts[s]) * kRansScale / total));
        sum += freq[s];
        if (counts[s] > counts[top]) top = s;
    }
    if (sum < int64_t(kRansScale)) freq[top] = uint16_t(freq[top] + (int64_t(kRansScale) - sum));
    while (sum > int64_t(kRansScale)) {
        int big = 0;
        for (int s = 1; s < 256; ++s)
            if (freq[s] > freq[big]) big = s;
        const int64_t take = std::min<int64_t>(sum - kRansScale, freq[big] - 1);
        freq[big] = uint16_t(freq[big] - take);
        sum -= take;
    }
}

// Tables are stored as Elias gamma codes (a value v >= 1 as floor(log2 v) zero bits, then v's bits
// from the top), bits filled from the low end of each byte: most gaps between symbols are 0 and most
// frequencies small, 1 to 7 bits each instead of a varint's 8.
uint32_t gammaBits(uint32_t v) { return 2 * (31 - uint32_t(__builtin_clz(v))) + 1; }

class BitWriter {
public:
    explicit BitWriter(std::vector<uint8_t>& out) : m_out(out) {}
    void gamma(uint32_t v) {
        const uint32_t top = 31 - uint32_t(__builtin_clz(v));
        for (uint32_t k = 0; k < top; ++k) bit(0);
        for (uint32_t k = top + 1; k-- > 0;) bit((v >> k) & 1);
    }
    void flush() {  // pads the last byte with zero bits
        if (m_count) m_out.push_back(m_byte);
        m_byte = 0;
        m_count = 0;
    }

private:
    void bit(uint32_t b) {
        m_byte = uint8_t(m_byte | b << m_count);
        if (++m_count == 8) flush();
    }
    std::vector<uint8_t>& m_out;
    uint8_t m_byte = 0;
    uint32_t m_count = 0;
};

class BitReader {
public:
    BitReader(const uint8_t* at, const uint8_t* end) : m_at(at), m_end(end) {}
    // False when the bits run out or the code is longer than 32 bits.
    bool gamma(uint32_t& v) {
        uint32_t zeros = 0, b = 0;
        for (;;) {
            if (!bit(b)) return false;
            if (b) break;
            if (++zeros > 31) return false;
        }
        v = 1;
        for (uint32_t k = 0; k < zeros; ++k) {
            if (!bit(b)) return false;
            v = v << 1 | b;
        }
        return true;
    }
    const uint8_t* end() const { return m_count ? m_at + 1 : m_at; }  // past the last byte read

private:
    bool bit(uint32_t& b) {
        if (m_at == m_end) return false;
        b = (*m_at >> m_count) & 1;
        if (++m_count == 8) {
            m_count = 0;
            ++m_at;
        }
        return true;
    }
    const uint8_t* m_at;
    const uint8_t* m_end;
    uint32_t m_count = 0;
};

// Stored bits of one table with these frequencies (serialize's form).
uint32_t storedTableBits(const uint16_t* freq) {
    uint32_t n = 0, bits = 0;
    int prev = -1;
    for (int s = 0; s < 256; ++s) {
        if (!freq[s]) continue;
        ++n;
        bits += gammaBits(uint32_t(s - prev)) + gammaBits(freq[s]);
        prev = s;
    }
    return bits + gammaBits(n + 1);
}

void completeTable(RansTableSet::Table& t);

}  // namespace

void appendVarint(std::vector<uint8_t>& out, uint32_t v) {
    while (v >= 0x80) {
        out.push_back(uint8_t(v | 0x80));
        v >>= 7;
    }
    out.push_back(uint8_t(v));
}

bool readVarint(const uint8_t*& at, const uint8_t* end, uint32_t& v) {
    v = 0;
    for (uint32_t shift = 0; shift < 35; shift += 7) {
        if (at == end) return false;
        const uint8_t b = *at++;
        if (shift == 28 && b > 0x0f) return false;  // more than 32 bits
        v |= uint32_t(b & 0x7f) << shift;
        if (!(b & 0x80)) return true;
    }
    return false;
}

const uint32_t* RansHistogram::contextCounts(uint32_t c, uint32_t* scratch) const {
    const uint32_t* a = counts.data() + size_t(c) * 256;
    const uint32_t* b = lane1.data() + size_t(c) * 256;
    for (uint32_t s = 0; s < 256; ++s) scratch[s] = a[s] + b[s];
    return scratch;
}

void RansHistogram::add(const RansHistogram& other) {
    for (size_t k = 0; k < counts.size(); ++k) counts[k] += other.counts[k] + other.lane1[k];
}

double RansHistogram::codedBits() const {
    double bits = 0;
    uint16_t freq[256];
    uint32_t scratch[256];
    for (uint32_t c = 0; c < contexts(); ++c) {
        const uint32_t* n = contextCounts(c, scratch);
        normalize(n, freq);
        bits += storedTableBits(freq);
        for (int s = 0; s < 256; ++s)
            if (n[s]) bits += double(n[s]) * (kRansScaleBits - std::log2(double(freq[s])));
    }
    return bits;
}

namespace {

// walkPage's contexts for one-byte samples, found without walking: a context depends only on the
// residuals around its texel, all known when counting. Per texel i of a channel, the context is
// min(11, left weight * class(z[i-1]) + up weight * class(z[i-8])), or the start context, with the
// weights of walkPage's rule (2 and 0 in a block's first row, 0 and 2 in column 0, else 1 and 1).
struct OneByteContextRule {
    uint8_t left[kPageTexels], up[kPageTexels];
    bool start[kPageTexels];
    uint8_t bitLength[256];
    OneByteContextRule() {
        for (uint32_t i = 0; i < kPageTexels; ++i) {
            const uint32_t x = i % kPageSizeTexels, y = i / kPageSizeTexels;
            start[i] = i == 1 || i == kPageSizeTexels || i == 4 * kPageSizeTexels;
            left[i] = y % 4 == 0 ? 2 : x == 0 ? 0 : 1;
            up[i] = y % 4 == 0 ? 0 : x == 0 ? 2 : 1;
        }
        for (uint32_t v = 0; v < 256; ++v) bitLength[v] = uint8_t(magnitudeOf(v));
    }
};

// Contexts of texels 1..63 of one channel's residual plane (plane[i - 1] is texel i's), at ctx[i].
inline void oneByteContexts(const OneByteContextRule& rule, const uint8_t* plane, uint8_t* ctx) {
    uint8_t mag[kPageTexels];
    mag[0] = 0;
    for (uint32_t i = 1; i < kPageTexels; ++i) mag[i] = rule.bitLength[plane[i - 1]];
    for (uint32_t i = 1; i < kPageTexels; ++i) {
        const uint32_t l = rule.left[i] * mag[i - 1];
        const uint32_t u = i >= kPageSizeTexels ? rule.up[i] * mag[i - kPageSizeTexels] : 0;
        const uint32_t act = std::min(l + u, kRansActivityBuckets - 1);
        ctx[i] = rule.start[i] ? uint8_t(kRansStartContext) : uint8_t(act);
    }
}

void ransCountOneByte(const uint8_t* planes, uint32_t channels, uint32_t* counts, uint32_t* lane1, uint8_t* contexts) {
    static const OneByteContextRule rule;
    constexpr uint32_t kHalf = 4 * kPageSizeTexels;
    for (uint32_t c = 0; c < channels; ++c) {
        const uint8_t* plane = planes + size_t(c) * kPageResiduals;
        uint8_t ctx[kPageTexels];
        oneByteContexts(rule, plane, ctx);
        // Texels 1..31 count in one lane and 32..63 in the other, the two interleaved.
        constexpr uint32_t kPairs = kHalf - 1;
        for (uint32_t i = 1; i <= kPairs; ++i) {
            ++counts[ctx[i] * 256u + plane[i - 1]];
            ++lane1[ctx[i + kPairs] * 256u + plane[i + kPairs - 1]];
        }
        ++lane1[ctx[kPageTexels - 1] * 256u + plane[kPageTexels - 2]];
        if (!contexts) continue;
        // walkPage's order: texel 32 (state B), then texels t (A) and t + 32 (B) in turn.
        *contexts++ = uint8_t(ctx[kHalf] | 1u << kRansStateBit);
        for (uint32_t t = 1; t < kHalf; ++t) {
            *contexts++ = ctx[t];
            *contexts++ = uint8_t(ctx[t + kHalf] | 1u << kRansStateBit);
        }
    }
}

}  // namespace

void ransCount(const uint8_t* packed, uint32_t channels, PixelType type, RansHistogram& histogram,
               uint8_t* contexts) {
    if (bytesPerSample(type) == 1) {
        ransCountOneByte(packed + pagePrefixBytes(channels, type), channels, histogram.counts.data(),
                         histogram.lane1.data(), contexts);
        return;
    }
    // walkPage stores each byte back into its plane; counting passes a copy.
    thread_local std::array<uint8_t, size_t(kPageSizeTexels) * kPageSizeTexels * kMaxChannels * 4> copy;
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t raw = pageRawBytes(channels, type);
    std::memcpy(copy.data(), packed + prefix, raw - prefix);
    uint32_t* counts = histogram.counts.data();
    if (!contexts) {
        walkPageAnyType(type, channels, copy.data(), [counts](uint32_t ctx, uint8_t byte, uint32_t) {
            ++counts[ctx * 256 + byte];
            return byte;
        });
        return;
    }
    walkPageAnyType(type, channels, copy.data(), [counts, &contexts](uint32_t ctx, uint8_t byte, uint32_t state) {
        ++counts[ctx * 256 + byte];
        *contexts++ = uint8_t(ctx | state << kRansStateBit);
        return byte;
    });
}

namespace {

void completeTable(RansTableSet::Table& t) {
    uint32_t cum = 0;
    for (int s = 0; s < 256; ++s) {
        t.cum[s] = uint16_t(cum);
        cum += t.freq[s];
    }
}

}  // namespace

void RansTableSet::index() {
    m_decode.assign(m_contexts, RansDecodeBlock{});
    for (uint32_t c = 0; c < m_contexts; ++c) {
        RansDecodeBlock& block = m_decode[c];
        if (m_tableOf[c] < 0) {
            // Every slot decodes symbol 0, whose mark makes the page corrupt (its frequency, 2048,
            // keeps the state's arithmetic in range meanwhile).
            block.steps[0] = {uint16_t(kRansScale), kRansUnusedCum};
            continue;
        }
        const Table& t = m_tables[size_t(m_tableOf[c])];
        for (uint32_t s = 0; s < 256; ++s) {
            std::memset(block.symbols + t.cum[s], int(s), t.freq[s]);
            block.steps[s] = {t.freq[s], t.cum[s]};
        }
    }
}

std::shared_ptr<const RansTableSet> RansTableSet::fit(const RansHistogram& histogram) {
    std::shared_ptr<RansTableSet> set(new RansTableSet());
    set->m_contexts = histogram.contexts();
    set->m_tableOf.assign(set->m_contexts, -1);
    uint32_t scratch[256];
    for (uint32_t c = 0; c < set->m_contexts; ++c) {
        Table t{};
        normalize(histogram.contextCounts(c, scratch), t.freq);
        if (t.freq[0] == 0 && std::all_of(t.freq, t.freq + 256, [](uint16_t f) { return f == 0; })) continue;
        completeTable(t);
        set->m_tableOf[c] = int32_t(set->m_tables.size());
        set->m_tables.push_back(t);
    }
    // Every context gets 256 entries, an unused one all zero frequencies, so that encode indexes
    // them by context and symbol alone.
    set->m_encode.assign(size_t(set->m_contexts) * 256, EncodeEntry{});
    for (uint32_t c = 0; c < set->m_contexts; ++c) {
        if (set->m_tableOf[c] < 0) continue;
        const Table& t = set->m_tables[size_t(set->m_tableOf[c])];
        for (int k = 0; k < 256; ++k) {
            if (!t.freq[k]) continue;
            // ceil(2^44 / freq), so that x / freq is (x * rcp) >> 44 exactly for every 32-bit x and
            // freq <= 2^11 (the error x * (rcp - 2^44/freq) / 2^44 stays below 2^-12 < 1/freq).
            set->m_encode[size_t(c) * 256 + size_t(k)] = {((uint64_t(1) << 44) + t.freq[k] - 1) / t.freq[k],
                                                          t.freq[k], t.cum[k]};
        }
    }
    set->index();
    return set;
}

std::shared_ptr<const RansTableSet> RansTableSet::parse(const uint8_t*& at, const uint8_t* end, uint32_t contexts) {
    std::shared_ptr<RansTableSet> set(new RansTableSet());
    set->m_contexts = contexts;
    set->m_tableOf.assign(contexts, -1);
    BitReader bits(at, end);
    for (uint32_t c = 0; c < contexts; ++c) {
        uint32_t n = 0;
        if (!bits.gamma(n) || n > 257) return nullptr;
        if (--n == 0) continue;
        Table t{};
        uint32_t sum = 0;
        int prev = -1;
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t step = 0, f = 0;
            if (!bits.gamma(step) || !bits.gamma(f)) return nullptr;
            if (step > 256 || prev + int(step) > 255 || f > kRansScale) return nullptr;
            prev += int(step);
            t.freq[prev] = uint16_t(f);
            sum += f;
            if (sum > kRansScale) return nullptr;
        }
        if (sum != kRansScale) return nullptr;
        completeTable(t);
        set->m_tableOf[c] = int32_t(set->m_tables.size());
        set->m_tables.push_back(t);
    }
    at = bits.end();
    set->index();
    return set;
}

void RansTableSet::serialize(std::vector<uint8_t>& out) const {
    BitWriter bits(out);
    for (uint32_t c = 0; c < m_contexts; ++c) {
        if (m_tableOf[c] < 0) {
            bits.gamma(1);
            continue;
        }
        const Table& t = m_tables[size_t(m_tableOf[c])];
        uint32_t n = 0;
        for (int s = 0; s < 256; ++s) n += t.freq[s] != 0;
        bits.gamma(n + 1);
        int prev = -1;
        for (int s = 0; s < 256; ++s) {
            if (!t.freq[s]) continue;
            bits.gamma(uint32_t(s - prev));
            bits.gamma(t.freq[s]);
            prev = s;
        }
    }
    bits.flush();
}

size_t RansTableSet::memoryBytes() const {
    return sizeof(RansTableSet) + m_tableOf.capacity() * sizeof(int32_t) + m_tables.capacity() * sizeof(Table) +
           m_encode.capacity() * sizeof(EncodeEntry) + m_decode.capacity() * sizeof(RansDecodeBlock);
}

namespace {

// What the two states carry from the encoder's start to the decoder's end (bot_rans.h): the check
// value, then the first prefix bytes, as one 47-bit number.
struct StatePayload {
    uint64_t bits;
    StatePayload(uint16_t check, const uint8_t* prefix, uint32_t inState) {
        bits = check & ((1u << kRansCheckBits) - 1);
        for (uint32_t j = 0; j < inState; ++j) bits |= uint64_t(prefix[j]) << (kRansCheckBits + 8 * j);
    }
    uint32_t stateA() const { return kRansLow | uint32_t(bits & ((1u << kRansPayloadBitsA) - 1)); }
    uint32_t stateB() const { return kRansLowB + uint32_t(bits >> kRansPayloadBitsA); }
};

inline void put32le(uint8_t* p, uint32_t v) {
    for (uint32_t j = 0; j < 4; ++j) p[j] = uint8_t(v >> (8 * j));
}
inline uint32_t get32le(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

size_t RansTableSet::encode(const uint8_t* packed, uint32_t channels, PixelType type, uint16_t check, uint8_t* out,
                            size_t capacity, const uint8_t* knownContexts) const {
    if (m_encode.empty()) return 0;  // tables that were parsed, not fitted
    constexpr size_t kMaxSymbols = size_t(kPageResiduals) * kMaxChannels * 4;
    // Each state's symbols and contexts in coding order (state B has one texel more per channel).
    thread_local std::array<uint8_t, kMaxSymbols> planes, symbolsA, contextsA, symbolsB, contextsB;
    // Renormalisation emits at most two bytes a symbol (11 bits of frequency precision), per state.
    thread_local std::array<uint8_t, 2 * kMaxSymbols + 8> emittedA, emittedB;
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t raw = pageRawBytes(channels, type);
    constexpr uint8_t kContextMask = (1u << kRansStateBit) - 1;
    // Contexts come from the symbols before each one, so they are found front to back; rANS codes
    // back to front so that the decoder reads front to back.
    size_t nA = 0, nB = 0;
    if (knownContexts) {
        // The symbols in walkPage's order, without finding their contexts again: per channel,
        // texel 32 (B), then texels t (A) and t + 32 (B) byte by byte in turn.
        const uint32_t bytes = bytesPerSample(type);
        const uint8_t* ctx = knownContexts;
        for (uint32_t c = 0; c < channels; ++c) {
            const uint8_t* plane = packed + prefix + size_t(c) * bytes * kPageResiduals;
            auto residualByte = [&](uint32_t texel, uint32_t k) {
                return plane[(bytes - 1 - k) * kPageResiduals + texel - 1];
            };
            for (uint32_t k = 0; k < bytes; ++k) {
                symbolsB[nB] = residualByte(4 * kPageSizeTexels, k);
                contextsB[nB++] = *ctx++ & kContextMask;
            }
            for (uint32_t t = 1; t < 4 * kPageSizeTexels; ++t)
                for (uint32_t k = 0; k < bytes; ++k) {
                    symbolsA[nA] = residualByte(t, k);
                    contextsA[nA++] = *ctx++ & kContextMask;
                    symbolsB[nB] = residualByte(t + 4 * kPageSizeTexels, k);
                    contextsB[nB++] = *ctx++ & kContextMask;
                }
        }
    } else {
        std::memcpy(planes.data(), packed + prefix, raw - prefix);
        walkPageAnyType(type, channels, planes.data(), [&](uint32_t ctx, uint8_t byte, uint32_t state) {
            if (state == 0) {
                symbolsA[nA] = byte;
                contextsA[nA++] = uint8_t(ctx);
            } else {
                symbolsB[nB] = byte;
                contextsB[nB++] = uint8_t(ctx);
            }
            return byte;
        });
    }
    // The check value and the first prefix bytes ride in the initial states: the decoder ends in
    // them and reads them back.
    const uint32_t inState = ransPrefixInState(prefix);
    const StatePayload payload(check, packed, inState);
    // The two states are independent: both are kept in registers and stepped in the same loop, so
    // that one's multiply overlaps the other's. State A's bytes are read front to back from the
    // start of the stream, state B's back to front from its end: each is emitted last byte first,
    // A's into the end of emittedA (so it reads in order there), B's in emission order.
    uint32_t xA = payload.stateA(), xB = payload.stateB();
    uint8_t* const endA = emittedA.data() + emittedA.size();
    uint8_t* pA = endA;
    uint8_t* pB = emittedB.data();
    const EncodeEntry* entries = m_encode.data();
    // x / freq by the reciprocal, then the rANS step C(s, x) = (x / f) * scale + x % f + cum.
    auto step = [](uint32_t x, const EncodeEntry& e) __attribute__((always_inline)) {
        const uint32_t q = uint32_t((static_cast<unsigned __int128>(x) * e.rcp) >> 44);
        return (q << kRansScaleBits) + (x - q * e.freq) + e.cum;
    };
    // Each codes one symbol after keeping its state below 256 times its lower bound once coded:
    // x < (low / scale) * 256 * f, that is 2^21 f for state A and 2^13 f for state B.
    auto codeA = [&](const EncodeEntry& e) __attribute__((always_inline)) {
        while (xA >= uint64_t(e.freq) << 21) {
            *--pA = uint8_t(xA);
            xA >>= 8;
        }
        xA = step(xA, e);
    };
    auto codeB = [&](const EncodeEntry& e) __attribute__((always_inline)) {
        while (xB >= uint64_t(e.freq) << 13) {
            *pB++ = uint8_t(xB);
            xB >>= 8;
        }
        xB = step(xB, e);
    };
    // Back to front: the pairs, then state B's extra symbols at the start of its list.
    for (size_t k = nA; k-- > 0;) {
        const size_t kB = k + (nB - nA);
        const EncodeEntry& a = entries[size_t(contextsA[k]) * 256 + symbolsA[k]];
        const EncodeEntry& b = entries[size_t(contextsB[kB]) * 256 + symbolsB[kB]];
        if (a.freq == 0 || b.freq == 0) return 0;
        codeA(a);
        codeB(b);
    }
    for (size_t kB = nB - nA; kB-- > 0;) {
        const EncodeEntry& b = entries[size_t(contextsB[kB]) * 256 + symbolsB[kB]];
        if (b.freq == 0) return 0;
        codeB(b);
    }
    const size_t bytesA = size_t(endA - pA), bytesB = size_t(pB - emittedB.data());
    const size_t total = (prefix - inState) + kRansStateBytes + kRansStateBytesB + bytesA + bytesB;
    if (total > capacity) return 0;
    std::memcpy(out, packed + inState, prefix - inState);
    uint8_t* o = out + (prefix - inState);
    put32le(o, xA);
    for (uint32_t j = 0; j < kRansStateBytesB; ++j) o[kRansStateBytes + j] = uint8_t(xB >> (8 * j));
    o += kRansStateBytes + kRansStateBytesB;
    std::memcpy(o, pA, bytesA);
    std::memcpy(o + bytesA, emittedB.data(), bytesB);
    return total;
}

namespace {

// The two states' byte stream of a page, copied between zero bytes so that renormalisation reads
// without a bounds test per symbol. State A reads forward from the start, state B backward from the
// end; a row of texels moves each by at most 2 bytes a symbol, and the decoder checks after each row
// that they have not crossed (the padding is never taken as data: a coding that reaches it is
// refused).
constexpr size_t kStreamPadding = 2 * kPageSizeTexels * 4 + 8;
struct PaddedStream {
    uint8_t bytes[kStreamPadding + size_t(kPageTexels) * kMaxChannels * 4 + kStreamPadding];
};

// One state of the decoder. step() decodes the symbol of slot x mod 2048 in a context's decoding
// block, then renormalises by reading 0, 1 or 2 bytes (after a step the state is at least
// kLow / 2^11, so two always suffice), branch-free: which of the three happens follows the data, and
// a branch on it is mispredicted on most noisy symbols. The chain each symbol waits on is the
// state's: slot, symbol, frequency, multiplication, renormalisation; everything else (the
// cumulative frequency, the bytes to read) is formed beside it.
template <bool kForward, uint32_t kLow>
struct RansLane {
    uint32_t x;
    const uint8_t* p;    // A: the next byte; B: one past it
    uint32_t marks = 0;  // ORed cumulative frequencies: kRansUnusedCum when a context without symbols was used
    inline uint32_t step(const RansDecodeBlock* block) {
        const size_t slot = x & (kRansScale - 1);
        const uint32_t sym = block->symbols[slot];
        const uint32_t freq = block->steps[sym].freq, cum = block->steps[sym].cum;
        marks |= cum;
        uint32_t bias = uint32_t(slot) - cum;
#if defined(__GNUC__)
        // Keeps the compiler from reassociating the sum into two additions after the product.
        asm("" : "+r"(bias));
#endif
        x = freq * (x >> kRansScaleBits) + bias;
        const uint32_t first = kForward ? p[0] : p[-1], second = kForward ? p[1] : p[-2];
#if defined(__x86_64__)
        // The state and position with one and with two bytes read are formed beside the
        // comparisons, and conditional moves pick them: fewer cycles on the chain every symbol
        // waits for than shifts by 8n. (GCC turns the same selections written in C++ into
        // branches, mispredicted on most noisy symbols.)
        const uint32_t one = x << 8 | first, two = x << 16 | (first << 8 | second);
        const uint8_t* p1 = kForward ? p + 1 : p - 1;
        const uint8_t* p2 = kForward ? p + 2 : p - 2;
        uint32_t y = x;
        asm("cmpl %[low], %[x]\n\t"
            "cmovbl %[one], %[y]\n\t"
            "cmovbq %[p1], %[p]\n\t"
            "cmpl %[low2], %[x]\n\t"
            "cmovbl %[two], %[y]\n\t"
            "cmovbq %[p2], %[p]"
            : [y] "+&r"(y), [p] "+&r"(p)
            : [x] "r"(x), [one] "r"(one), [two] "r"(two), [p1] "r"(p1), [p2] "r"(p2), [low] "i"(kLow),
              [low2] "i"(kLow >> 8)
            : "cc");
        x = y;
#else
        const uint32_t n = uint32_t(x < kLow) + uint32_t(x < (kLow >> 8));
        const uint32_t next = first << 8 | second;
        x = x << (8 * n) | next >> (16 - 8 * n);
        p = kForward ? p + n : p - n;
#endif
        return sym;
    }
};

// Bit length of each byte value (0 for 0): the magnitude class of a u8 residual.
constexpr std::array<uint8_t, 256> kByteMagnitude = [] {
    std::array<uint8_t, 256> m{};
    for (uint32_t v = 1; v < 256; ++v) m[v] = uint8_t(32 - __builtin_clz(v));
    return m;
}();

using RansLaneA = RansLane<true, kRansLow>;
using RansLaneB = RansLane<false, kRansLowB>;

// walkPage<1> for decoding: both blocks' rows in step, the magnitude classes of the row above kept
// as they come, and the decoding block of every sum of two classes looked up once a page, so that
// a symbol's context is two loads and an addition from the symbol before.
inline bool decodeU8(RansLaneA& a, RansLaneB& b, const RansDecodeBlock* blocks, uint32_t channels, uint8_t* planes) {
    constexpr uint32_t n = kPageSizeTexels;
    const RansDecodeBlock* byActivity[2 * 9 + 1];
    for (uint32_t k = 0; k < std::size(byActivity); ++k)
        byActivity[k] = blocks + std::min(k, kRansActivityBuckets - 1);
    const RansDecodeBlock* const start = blocks + kRansStartContext;
    const uint8_t* const mag = kByteMagnitude.data();
    for (uint32_t c = 0; c < channels; ++c) {
        uint8_t* top = planes + size_t(c) * kPageResiduals - 1;  // top[i]: texel i's residual
        uint8_t* bottom = top + 4 * n;
        uint32_t upA[n], upB[n];
        uint32_t leftB = mag[bottom[0] = uint8_t(b.step(start))];
        upB[0] = leftB;
        uint32_t leftA = mag[top[1] = uint8_t(a.step(start))];
        upA[1] = leftA;
        leftB = mag[bottom[1] = uint8_t(b.step(byActivity[2 * leftB]))];
        upB[1] = leftB;
        for (uint32_t x = 2; x < n; ++x) {
            leftA = mag[top[x] = uint8_t(a.step(byActivity[2 * leftA]))];
            upA[x] = leftA;
            leftB = mag[bottom[x] = uint8_t(b.step(byActivity[2 * leftB]))];
            upB[x] = leftB;
        }
        if (a.p > b.p) return false;
        for (uint32_t y = 1; y < 4; ++y) {
            uint8_t* rowA = top + y * n;
            uint8_t* rowB = bottom + y * n;
            leftA = mag[rowA[0] = uint8_t(a.step(y == 1 ? start : byActivity[2 * upA[0]]))];
            upA[0] = leftA;
            leftB = mag[rowB[0] = uint8_t(b.step(byActivity[2 * upB[0]]))];
            upB[0] = leftB;
            for (uint32_t x = 1; x < n; ++x) {
                leftA = mag[rowA[x] = uint8_t(a.step(byActivity[leftA + upA[x]]))];
                upA[x] = leftA;
                leftB = mag[rowB[x] = uint8_t(b.step(byActivity[leftB + upB[x]]))];
                upB[x] = leftB;
            }
            if (a.p > b.p) return false;
        }
    }
    return true;
}

}  // namespace

bool RansTableSet::decode(const uint8_t* stored, size_t bytes, uint32_t channels, PixelType type, uint8_t* packed,
                          uint16_t& check) const {
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t inState = ransPrefixInState(prefix);
    const size_t head = (prefix - inState) + kRansStateBytes + kRansStateBytesB;
    if (bytes < head || bytes - head > sizeof(PaddedStream) - 2 * kStreamPadding) return false;
    std::memcpy(packed + inState, stored, prefix - inState);
    const uint8_t* p = stored + (prefix - inState);
    const size_t streamBytes = bytes - head;
    thread_local PaddedStream stream;
    uint8_t* const begin = stream.bytes + kStreamPadding;
    std::memset(stream.bytes, 0, kStreamPadding);
    std::memcpy(begin, p + kRansStateBytes + kRansStateBytesB, streamBytes);
    std::memset(begin + streamBytes, 0, kStreamPadding);
    RansLaneA a{get32le(p), begin};
    RansLaneB b{get32le(p + kRansStateBytes) & 0xffffff, begin + streamBytes};
    const RansDecodeBlock* const blocks = m_decode.data();
    if (type == PixelType::U8) {
        if (!decodeU8(a, b, blocks, channels, packed + prefix)) return false;
    } else {
        uint32_t count = 0;
        bool crossed = false;
        walkPageAnyType(type, channels, packed + prefix, [&](uint32_t ctx, uint8_t, uint32_t state) -> uint8_t {
            const RansDecodeBlock* block = blocks + ctx;
            const uint8_t s = uint8_t(state == 0 ? a.step(block) : b.step(block));
            // Checked once every 8 symbols, well within what the padding covers.
            if ((++count & 7) == 0) crossed |= a.p > b.p;
            return s;
        });
        if (crossed) return false;
    }
    // A valid coding ends exactly where the encoder began, each state at kRansLow plus its payload,
    // with every byte read once.
    if (((a.marks | b.marks) & kRansUnusedCum) || a.p != b.p || (a.x >> 24) != 1 ||
        (b.x - kRansLowB) >> kRansPayloadBitsB != 0)
        return false;
    const uint64_t payload = (a.x & ((1u << kRansPayloadBitsA) - 1)) | uint64_t(b.x - kRansLowB) << kRansPayloadBitsA;
    if (payload >> (kRansCheckBits + 8 * inState) != 0) return false;  // zeros past the prefix
    check = uint16_t(payload & ((1u << kRansCheckBits) - 1));
    for (uint32_t j = 0; j < inState; ++j) packed[j] = uint8_t(payload >> (kRansCheckBits + 8 * j));
    return true;
}

}  // namespace pushpin::texture::detail
