// texture/row_source.cpp: the libwebp row reader, the choice of reader and the band prefetcher.
#include "texture/row_source.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <webp/decode.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "cache/error.h"
#include "texture/detail/row_checks.h"

namespace pushpin::texture {
namespace {

using detail::requireConvertibleSize;
using detail::rowsText;

// 8-bit value -> float exactly as OpenImageIO converts it (v * (1/255), not v / 255).
const std::array<float, 256>& unitTable() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int v = 0; v < 256; ++v) t[size_t(v)] = float(v) * (1.0f / 255.0f);
        return t;
    }();
    return table;
}

// ------------------------------------------------------------------------------------ libwebp

const char* webpStatusText(VP8StatusCode status) {
    switch (status) {
        case VP8_STATUS_OK: return "ok";
        case VP8_STATUS_OUT_OF_MEMORY: return "out of memory";
        case VP8_STATUS_INVALID_PARAM: return "invalid parameter";
        case VP8_STATUS_BITSTREAM_ERROR: return "damaged bitstream";
        case VP8_STATUS_UNSUPPORTED_FEATURE: return "unsupported feature";
        case VP8_STATUS_SUSPENDED: return "suspended";
        case VP8_STATUS_USER_ABORT: return "aborted";
        case VP8_STATUS_NOT_ENOUGH_DATA: return "not enough data (truncated header)";
    }
    return "unknown error";
}

bool hasWebpMagic(const uint8_t* data, size_t size) {
    return size >= 12 && std::memcmp(data, "RIFF", 4) == 0 && std::memcmp(data + 8, "WEBP", 4) == 0;
}

// The file's bytes, read whole: libwebp needs what it has been given so far in one piece, and a
// copy (unlike a mapping) cannot fault if the file is cut short while it is decoded. A WebP file is
// a few MB where its image is tens.
class FileBytes {
public:
    explicit FileBytes(const std::filesystem::path& path) {
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw IoError(path, "open image", errno);
        struct stat st {};
        if (::fstat(fd, &st) != 0) {
            const int err = errno;
            ::close(fd);
            throw IoError(path, "stat image", err);
        }
        m_bytes.resize(size_t(st.st_size));
        size_t done = 0;
        while (done < m_bytes.size()) {
            const ssize_t n = ::pread(fd, m_bytes.data() + done, m_bytes.size() - done, off_t(done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                const int err = n < 0 ? errno : 0;
                ::close(fd);
                if (err) throw IoError(path, "read image", err);
                throw FormatError(path, "the file shrank while it was read");
            }
            done += size_t(n);
        }
        ::close(fd);
    }
    const uint8_t* data() const { return m_bytes.data(); }
    size_t size() const { return m_bytes.size(); }

private:
    std::vector<uint8_t> m_bytes;
};

// The header of the WebP file in `bytes`; throws FormatError when it is not one or its header
// cannot be read.
WebPBitstreamFeatures webpFeatures(const std::filesystem::path& path, const FileBytes& bytes) {
    if (!hasWebpMagic(bytes.data(), bytes.size())) throw FormatError(path, "not a WebP file");
    WebPBitstreamFeatures features;
    const VP8StatusCode status = WebPGetFeatures(bytes.data(), bytes.size(), &features);
    if (status != VP8_STATUS_OK)
        throw FormatError(path, std::string("cannot read the WebP header: ") + webpStatusText(status));
    return features;
}

class WebpRowSource final : public RowSource {
public:
    // `features`: webpFeatures of `bytes`, a still.
    WebpRowSource(const std::filesystem::path& path, std::unique_ptr<FileBytes> bytes,
                  const WebPBitstreamFeatures& features, size_t sliceBytes)
        : m_path(path), m_bytes(std::move(bytes)), m_slice(std::max<size_t>(1, sliceBytes)) {
        const uint32_t channels = features.has_alpha ? 4 : 3;
        requireConvertibleSize(path, features.width, features.height, channels);
        m_info.width = uint32_t(features.width);
        m_info.height = uint32_t(features.height);
        m_info.channels = channels;
        m_info.pixelType = PixelType::U8;
        m_info.colorSpace = ColorSpace::SRGB;  // WebP holds sRGB values (OpenImageIO says so too)
        m_info.alphaChannel = features.has_alpha ? 3 : -1;
        m_info.bandRows = 64;
        m_info.reader = "libwebp";

        m_stride = size_t(m_info.width) * channels;
        m_outBytes = m_stride * m_info.height;
        // Address space for the whole decoded image; only the rows between handed out and decoded
        // are ever resident, as handed-out pages are given back (read()).
        void* out = ::mmap(nullptr, m_outBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                           -1, 0);
        if (out == MAP_FAILED) throw std::bad_alloc();
        m_out = static_cast<uint8_t*>(out);
        m_decoder = WebPINewRGB(features.has_alpha ? MODE_RGBA : MODE_RGB, m_out, m_outBytes, int(m_stride));
        if (!m_decoder) {
            ::munmap(m_out, m_outBytes);
            throw std::bad_alloc();
        }
        m_page = size_t(::sysconf(_SC_PAGESIZE));
    }
    ~WebpRowSource() override {
        WebPIDelete(m_decoder);
        ::munmap(m_out, m_outBytes);
    }
    WebpRowSource(const WebpRowSource&) = delete;
    WebpRowSource& operator=(const WebpRowSource&) = delete;

