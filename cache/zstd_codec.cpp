#include "cache/zstd_codec.h"

// The compact frame format (no magic number) is an experimental zstd parameter; only its enum value
// is needed here, every function called is part of the stable API.
#define ZSTD_STATIC_LINKING_ONLY
#include <zdict.h>
#include <zstd.h>

#include <new>
#include <stdexcept>
#include <string>

#include "cache/error.h"

namespace pushpin::cache {

namespace {

ZSTD_CCtx* cctxOf(void* p) { return static_cast<ZSTD_CCtx*>(p); }
ZSTD_DCtx* dctxOf(void* p) { return static_cast<ZSTD_DCtx*>(p); }

}  // namespace

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

size_t zstdCompressBound(size_t srcBytes) { return ZSTD_compressBound(srcBytes); }

static void setCompactFrame(ZSTD_CCtx* cctx) {
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_format, ZSTD_f_zstd1_magicless);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 0);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_dictIDFlag, 0);
    ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 1);
}

ZstdCompressor::ZstdCompressor(int level, std::shared_ptr<const ZstdDictionary> dictionary)
    : m_dictionary(std::move(dictionary)) {
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

}  // namespace pushpin::cache
