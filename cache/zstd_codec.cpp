#include "cache/zstd_codec.h"

// The compact frame format (no magic number) and the literal compression mode are experimental zstd
// parameters; only their enum values are needed here, every function called is part of the stable
// API.
#define ZSTD_STATIC_LINKING_ONLY
#include <zdict.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include "cache/error.h"

namespace pushpin::cache {

namespace {

ZSTD_CCtx* cctxOf(void* p) { return static_cast<ZSTD_CCtx*>(p); }
ZSTD_DCtx* dctxOf(void* p) { return static_cast<ZSTD_DCtx*>(p); }

void setCompactFrame(ZSTD_CCtx* cctx) {
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_format, ZSTD_f_zstd1_magicless);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 0);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_dictIDFlag, 0);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 1);
}

// RFC 8878 field layouts used to cut headers from compact frames and to rebuild them.
constexpr size_t kBlockHeaderBytes = 3;
constexpr size_t kLiteralsHeaderBytes = 3;  // Size_Format 00: one stream, 10-bit sizes
constexpr size_t kMaxBlockBytes = size_t(1) << 17;  // Block_Maximum_Size
constexpr size_t kMaxLiteralsFormBytes = 1023;      // what 10-bit sizes can express

uint32_t get24(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16; }
void put24(uint8_t* p, uint32_t v) {
    p[0] = uint8_t(v);
    p[1] = uint8_t(v >> 8);
    p[2] = uint8_t(v >> 16);
}

// The frame header compact frames of `content` bytes get: no magic number, Single_Segment, no
// checksum or dictionary id, the content size in the smallest field. Returns its size (2..5).
size_t compactFrameHeader(size_t content, uint8_t* out) {
    if (content < 256) {
        out[0] = 0x20;  // FCS_Field_Size 0 (1 byte with Single_Segment), Single_Segment
        out[1] = uint8_t(content);
        return 2;
    }
    if (content < 65536 + 256) {
        out[0] = 0x60;  // FCS_Field_Size 1: 2 bytes holding content - 256
        out[1] = uint8_t(content - 256);
        out[2] = uint8_t((content - 256) >> 8);
        return 3;
    }
    out[0] = 0xa0;  // FCS_Field_Size 2: 4 bytes
    for (int i = 0; i < 4; ++i) out[1 + i] = uint8_t(uint64_t(content) >> (8 * i));
    return 5;
}

// Block_Header of the last block of a frame, compressed, with a body of `bodyBytes`.
uint32_t compressedBlockHeader(size_t bodyBytes) { return uint32_t(bodyBytes) << 3 | 2u << 1 | 1u; }

// Literals_Section_Header of treeless literals in one stream (Size_Format 00).
uint32_t treelessLiteralsHeader(size_t regenerated, size_t compressed) {
    return 3u | uint32_t(regenerated) << 4 | uint32_t(compressed) << 14;
}

// Bytes of a Huffman_Tree_Description that starts at p (its header byte says), or 0 when it
// does not fit in the `available` bytes.
size_t huffmanDescriptionBytes(const uint8_t* p, size_t available) {
    if (available == 0) return 0;
    const size_t n = p[0] < 128 ? 1 + size_t(p[0]) : 1 + (size_t(p[0]) - 127 + 1) / 2;
    return n <= available ? n : 0;
}

}  // namespace

const char* zstdFormName(ZstdForm form) {
    switch (form) {
        case ZstdForm::Frame: return "frame";
        case ZstdForm::Block: return "block";
        case ZstdForm::Literals: return "literals";
    }
    return "?";
}

size_t zstdFormOverheadBytes(ZstdForm form, size_t contentBytes) {
    uint8_t header[8];
    switch (form) {
        case ZstdForm::Frame: return 0;
        case ZstdForm::Block: return compactFrameHeader(contentBytes, header) + kBlockHeaderBytes;
        case ZstdForm::Literals:
            return compactFrameHeader(contentBytes, header) + kBlockHeaderBytes + kLiteralsHeaderBytes + 1;
    }
    return 0;
}

ZstdDictionary::ZstdDictionary(const void* bytes, size_t byteCount, int compressionLevel)
    : m_bytes(static_cast<const uint8_t*>(bytes), static_cast<const uint8_t*>(bytes) + byteCount),
      m_level(compressionLevel) {
    m_cdict = ZSTD_createCDict(m_bytes.data(), m_bytes.size(), compressionLevel);
    m_ddict = ZSTD_createDDict(m_bytes.data(), m_bytes.size());
    if (!m_cdict || !m_ddict) {
        ZSTD_freeCDict(static_cast<ZSTD_CDict*>(m_cdict));
        ZSTD_freeDDict(static_cast<ZSTD_DDict*>(m_ddict));
        throw Error("zstd rejected a dictionary of " + std::to_string(byteCount) + " bytes");
    }
}