    void read(uint32_t y0, uint32_t rows, float* out) override {
        if (y0 != m_next || rows == 0 || rows > m_info.height - y0)
            throw std::logic_error("WebpRowSource::read: rows out of order");
        const uint32_t end = y0 + rows;
        while (m_decoded < end) decodeSlice(y0, rows);

        const auto& unit = unitTable();
        const size_t values = m_stride * rows;
        const uint8_t* src = m_out + size_t(y0) * m_stride;
        if (m_info.channels == 3) {
            for (size_t i = 0; i < values; ++i) out[i] = unit[src[i]];
        } else {
            // Premultiplied in 8 bits, as OpenImageIO hands out WebP with alpha.
            for (size_t i = 0; i < values; i += 4) {
                const uint32_t a = src[i + 3];
                out[i + 0] = unit[(src[i + 0] * a + 127) / 255];
                out[i + 1] = unit[(src[i + 1] * a + 127) / 255];
                out[i + 2] = unit[(src[i + 2] * a + 127) / 255];
                out[i + 3] = unit[a];
            }
        }
        // The decoder never writes a finished row again: give the pages of handed-out rows back.
        const size_t done = (size_t(end) * m_stride) / m_page * m_page;
        if (done > m_released) {
            ::madvise(m_out + m_released, done - m_released, MADV_DONTNEED);
            m_released = done;
        }
        m_next = end;
    }

private:
    // Gives the decoder the next slice of the file and notes how many rows it has finished.
    void decodeSlice(uint32_t y0, uint32_t rows) {
        if (m_finished || m_fed == m_bytes->size())
            throw FormatError(m_path, "cannot read " + rowsText(y0, rows) + ": the WebP data ends after row " +
                                          std::to_string(m_decoded) + " of " + std::to_string(m_info.height) +
                                          " (the file is truncated)");
        m_fed = std::min(m_bytes->size(), m_fed + m_slice);
        const VP8StatusCode status = WebPIUpdate(m_decoder, m_bytes->data(), m_fed);
        if (status == VP8_STATUS_OK) {
            m_finished = true;
        } else if (status != VP8_STATUS_SUSPENDED) {
            throw FormatError(m_path, "cannot read " + rowsText(y0, rows) + ": " + webpStatusText(status) +
                                          " after row " + std::to_string(m_decoded) +
                                          " (the file may be truncated or damaged)");
        }
        int lastY = 0;
        if (WebPIDecGetRGB(m_decoder, &lastY, nullptr, nullptr, nullptr) && lastY > 0)
            m_decoded = std::max(m_decoded, std::min(uint32_t(lastY), m_info.height));
    }

