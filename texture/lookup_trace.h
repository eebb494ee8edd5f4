// texture/lookup_trace.h: records the texture lookups of a render to a compact binary file and
// reads it back, so the same stream can be replayed against other cache sizes
// (bench/cache_hits_bench --stream trace FILE).
// File layout (little-endian): "PPTRACE1", u32 version (1), then chunks, each starting with a
// u8 kind:
//   1 texture: u32 id, u32 byteCount, the path's bytes (once per texture, before its lookups)
//   2 batch:   u32 texture id, u8 filter, u8 kernel, u8 overrideWrap, u8 wrapS, u8 wrapT,
//              u32 maxAnisotropy, f32 widthScale, f32 widthOffset, u32 count,
//              count × 6 f32 (s, t, dsdx, dsdy, dtdx, dtdy per lookup)
// Thread safety: LookupTraceWriter::record() may be called from several threads (one lock per
// batch); readLookupTrace() is reentrant.
// Memory: the writer buffers up to 1 MiB; the reader holds the whole trace.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <unordered_set>
#include <vector>

#include "texture/texture_sampler.h"

namespace pushpin::texture {

class LookupTraceWriter {
public:
    // Creates (truncates) the file. Throws IoError naming the path.
    explicit LookupTraceWriter(const std::filesystem::path& path);
    // Closes the file; a failure here is only reported through the warning on stderr.
    ~LookupTraceWriter();
    LookupTraceWriter(const LookupTraceWriter&) = delete;
    LookupTraceWriter& operator=(const LookupTraceWriter&) = delete;

    // Appends one batch (declaring the texture first if this is its first batch). Never throws:
    // after a failed write the writer stops recording and close() reports the error.
    void record(uint32_t textureId, const std::filesystem::path& texturePath,
                const LookupOptions& options, const LookupBatch& batch);
    // Flushes and closes. Throws IoError if any write failed. Idempotent.
    void close();
    uint64_t recordedLookups() const;

private:
    void put(const void* bytes, size_t n);  // caller holds m_mutex
    std::filesystem::path m_path;
    mutable std::mutex m_mutex;
    std::FILE* m_file = nullptr;
    std::vector<uint8_t> m_buffer;
    std::unordered_set<uint32_t> m_declared;
    uint64_t m_lookups = 0;
    int m_errno = 0;
};

// One recorded batch, struct-of-arrays.
struct TraceBatch {
    uint32_t texture = 0;
    LookupOptions options;
    std::vector<float> s, t, dsdx, dsdy, dtdx, dtdy;
    LookupBatch view() const;  // points into this object
};

struct LookupTrace {
    std::vector<std::filesystem::path> textures;  // indexed by recorded texture id
    std::vector<TraceBatch> batches;
    uint64_t lookupCount() const;
};

// Reads a whole trace. Throws IoError if the file cannot be read and FormatError (naming the file
// and byte offset) if it is not a trace, is truncated, or names an undeclared texture.
LookupTrace readLookupTrace(const std::filesystem::path& path);

}  // namespace pushpin::texture