ZstdDictionary::ZstdDictionary(const void* bytes, size_t byteCount)
    : m_bytes(static_cast<const uint8_t*>(bytes), static_cast<const uint8_t*>(bytes) + byteCount) {
    m_ddict = ZSTD_createDDict(m_bytes.data(), m_bytes.size());
    if (!m_ddict) throw Error("zstd rejected a dictionary of " + std::to_string(byteCount) + " bytes");
}

ZstdDictionary::~ZstdDictionary() {
    ZSTD_freeCDict(static_cast<ZSTD_CDict*>(m_cdict));
    ZSTD_freeDDict(static_cast<ZSTD_DDict*>(m_ddict));
}

size_t ZstdDictionary::memoryBytes() const {
    return m_bytes.capacity() + ZSTD_sizeof_CDict(static_cast<const ZSTD_CDict*>(m_cdict)) +
           ZSTD_sizeof_DDict(static_cast<const ZSTD_DDict*>(m_ddict));
}

std::vector<uint8_t> trainZstdDictionary(const void* samples, const size_t* sampleBytes, size_t count,
                                         size_t capacityBytes) {
    // zstd needs a handful of samples and refuses absurdly small capacities.
    if (count < 8 || capacityBytes < 256 || count > 0xffffffffu) return {};
    std::vector<uint8_t> dict(capacityBytes);
    const size_t r = ZDICT_trainFromBuffer(dict.data(), dict.size(), samples, sampleBytes,
                                           static_cast<unsigned>(count));
    if (ZDICT_isError(r)) return {};
    dict.resize(r);
    return dict;
}

std::vector<uint8_t> buildZstdLiteralDictionary(const void* samples, const size_t* sampleBytes, size_t count,
                                                size_t maxBlockBytes, int compressionLevel) {
    if (count < 8 || count > 0xffffffffu || maxBlockBytes == 0 || maxBlockBytes > kMaxBlockBytes) return {};
    size_t total = 0;
    for (size_t i = 0; i < count; ++i) total += sampleBytes[i];
    if (total == 0) return {};

    // zstd's finalizer writes a valid dictionary around our content: sequence tables fitted to the
    // samples, repeat offsets, and a literal table that covers all 256 byte values.
    const std::vector<uint8_t> content(maxBlockBytes + 64, 0xff);
    std::vector<uint8_t> dict(content.size() + 4096);
    ZDICT_params_t params{};
    params.compressionLevel = compressionLevel;
    params.notificationLevel = 0;
    const size_t built = ZDICT_finalizeDictionary(dict.data(), dict.size(), content.data(), content.size(), samples,
                                                  sampleBytes, unsigned(count), params);
    if (ZDICT_isError(built) || built < 8 + content.size() + 12 ||
        std::memcmp(dict.data() + built - content.size(), content.data(), content.size()) != 0)
        return {};
    dict.resize(built);

    // The public API has no call that writes a Huffman table description, but the block
    // compressor writes one for the literals of each block it codes with a fresh table. A block
    // whose bytes have the samples' histogram (shuffled, so that it holds no matches) therefore
    // carries the table we want; byte 255 is added once if missing, because a dictionary's
    // table must reach the last byte value.
    uint64_t histogram[256] = {};
    const uint8_t* bytes = static_cast<const uint8_t*>(samples);
    for (size_t i = 0; i < total; ++i) ++histogram[bytes[i]];
    constexpr double kSyntheticBytes = 60000.0;
    std::vector<uint8_t> synthetic;
    for (int v = 0; v < 256; ++v) {
        if (histogram[v] == 0) continue;
        const size_t n = std::max<size_t>(1, size_t(double(histogram[v]) / double(total) * kSyntheticBytes + 0.5));
        synthetic.insert(synthetic.end(), n, uint8_t(v));
    }
    if (histogram[255] == 0) synthetic.push_back(255);
    uint64_t state = 0x9e3779b97f4a7c15ull;  // fixed seed: the same samples give the same dictionary
    for (size_t i = synthetic.size() - 1; i > 0; --i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        std::swap(synthetic[i], synthetic[size_t((state >> 33) % (i + 1))]);
    }
    std::vector<uint8_t> frame(ZSTD_compressBound(synthetic.size()));
    size_t frameBytes = 0;
    {
        ZSTD_CCtx* cctx = ZSTD_createCCtx();
        if (!cctx) return {};
        setCompactFrame(cctx);
        ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, 1);
        ZSTD_CCtx_setParameter(cctx, ZSTD_c_minMatch, 7);
        frameBytes = ZSTD_compress2(cctx, frame.data(), frame.size(), synthetic.data(), synthetic.size());
        ZSTD_freeCCtx(cctx);
        if (ZSTD_isError(frameBytes)) return {};
    }
    // A compact frame: its header is the one compactFrameHeader() writes.
    uint8_t header[8];
    size_t pos = compactFrameHeader(synthetic.size(), header);
    if (pos + kBlockHeaderBytes + 5 > frameBytes || std::memcmp(frame.data(), header, pos) != 0) return {};
    const uint32_t blockHeader = get24(frame.data() + pos);
    pos += kBlockHeaderBytes;
    const uint8_t literalsType = frame[pos] & 3, sizeFormat = (frame[pos] >> 2) & 3;
    if (((blockHeader >> 1) & 3) != 2 || literalsType != 2) return {};  // need compressed literals with a table
    pos += sizeFormat < 2 ? 3 : sizeFormat == 2 ? 4 : 5;
    const size_t tableBytes = pos < frameBytes ? huffmanDescriptionBytes(frame.data() + pos, frameBytes - pos) : 0;
    const size_t oldTableBytes = huffmanDescriptionBytes(dict.data() + 8, dict.size() - 8);
    if (tableBytes == 0 || oldTableBytes == 0) return {};

    std::vector<uint8_t> out(dict.begin(), dict.begin() + 8);  // magic number and dictionary id
    out.insert(out.end(), frame.begin() + ptrdiff_t(pos), frame.begin() + ptrdiff_t(pos + tableBytes));
    out.insert(out.end(), dict.begin() + ptrdiff_t(8 + oldTableBytes), dict.end());
    // Repeat offsets: three u32 just before the content; each must lie inside the content.
    uint8_t* repeats = out.data() + out.size() - content.size() - 12;
    for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t offset = uint32_t(maxBlockBytes) + 1 + k;
        for (int i = 0; i < 4; ++i) repeats[4 * k + uint32_t(i)] = uint8_t(offset >> (8 * i));
    }
    ZSTD_CDict* cdict = ZSTD_createCDict(out.data(), out.size(), compressionLevel);
    ZSTD_DDict* ddict = ZSTD_createDDict(out.data(), out.size());
    const bool valid = cdict && ddict;
    ZSTD_freeCDict(cdict);
    ZSTD_freeDDict(ddict);
    if (!valid) return {};
    return out;
}

