#include "texture/detail/bot_rans.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "texture/detail/bot_page.h"

namespace pushpin::texture::detail {

// Decoding looks everything a step needs up by the slot, in one load: a search over the cumulative
// frequencies, even one that starts near the answer, costs a mispredicted branch on most noisy
// symbols (pages decoded 1.4 times slower), and a symbol table followed by frequency tables puts two
// dependent loads on the chain every symbol waits for (1.1 times slower). 9 KiB a table.
struct RansTableSet::Table {
    uint16_t freq[256];
    uint16_t cum[256];
    // Per slot: frequency (bits 0-11) | slot - cumulative frequency (bits 12-22) | symbol (24-31).
    uint32_t step[kRansScale];
    uint8_t unused;  // 1 in the table of contexts a band has no symbols for
};

namespace {
// What a context without symbols decodes with: any use of it marks the page corrupt.
const RansTableSet::Table& unusedTable() {
    static const RansTableSet::Table t = [] {
        RansTableSet::Table u{};
        u.unused = 1;
        return u;
    }();
    return t;
}
}  // namespace

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

// Visits the symbols of a page in coding order: channel by channel, texel 1 to 63 in raster order,
// the bytes of a sample from the most significant down. `planes` points at the packed page's first
// plane (past the prefix); step(context, byte) returns the byte (the encoder and the counter pass
// it through, the decoder decodes it) and the walk stores it in its plane.
//
// Context of byte b of texel (x, y): the magnitude classes of the left and upper texels' residuals
// shifted down by 8b bits, added (0..18) and capped at kRansActivityBuckets - 1; in row 0 and
// column 0, where one neighbour is missing, twice the other's; texels 1 and 8, whose only neighbour
// is texel 0 (stored in the prefix, not predicted), have their own context; and a byte under a
// non-zero higher byte of the same residual has its own (it is close to uniform).
template <uint32_t kBytes, class Step>
inline void walkPage(uint32_t channels, uint8_t* planes, Step&& step) {
    for (uint32_t c = 0; c < channels; ++c) {
        uint32_t z[kPageSizeTexels * kPageSizeTexels];
        z[0] = 0;
        uint8_t* plane = planes + size_t(c) * kBytes * kPageResiduals;
        for (uint32_t i = 1; i <= kPageResiduals; ++i) {
            const uint32_t x = i & 7, y = i >> 3;
            uint32_t v = 0;
            for (uint32_t k = 0; k < kBytes; ++k) {
                const uint32_t b = kBytes - 1 - k;
                const uint32_t shift = 8 * b;
                uint32_t ctx;
                if (k > 0 && (v >> (shift + 8)) != 0) {
                    ctx = kRansHighContext;
                } else if (i == 1 || i == kPageSizeTexels) {
                    ctx = kRansStartContext;
                } else {
                    uint32_t act;
                    if (y == 0) act = 2 * magnitudeOf(z[i - 1] >> shift);
                    else if (x == 0) act = 2 * magnitudeOf(z[i - kPageSizeTexels] >> shift);
                    else act = magnitudeOf(z[i - 1] >> shift) + magnitudeOf(z[i - kPageSizeTexels] >> shift);
                    ctx = std::min(act, kRansActivityBuckets - 1);
                }
                uint8_t& byte = plane[b * kPageResiduals + (i - 1)];
                byte = step(b * kRansContextsPerByte + ctx, byte);
                v |= uint32_t(byte) << shift;
            }
            z[i] = v;
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

void RansHistogram::add(const RansHistogram& other) {
    for (size_t k = 0; k < counts.size(); ++k) counts[k] += other.counts[k];
}

double RansHistogram::codedBits() const {
    double bits = 0;
    uint16_t freq[256];
    for (size_t c = 0; c + 256 <= counts.size(); c += 256) {
        normalize(counts.data() + c, freq);
        bits += storedTableBits(freq);
        for (int s = 0; s < 256; ++s)
            if (counts[c + s]) bits += double(counts[c + s]) * (kRansScaleBits - std::log2(double(freq[s])));
    }
    return bits;
}

void ransCount(const uint8_t* packed, uint32_t channels, PixelType type, RansHistogram& histogram,
               uint8_t* contexts) {
    // walkPage stores each byte back into its plane; counting passes a copy.
    thread_local std::array<uint8_t, size_t(kPageSizeTexels) * kPageSizeTexels * kMaxChannels * 4> copy;
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t raw = pageRawBytes(channels, type);
    std::memcpy(copy.data(), packed + prefix, raw - prefix);
    uint32_t* counts = histogram.counts.data();
    if (!contexts) {
        walkPageAnyType(type, channels, copy.data(), [counts](uint32_t ctx, uint8_t byte) {
            ++counts[ctx * 256 + byte];
            return byte;
        });
        return;
    }
    walkPageAnyType(type, channels, copy.data(), [counts, &contexts](uint32_t ctx, uint8_t byte) {
        ++counts[ctx * 256 + byte];
        *contexts++ = uint8_t(ctx);
        return byte;
    });
}

namespace {

void completeTable(RansTableSet::Table& t) {
    uint32_t cum = 0;
    for (int s = 0; s < 256; ++s) {
        t.cum[s] = uint16_t(cum);
        for (uint32_t k = 0; k < t.freq[s]; ++k) t.step[cum + k] = t.freq[s] | k << 12 | uint32_t(s) << 24;
        cum += t.freq[s];
    }
}

}  // namespace

void RansTableSet::index() {
    m_decodeTables.assign(m_contexts, &unusedTable());
    for (uint32_t c = 0; c < m_contexts; ++c)
        if (m_tableOf[c] >= 0) m_decodeTables[c] = &m_tables[size_t(m_tableOf[c])];
}

std::shared_ptr<const RansTableSet> RansTableSet::fit(const RansHistogram& histogram) {
    std::shared_ptr<RansTableSet> set(new RansTableSet());
    set->m_contexts = uint32_t(histogram.counts.size() / 256);
    set->m_tableOf.assign(set->m_contexts, -1);
    for (uint32_t c = 0; c < set->m_contexts; ++c) {
        Table t{};
        normalize(histogram.counts.data() + size_t(c) * 256, t.freq);
        if (t.freq[0] == 0 && std::all_of(t.freq, t.freq + 256, [](uint16_t f) { return f == 0; })) continue;
        completeTable(t);
        set->m_tableOf[c] = int32_t(set->m_tables.size());
        set->m_tables.push_back(t);
        // ceil(2^44 / freq), so that x / freq is (x * rcp) >> 44 exactly for every 32-bit x and
        // freq <= 2^11 (the error x * (rcp - 2^44/freq) / 2^44 stays below 2^-12 < 1/freq).
        for (int k = 0; k < 256; ++k)
            set->m_reciprocals.push_back(t.freq[k] ? ((uint64_t(1) << 44) + t.freq[k] - 1) / t.freq[k] : 0);
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
           m_reciprocals.capacity() * sizeof(uint64_t) + m_decodeTables.capacity() * sizeof(const Table*);
}

size_t RansTableSet::encode(const uint8_t* packed, uint32_t channels, PixelType type, uint8_t* out,
                            size_t capacity, const uint8_t* knownContexts) const {
    constexpr size_t kMaxSymbols = size_t(kPageResiduals) * kMaxChannels * 4;
    thread_local std::array<uint8_t, kMaxSymbols> planes, contexts, symbols;
    // Renormalisation emits at most two bytes a symbol (12 bits of frequency precision).
    thread_local std::array<uint8_t, 2 * kMaxSymbols + 8> emitted;
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t raw = pageRawBytes(channels, type);
    // Contexts come from the symbols before each one, so they are found front to back; rANS codes
    // back to front so that the decoder reads front to back.
    size_t n = 0;
    const uint8_t* ctxOf = contexts.data();
    if (knownContexts) {
        // The symbols in coding order: channel, texel, bytes from the most significant down.
        const uint32_t bytes = bytesPerSample(type);
        const uint8_t* p = packed + prefix;
        if (bytes == 1) {
            n = raw - prefix;
            std::memcpy(symbols.data(), p, n);
        } else {
            for (uint32_t c = 0; c < channels; ++c)
                for (uint32_t i = 0; i < kPageResiduals; ++i)
                    for (uint32_t b = bytes; b-- > 0;) symbols[n++] = p[(c * bytes + b) * kPageResiduals + i];
        }
        ctxOf = knownContexts;
    } else {
        std::memcpy(planes.data(), packed + prefix, raw - prefix);
        walkPageAnyType(type, channels, planes.data(), [&](uint32_t ctx, uint8_t byte) {
            contexts[n] = uint8_t(ctx);
            symbols[n] = byte;
            ++n;
            return byte;
        });
    }
    // The first prefix bytes ride in the initial state: the decoder ends in that state and reads them
    // back, so they cost nothing beyond the 4 bytes every page's final state takes.
    const uint32_t inState = ransPrefixInState(prefix);
    uint32_t x = kRansLow;
    for (uint32_t j = 0; j < inState; ++j) x |= uint32_t(packed[j]) << (8 * j);
    uint8_t* const end = emitted.data() + emitted.size();
    uint8_t* p = end;
    for (size_t i = n; i-- > 0;) {
        const int32_t ti = m_tableOf[ctxOf[i]];
        if (ti < 0) return 0;
        const Table& t = m_tables[size_t(ti)];
        const uint32_t s = symbols[i], f = t.freq[s];
        if (f == 0) return 0;
        // Keep the state below 2^32 after coding: x < (kRansLow / scale) * 256 * f.
        const uint64_t xMax = uint64_t(kRansLow >> kRansScaleBits << 8) * f;
        while (x >= xMax) {
            *--p = uint8_t(x);
            x >>= 8;
        }
        const uint64_t rcp = m_reciprocals[size_t(ti) * 256 + s];
        const uint32_t q = uint32_t((static_cast<unsigned __int128>(x) * rcp) >> 44);
        x = (q << kRansScaleBits) + (x - q * f) + t.cum[s];
    }
    const size_t emittedBytes = size_t(end - p);
    const size_t total = (prefix - inState) + kRansStateBytes + emittedBytes;
    if (total > capacity) return 0;
    std::memcpy(out, packed + inState, prefix - inState);
    uint8_t* o = out + (prefix - inState);
    for (uint32_t j = 0; j < 4; ++j) o[j] = uint8_t(x >> (8 * j));
    std::memcpy(o + kRansStateBytes, p, emittedBytes);
    return total;
}

bool RansTableSet::decode(const uint8_t* stored, size_t bytes, uint32_t channels, PixelType type,
                          uint8_t* packed) const {
    const uint32_t prefix = pagePrefixBytes(channels, type);
    const uint32_t inState = ransPrefixInState(prefix);
    if (bytes < (prefix - inState) + kRansStateBytes) return false;
    std::memcpy(packed + inState, stored, prefix - inState);
    const uint8_t* p = stored + (prefix - inState);
    const uint8_t* const end = stored + bytes;
    uint32_t x = uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
    p += kRansStateBytes;
    uint32_t bad = 0;
    const Table* const* tableOf = m_decodeTables.data();
    walkPageAnyType(type, channels, packed + prefix, [&](uint32_t ctx, uint8_t) -> uint8_t {
        const Table& t = *tableOf[ctx];
        bad |= t.unused;
        const uint32_t step = t.step[x & (kRansScale - 1)];
        x = (step & 0xfff) * (x >> kRansScaleBits) + ((step >> 12) & 0x7ff);
        while (x < kRansLow && p < end) x = x << 8 | *p++;
        return uint8_t(step >> 24);
    });
    // A valid coding ends exactly where the encoder began: kRansLow plus the prefix bytes it carried.
    if (bad || p != end || (x >> 24) != 1 || ((x & 0xffffffu) >> (8 * inState)) != 0) return false;
    for (uint32_t j = 0; j < inState; ++j) packed[j] = uint8_t(x >> (8 * j));
    return true;
}

}  // namespace pushpin::texture::detail
