// cache/zstd_codec.h: a small wrapper over zstd for many tiny independent blocks (texture pages, swap
// items): compact frames (no magic number, no dictionary id, no zstd checksum; callers keep their own
// checksums and know each block's decompressed size) and optional trained dictionaries.
// Thread safety: ZstdDictionary is immutable and may be shared by any number of threads; a
// ZstdCompressor or ZstdDecompressor holds a zstd context and belongs to one thread at a time.
// Memory: a context holds a few hundred KB; a dictionary holds its bytes plus zstd's digested
// copies. Nothing here is charged to a MemoryBudget; owners of many contexts should do so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pushpin::cache {

// A trained (or raw-content) zstd dictionary, digested once for compression and decompression.
class ZstdDictionary {
public:
    // Digests `bytes` for `compressionLevel`. Throws pushpin::Error when zstd rejects the buffer.
    ZstdDictionary(const void* bytes, size_t byteCount, int compressionLevel);
    // Digests `bytes` for decompression only (readers: no compression tables, a fraction of the
    // memory). A ZstdCompressor refuses such a dictionary. Throws pushpin::Error like the above.
    ZstdDictionary(const void* bytes, size_t byteCount);
    ~ZstdDictionary();
    ZstdDictionary(const ZstdDictionary&) = delete;
    ZstdDictionary& operator=(const ZstdDictionary&) = delete;

    const std::vector<uint8_t>& bytes() const { return m_bytes; }
    int compressionLevel() const { return m_level; }
    // Heap bytes held: the raw dictionary plus zstd's digested copies for both directions.
    size_t memoryBytes() const;

private:
    friend class ZstdCompressor;
    friend class ZstdDecompressor;
    std::vector<uint8_t> m_bytes;
    int m_level = 0;
    void* m_cdict = nullptr;  // ZSTD_CDict*
    void* m_ddict = nullptr;  // ZSTD_DDict*
};

// Trains a dictionary of at most `capacityBytes` from `count` samples stored back to back in
// `samples` (sample i has sampleBytes[i] bytes). Returns an empty vector when training fails
// (too few or too uniform samples); that is an expected outcome, not an error.
std::vector<uint8_t> trainZstdDictionary(const void* samples, const size_t* sampleBytes, size_t count,
                                         size_t capacityBytes);

// Largest compressed size of `srcBytes` input bytes (for sizing destination buffers).
size_t zstdCompressBound(size_t srcBytes);

class ZstdCompressor {
public:
    // `dictionary` may be null; when given, its compression level is used instead of `level`.
    // Throws std::invalid_argument for a dictionary digested for decompression only.
    explicit ZstdCompressor(int level = 3, std::shared_ptr<const ZstdDictionary> dictionary = nullptr);
    ~ZstdCompressor();
    ZstdCompressor(const ZstdCompressor&) = delete;
    ZstdCompressor& operator=(const ZstdCompressor&) = delete;

    // Compresses src into dst (capacity dstCapacity). Returns the compressed size, or 0 when the
    // result does not fit in dstCapacity or zstd fails. Never throws.
    size_t compress(const void* src, size_t srcBytes, void* dst, size_t dstCapacity);

private:
    void* m_cctx = nullptr;  // ZSTD_CCtx*
    std::shared_ptr<const ZstdDictionary> m_dictionary;
};

class ZstdDecompressor {
public:
    explicit ZstdDecompressor(std::shared_ptr<const ZstdDictionary> dictionary = nullptr);
    ~ZstdDecompressor();
    ZstdDecompressor(const ZstdDecompressor&) = delete;
    ZstdDecompressor& operator=(const ZstdDecompressor&) = delete;

    // Replaces the dictionary used by later calls (null for none).
    void setDictionary(std::shared_ptr<const ZstdDictionary> dictionary);

    // Decompresses one frame made by ZstdCompressor with the same dictionary. Returns true only
    // when the frame is valid and decodes to exactly expectedBytes bytes; corrupt input returns
    // false and never writes past dst + expectedBytes. Never throws.
    bool decompress(const void* src, size_t srcBytes, void* dst, size_t expectedBytes);

private:
    void* m_dctx = nullptr;  // ZSTD_DCtx*
    std::shared_ptr<const ZstdDictionary> m_dictionary;
};

}  // namespace pushpin::cache