size_t zstdCompressBound(size_t srcBytes) { return ZSTD_compressBound(srcBytes); }

ZstdCompressor::ZstdCompressor(int level, std::shared_ptr<const ZstdDictionary> dictionary)
    : m_dictionary(std::move(dictionary)), m_level(level) {
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    if (!cctx) throw std::bad_alloc();
    m_cctx = cctx;
    setCompactFrame(cctx);
    if (m_dictionary && !m_dictionary->m_cdict) {
        ZSTD_freeCCtx(cctx);
        m_cctx = nullptr;
        throw std::invalid_argument("ZstdCompressor: the dictionary was digested for decompression only");
    }
    if (m_dictionary) {
        ZSTD_CCtx_refCDict(cctx, static_cast<const ZSTD_CDict*>(m_dictionary->m_cdict));
    } else {
        ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
    }
}

ZstdCompressor::~ZstdCompressor() { ZSTD_freeCCtx(cctxOf(m_cctx)); }

size_t ZstdCompressor::compress(const void* src, size_t srcBytes, void* dst, size_t dstCapacity) {
    const size_t r = ZSTD_compress2(cctxOf(m_cctx), dst, dstCapacity, src, srcBytes);
    if (ZSTD_isError(r)) return 0;
    return r;
}

void ZstdCompressor::tune(const ZstdTuning& tuning) {
    ZSTD_CCtx* cctx = cctxOf(m_cctx);
    const int level = tuning.level ? tuning.level : m_dictionary ? m_dictionary->compressionLevel() : m_level;
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_minMatch, tuning.minMatch);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_literalCompressionMode,
                           tuning.huffmanLiterals ? ZSTD_ps_enable : ZSTD_ps_auto);
    // A referenced CDict brings the parameters it was digested with, which would override these;
    // loading the dictionary's bytes instead digests them once more with the context's parameters.
    if (m_dictionary) ZSTD_CCtx_loadDictionary(cctx, m_dictionary->bytes().data(), m_dictionary->bytes().size());
}

