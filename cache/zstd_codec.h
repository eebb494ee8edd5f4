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

// Builds a dictionary for blocks that are almost all literals, such as prediction residuals: the
// literal Huffman table is fitted to the byte histogram of the samples, and bytes the samples never
// hold get no code at all (a block that holds one codes its literals with a table of its own).
// zstd's own builders give every one of the 256 byte values a code of at most 11 bits, which costs
// blocks of a few hundred residual bytes several percent. The content is `maxBlockBytes` + 64 bytes
// of 0xff and the repeat offsets point past any block of up to `maxBlockBytes`, so that matches
// come only from real repeats. Returns an empty vector when zstd cannot build it (too few samples);
// that is an expected outcome, not an error.
std::vector<uint8_t> buildZstdLiteralDictionary(const void* samples, const size_t* sampleBytes, size_t count,
                                                size_t maxBlockBytes, int compressionLevel);

// Largest compressed size of `srcBytes` input bytes (for sizing destination buffers).
size_t zstdCompressBound(size_t srcBytes);

// How much of a compact frame a container stores. The headers left out are the RFC 8878 fields whose
// values the container already knows: the content size and the stored size. The decompressor
// rebuilds them, so the stored bytes are always decoded by zstd itself.
enum class ZstdForm : uint8_t {
    Frame = 0,     // the whole compact frame
    Block = 1,     // the body of the frame's single compressed block (frame and block header implied)
    Literals = 2,  // the Huffman stream of a block that holds only literals, in one stream, coded with
                   // the dictionary's table (frame, block, literals section and sequences headers implied)
};
const char* zstdFormName(ZstdForm form);
// Bytes the rebuilt headers of `form` add to `storedBytes` stored bytes of a `contentBytes` frame.
size_t zstdFormOverheadBytes(ZstdForm form, size_t contentBytes);

// Compression parameters beyond the level, for small blocks that are mostly literals (prediction
// residuals), where zstd's match finder costs time and rarely finds anything worth coding.
struct ZstdTuning {
    int level = 0;         // 0: the dictionary's level (or the constructor's); negative: zstd's fast levels
    int minMatch = 0;      // zstd's shortest match, 3..7 (0: the level's own)
    bool huffmanLiterals = false;  // code literals with Huffman even at negative levels, which skip it
};

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
    // Compresses src and stores the smallest form of the frame that ZstdDecompressor can rebuild:
    // writes the stored bytes to dst and their form to `form`. Returns the stored size, or 0 when
    // it does not fit in dstCapacity or zstd fails. srcBytes must be at most 128 KiB (one block).
    // Never throws.
    size_t compressCompact(const void* src, size_t srcBytes, void* dst, size_t dstCapacity, ZstdForm& form);

    // Retunes later calls for small blocks (see ZstdTuning).
    void tune(const ZstdTuning& tuning);

private:
    void* m_cctx = nullptr;  // ZSTD_CCtx*
    std::shared_ptr<const ZstdDictionary> m_dictionary;
    int m_level = 3;
    std::vector<uint8_t> m_frame;  // compressCompact's whole frame before its headers are cut
};

class ZstdDecompressor {
public:
    explicit ZstdDecompressor(std::shared_ptr<const ZstdDictionary> dictionary = nullptr);
    ~ZstdDecompressor();
    ZstdDecompressor(const ZstdDecompressor&) = delete;
    ZstdDecompressor& operator=(const ZstdDecompressor&) = delete;

    // Sizes the buffer that decompress(form, ...) rebuilds frames in for stored blocks of up to
    // `storedBytes`, so that later calls do not allocate.
    void reserve(size_t storedBytes);

    // Replaces the dictionary used by later calls (null for none).
    void setDictionary(std::shared_ptr<const ZstdDictionary> dictionary);

    // Decompresses one frame made by ZstdCompressor with the same dictionary. Returns true only
    // when the frame is valid and decodes to exactly expectedBytes bytes; corrupt input returns
    // false and never writes past dst + expectedBytes. Never throws.
    bool decompress(const void* src, size_t srcBytes, void* dst, size_t expectedBytes);
    // The same for bytes that ZstdCompressor::compressCompact stored in `form`: rebuilds the
    // headers that were left out (copying the stored bytes once) and decompresses. Corrupt input,
    // and stored bytes too long for `form`, return false. Never throws and never allocates after
    // the first call with the largest size.
    bool decompress(ZstdForm form, const void* src, size_t srcBytes, void* dst, size_t expectedBytes);

private:
    void* m_dctx = nullptr;  // ZSTD_DCtx*
    std::vector<uint8_t> m_frame;  // rebuilt frames
    std::shared_ptr<const ZstdDictionary> m_dictionary;
};

}  // namespace pushpin::cache
