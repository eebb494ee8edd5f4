#include "core/scene/packed_ints.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <stdexcept>

#include "cache/zstd_codec.h"

namespace pushpin::scene {

namespace {

// A block's first byte: how its numbers are stored after the two header bytes.
constexpr uint8_t kVarints = 0;  // the 7-bit groups themselves
constexpr uint8_t kZstd = 1;     // their byte count (7-bit groups), then a compact zstd frame of them
constexpr int kZstdLevel = 1;
constexpr size_t kProbeNumbers = 256;

std::atomic<uint64_t> g_nextId{1};

uint32_t zigzag(int32_t v) { return (uint32_t(v) << 1) ^ uint32_t(v >> 31); }
int32_t unzigzag(uint32_t u) { return int32_t((u >> 1) ^ (0u - (u & 1u))); }

void putVarint(std::vector<uint8_t>& out, uint64_t v) {
    while (v >= 0x80) {
        out.push_back(uint8_t(v) | 0x80);
        v >>= 7;
    }
    out.push_back(uint8_t(v));
}

// Reads one 7-bit group number at p (below end); false when it runs past end or past 64 bits.
bool getVarint(const uint8_t*& p, const uint8_t* end, uint64_t& v) {
    v = 0;
    for (int shift = 0; shift < 64 && p < end; shift += 7) {
        const uint8_t b = *p++;
        v |= uint64_t(b & 0x7f) << shift;
        if (!(b & 0x80)) return true;
    }
    return false;
}

// Bytes of the 7-bit groups of v.
size_t varintBytes(uint32_t v) { return size_t(std::bit_width(v | 1u) + 6) / 7; }

uint32_t residual(std::span<const int32_t> values, size_t i, size_t stride) {
    const uint32_t predicted = i >= stride ? zigzag(values[i - stride]) : 0u;
    return zigzag(int32_t(zigzag(values[i]) - predicted));
}

// Bytes the 7-bit groups of `values` predicted at `stride` take.
size_t encodedBytes(std::span<const int32_t> values, size_t stride) {
    size_t bytes = 0;
    const size_t head = std::min(stride, values.size());
    for (size_t i = 0; i < head; ++i) bytes += varintBytes(zigzag(int32_t(zigzag(values[i]))));
    for (size_t i = head; i < values.size(); ++i)
        bytes += varintBytes(zigzag(int32_t(zigzag(values[i]) - zigzag(values[i - stride]))));
    return bytes;
}

// The 7-bit groups of `values` predicted at `stride`.
void encodeBlock(std::span<const int32_t> values, size_t stride, std::vector<uint8_t>& out) {
    out.resize(5 * values.size());
    uint8_t* p = out.data();
    for (size_t i = 0; i < values.size(); ++i) {
        uint32_t v = residual(values, i, stride);
        while (v >= 0x80) {
            *p++ = uint8_t(v) | 0x80;
            v >>= 7;
        }
        *p++ = uint8_t(v);
    }
    out.resize(size_t(p - out.data()));
}

bool decodeBlock(const uint8_t* p, const uint8_t* end, size_t stride, size_t count, int32_t* out) {
    for (size_t i = 0; i < count; ++i) {
        uint64_t d = 0;
        if (!getVarint(p, end, d) || d > UINT32_MAX) return false;
        const uint32_t predicted = i >= stride ? zigzag(out[i - stride]) : 0u;
        out[i] = unzigzag(predicted + uint32_t(unzigzag(uint32_t(d))));
    }
    return p == end;
}

struct Maker {
    cache::ZstdCompressor zstd{kZstdLevel};
    std::vector<uint8_t> groups, compressed;
};

struct Reader {
    struct Block {
        uint64_t id = 0;
        size_t index = 0;
        std::array<int32_t, PackedInts::kBlockNumbers> values;
    };
    std::array<Block, PackedInts::kCachedBlocks> blocks;
    size_t next = 0;  // the block replaced next
    cache::ZstdDecompressor zstd;
    std::vector<uint8_t> groups;
};

Maker& maker() {
    thread_local Maker m;
    return m;
}

Reader& reader() {
    thread_local Reader r;
    return r;
}

}  // namespace

PackedInts::PackedInts(std::span<const int32_t> values, size_t strideHint) : m_size(values.size()) {
    if (values.empty()) return;
    m_id = g_nextId.fetch_add(1, std::memory_order_relaxed);
    const size_t hint = strideHint >= 1 && strideHint <= kMaxStride ? strideHint : 1;
    Maker& mk = maker();
    const size_t blocks = (values.size() + kBlockNumbers - 1) / kBlockNumbers;
    m_blockEnds.reserve(blocks);
    for (size_t b = 0; b < blocks; ++b) {
        const std::span<const int32_t> part = values.subspan(b * kBlockNumbers, std::min(kBlockNumbers, values.size() - b * kBlockNumbers));
        // The stride is chosen on the block's first numbers (blocks of one run are alike).
        const std::span<const int32_t> probe = part.first(std::min(part.size(), kProbeNumbers));
        const size_t stride = hint != 1 && encodedBytes(probe, hint) < encodedBytes(probe, 1) ? hint : 1;
        encodeBlock(part, stride, mk.groups);
        mk.compressed.resize(cache::zstdCompressBound(mk.groups.size()));
        const size_t packed = mk.zstd.compress(mk.groups.data(), mk.groups.size(), mk.compressed.data(), mk.compressed.size());
        if (packed > 0 && packed + 5 < mk.groups.size() - mk.groups.size() / 8) {
            m_bytes.push_back(kZstd);
            m_bytes.push_back(uint8_t(stride));
            putVarint(m_bytes, mk.groups.size());
            m_bytes.insert(m_bytes.end(), mk.compressed.begin(), mk.compressed.begin() + std::ptrdiff_t(packed));
        } else {
            m_bytes.push_back(kVarints);
            m_bytes.push_back(uint8_t(stride));
            m_bytes.insert(m_bytes.end(), mk.groups.begin(), mk.groups.end());
        }
        m_blockEnds.push_back(m_bytes.size());
    }
    m_bytes.shrink_to_fit();
}

const int32_t* PackedInts::block(size_t b) const {
    Reader& r = reader();
    for (Reader::Block& held : r.blocks)
        if (held.id == m_id && held.index == b) return held.values.data();
    Reader::Block& slot = r.blocks[r.next];
    r.next = (r.next + 1) % r.blocks.size();
    slot.id = 0;
    const size_t count = std::min(kBlockNumbers, m_size - b * kBlockNumbers);
    const uint8_t* p = m_bytes.data() + (b == 0 ? 0 : m_blockEnds[b - 1]);
    const uint8_t* end = m_bytes.data() + m_blockEnds[b];
    bool ok = end - p >= 2;
    if (ok) {
        const uint8_t how = p[0];
        const size_t stride = p[1];
        p += 2;
        if (how == kZstd) {
            uint64_t groups = 0;
            ok = getVarint(p, end, groups) && groups <= 5 * kBlockNumbers;
            if (ok) {
                r.groups.resize(size_t(groups));
                ok = r.zstd.decompress(p, size_t(end - p), r.groups.data(), r.groups.size()) &&
                     decodeBlock(r.groups.data(), r.groups.data() + r.groups.size(), stride, count, slot.values.data());
            }
        } else {
            ok = how == kVarints && decodeBlock(p, end, stride, count, slot.values.data());
        }
    }
    if (!ok) throw std::logic_error("PackedInts: a block does not decode");
    slot.id = m_id;
    slot.index = b;
    return slot.values.data();
}

void PackedInts::read(size_t first, size_t n, int32_t* out) const {
    if (first > m_size || n > m_size - first) throw std::out_of_range("PackedInts::read past the end");
    while (n > 0) {
        const size_t b = first / kBlockNumbers, at = first % kBlockNumbers;
        const size_t take = std::min(n, kBlockNumbers - at);
        std::memcpy(out, block(b) + at, take * sizeof(int32_t));
        out += take;
        first += take;
        n -= take;
    }
}

}  // namespace pushpin::scene