size_t ZstdCompressor::compressCompact(const void* src, size_t srcBytes, void* dst, size_t dstCapacity,
                                       ZstdForm& form) {
    if (srcBytes > kMaxBlockBytes) return 0;
    const size_t bound = ZSTD_compressBound(srcBytes);
    if (m_frame.size() < bound) m_frame.resize(bound);
    const size_t r = ZSTD_compress2(cctxOf(m_cctx), m_frame.data(), m_frame.size(), src, srcBytes);
    if (ZSTD_isError(r)) return 0;
    const uint8_t* frame = m_frame.data();
    const uint8_t* stored = frame;
    size_t storedBytes = r;
    form = ZstdForm::Frame;
    // Only a frame whose header is exactly the one decompress() rebuilds, holding one compressed
    // block, loses its headers; anything else (raw or RLE blocks, other header choices of a later
    // zstd) is stored whole.
    uint8_t header[8];
    const size_t headerBytes = compactFrameHeader(srcBytes, header);
    if (r > headerBytes + kBlockHeaderBytes && std::memcmp(frame, header, headerBytes) == 0 &&
        get24(frame + headerBytes) == compressedBlockHeader(r - headerBytes - kBlockHeaderBytes)) {
        const uint8_t* body = frame + headerBytes + kBlockHeaderBytes;
        const size_t bodyBytes = r - headerBytes - kBlockHeaderBytes;
        form = ZstdForm::Block;
        stored = body;
        storedBytes = bodyBytes;
        if (bodyBytes > kLiteralsHeaderBytes + 1 && srcBytes <= kMaxLiteralsFormBytes) {
            const size_t streamBytes = bodyBytes - kLiteralsHeaderBytes - 1;
            if (get24(body) == treelessLiteralsHeader(srcBytes, streamBytes) && body[bodyBytes - 1] == 0) {
                form = ZstdForm::Literals;  // treeless literals, then Number_of_Sequences = 0
                stored = body + kLiteralsHeaderBytes;
                storedBytes = streamBytes;
            }
        }
    }
    if (storedBytes > dstCapacity) return 0;
    std::memcpy(dst, stored, storedBytes);
    return storedBytes;
}

ZstdDecompressor::ZstdDecompressor(std::shared_ptr<const ZstdDictionary> dictionary) {
    ZSTD_DCtx* dctx = ZSTD_createDCtx();
    if (!dctx) throw std::bad_alloc();
    m_dctx = dctx;
    ZSTD_DCtx_setParameter(dctx, ZSTD_d_format, ZSTD_f_zstd1_magicless);
    setDictionary(std::move(dictionary));
}

ZstdDecompressor::~ZstdDecompressor() { ZSTD_freeDCtx(dctxOf(m_dctx)); }

void ZstdDecompressor::setDictionary(std::shared_ptr<const ZstdDictionary> dictionary) {
    m_dictionary = std::move(dictionary);
    ZSTD_DCtx_refDDict(dctxOf(m_dctx),
                       m_dictionary ? static_cast<const ZSTD_DDict*>(m_dictionary->m_ddict) : nullptr);
}

bool ZstdDecompressor::decompress(const void* src, size_t srcBytes, void* dst, size_t expectedBytes) {
    // dst capacity is exactly expectedBytes, so a frame that would decode to more fails inside zstd
    // (dstSize_tooSmall) without writing past the buffer.
    const size_t r = ZSTD_decompressDCtx(dctxOf(m_dctx), dst, expectedBytes, src, srcBytes);
    if (ZSTD_isError(r)) return false;
    return r == expectedBytes;
}

void ZstdDecompressor::reserve(size_t storedBytes) {
    if (m_frame.size() < storedBytes + 16) m_frame.resize(storedBytes + 16);
}

bool ZstdDecompressor::decompress(ZstdForm form, const void* src, size_t srcBytes, void* dst, size_t expectedBytes) {
    if (form == ZstdForm::Frame) return decompress(src, srcBytes, dst, expectedBytes);
    if (form != ZstdForm::Block && form != ZstdForm::Literals) return false;
    if (expectedBytes > kMaxBlockBytes || srcBytes > kMaxBlockBytes) return false;
    if (form == ZstdForm::Literals && (expectedBytes > kMaxLiteralsFormBytes || srcBytes > kMaxLiteralsFormBytes))
        return false;
    const size_t needed = srcBytes + 16;
    if (m_frame.size() < needed) m_frame.resize(std::max(needed, m_frame.size() * 2));
    uint8_t* p = m_frame.data();
    size_t n = compactFrameHeader(expectedBytes, p);
    if (form == ZstdForm::Block) {
        put24(p + n, compressedBlockHeader(srcBytes));
        n += kBlockHeaderBytes;
    } else {
        put24(p + n, compressedBlockHeader(kLiteralsHeaderBytes + srcBytes + 1));
        n += kBlockHeaderBytes;
        put24(p + n, treelessLiteralsHeader(expectedBytes, srcBytes));
        n += kLiteralsHeaderBytes;
    }
    std::memcpy(p + n, src, srcBytes);
    n += srcBytes;
    if (form == ZstdForm::Literals) p[n++] = 0;  // Number_of_Sequences = 0
    return decompress(p, n, dst, expectedBytes);
}

}  // namespace pushpin::cache