    std::filesystem::path m_path;
    std::unique_ptr<FileBytes> m_bytes;
    size_t m_slice;
    size_t m_stride = 0, m_outBytes = 0, m_page = 4096;
    uint8_t* m_out = nullptr;
    WebPIDecoder* m_decoder = nullptr;
    size_t m_fed = 0;        // bytes of the file given to the decoder
    size_t m_released = 0;   // bytes at the start of m_out given back to the kernel
    uint32_t m_decoded = 0;  // rows the decoder has finished
    uint32_t m_next = 0;     // first row not yet handed out
    bool m_finished = false;
};

}  // namespace

RowPrefetcher::RowPrefetcher(RowSource& source, uint32_t depth)
    : m_source(source), m_bandRows(std::max(1u, source.info().bandRows)) {
    const RowSourceInfo& info = source.info();
    m_bands = (info.height + m_bandRows - 1) / m_bandRows;
    m_slots.resize(std::max(1u, std::min(depth, m_bands)));
    for (auto& slot : m_slots) slot.resize(size_t(info.width) * info.channels * m_bandRows);
    m_thread = std::thread([this] { readAll(); });
}

uint32_t RowPrefetcher::rowsOf(uint32_t band) const {
    return std::min(m_bandRows, m_source.info().height - band * m_bandRows);
}

RowPrefetcher::~RowPrefetcher() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
    }
    m_changed.notify_all();
    m_thread.join();
}

void RowPrefetcher::readAll() {
    for (uint32_t b = 0; b < m_bands; ++b) {
        {
            // Wait for the slot's previous band to be let go of.
            std::unique_lock<std::mutex> lock(m_mutex);
            m_changed.wait(lock, [&] { return m_stop || b < m_consumedBands + m_slots.size(); });
            if (m_stop) return;
        }
        try {
            m_source.read(b * m_bandRows, rowsOf(b), m_slots[b % m_slots.size()].data());
        } catch (...) {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_error = std::current_exception();
            m_changed.notify_all();
            return;
        }
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_readBands = b + 1;
        }
        m_changed.notify_all();
    }
}

RowPrefetcher::Band RowPrefetcher::next() {
    std::unique_lock<std::mutex> lock(m_mutex);
    if (m_handedOut > 0) {
        m_consumedBands = m_handedOut;  // the band returned last time is free again
        m_changed.notify_all();
    }
    if (m_handedOut == m_bands) return {};
    m_changed.wait(lock, [&] { return m_readBands > m_handedOut || m_error; });
    if (m_readBands <= m_handedOut) std::rethrow_exception(m_error);
    const uint32_t b = m_handedOut++;
    return {b * m_bandRows, rowsOf(b), m_slots[b % m_slots.size()].data()};
}

std::unique_ptr<RowSource> openWebpRowSource(const std::filesystem::path& path, size_t sliceBytes) {
    auto bytes = std::make_unique<FileBytes>(path);
    const WebPBitstreamFeatures features = webpFeatures(path, *bytes);
    if (features.has_animation) throw FormatError(path, "animated WebP (read through OpenImageIO instead)");
    return std::make_unique<WebpRowSource>(path, std::move(bytes), features, sliceBytes);
}

std::unique_ptr<RowSource> openRowSource(const std::filesystem::path& path, const RowSourceOpener& otherFormats) {
    // A WebP still by its bytes; an animation (VP8X flag, or an ANIM chunk) goes to OpenImageIO.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        uint8_t head[32] = {};
        const ssize_t n = ::pread(fd, head, sizeof head, 0);
        ::close(fd);
        if (n >= 12 && hasWebpMagic(head, size_t(n))) {
            auto bytes = std::make_unique<FileBytes>(path);
            const WebPBitstreamFeatures features = webpFeatures(path, *bytes);
            if (!features.has_animation)
                return std::make_unique<WebpRowSource>(path, std::move(bytes), features, kWebpSliceBytes);
        }
    }
    return otherFormats(path);
}

}  // namespace pushpin::texture
