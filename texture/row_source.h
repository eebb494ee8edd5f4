// texture/row_source.h: a source image read top to bottom in bands of rows, as float, for
// conversions that stream (makebot). Two readers sit behind one interface:
//  - WebP stills are decoded by libwebp's incremental decoder while the file is fed to it a slice
//    at a time, and the decoded rows are handed out and dropped as the decoder finishes them, so a
//    4096x4096 WebP is never resident whole (OpenImageIO 2.4's reader decodes the whole image
//    into RGBA on the first scanline read, 64 MiB at that size);
//  - every other image, animated WebP included, goes through OpenImageIO a band at a time
//    (texture/oiio_row_source.h, kept apart so that a program reading only WebP need not load
//    OpenImageIO and the libraries it brings: with Debian 12's OpenImageIO 2.4, about 130 MB and
//    0.18 s at start).
// Both hand out the values OpenImageIO's float read would: 8-bit values times 1/255, and a WebP
// with alpha premultiplied in 8 bits as (c * a + 127) / 255 first, which is what OpenImageIO does.
// Errors: IoError when the file cannot be opened or read, FormatError (naming the file and the
// rows) when it is not an image, is truncated or is damaged.
// Thread safety: one RowSource is read by one thread at a time.
// Memory: the WebP reader holds the file's bytes, libwebp's per-row state and the
// decoded rows not yet handed out (a slice's worth, tens of rows); lossless WebP also makes libwebp
// keep a 4-byte-per-pixel copy of the image, as its back-references may reach any earlier pixel.
// The OpenImageIO reader holds what its format reader keeps.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture {

struct RowSourceInfo {
    uint32_t width = 0, height = 0, channels = 0;
    PixelType pixelType = PixelType::U8;         // the stored type closest to the source's
    ColorSpace colorSpace = ColorSpace::Linear;  // what the file says or, without a word, its type implies
    int alphaChannel = -1;                       // -1: none
    uint32_t bandRows = 64;                      // rows per read that suit the file's layout
    const char* reader = "";                     // "libwebp" or "OpenImageIO"
};

class RowSource {
public:
    virtual ~RowSource() = default;
    const RowSourceInfo& info() const { return m_info; }
    // Writes rows y0 .. y0 + rows - 1 (width * channels floats each) to out. Rows are read in
    // order: y0 is the row after the last one read (0 at first).
    virtual void read(uint32_t y0, uint32_t rows, float* out) = 0;

protected:
    RowSourceInfo m_info;
};

// Reads a RowSource's bands (info().bandRows rows each, the last one shorter) on a thread of its
// own, up to `depth` bands ahead of the caller, so that decoding overlaps the work on the bands
// already read. An error of the source is thrown by the next() that would have returned the band.
// Memory: depth bands of width * channels floats per row.
class RowPrefetcher {
public:
    RowPrefetcher(RowSource& source, uint32_t depth);
    ~RowPrefetcher();  // stops the thread (after the band it is reading)
    RowPrefetcher(const RowPrefetcher&) = delete;
    RowPrefetcher& operator=(const RowPrefetcher&) = delete;

    struct Band {
        uint32_t firstRow = 0, rows = 0;
        const float* values = nullptr;  // valid until the next call of next()
    };
    // The next band in order; rows == 0 after the last one.
    Band next();

private:
    void readAll();
    uint32_t rowsOf(uint32_t band) const;
    RowSource& m_source;
    const uint32_t m_bandRows;
    std::vector<std::vector<float>> m_slots;  // band b is read into slot b % size
    uint32_t m_bands = 0;
    uint32_t m_readBands = 0;      // bands the thread has finished (guarded by m_mutex)
    uint32_t m_consumedBands = 0;  // bands the caller has let go of (guarded by m_mutex)
    uint32_t m_handedOut = 0;      // bands next() has returned
    bool m_stop = false;
    std::exception_ptr m_error;
    std::mutex m_mutex;
    std::condition_variable m_changed;
    std::thread m_thread;
};

// Opens the reader for every file that is not a WebP still (openOiioRowSource, or makebot's loader
// of it, tools/makebot/oiio_module.h).
using RowSourceOpener = std::function<std::unique_ptr<RowSource>(const std::filesystem::path&)>;

// The reader that suits the file: libwebp for a WebP still (by its bytes, not its name),
// otherFormats for everything else.
std::unique_ptr<RowSource> openRowSource(const std::filesystem::path& path, const RowSourceOpener& otherFormats);
// How much of a WebP file libwebp is given per step.
constexpr size_t kWebpSliceBytes = 32 * 1024;
// The libwebp reader whatever the file (it throws FormatError for anything but a WebP still,
// animations included).
std::unique_ptr<RowSource> openWebpRowSource(const std::filesystem::path& path, size_t sliceBytes = kWebpSliceBytes);

}  // namespace pushpin::texture
