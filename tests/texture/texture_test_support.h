// tests/texture/texture_test_support.h: small textures and page sources shared by the texture
// cache, sampler, file texture and trace tests.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cache/error.h"
#include "texture/bot_file.h"
#include "texture/detail/page_source.h"
#include "texture/texture_cache.h"

namespace pushpin::texture::testing {

// width × height × channels floats from f(x, y, channel).
inline std::vector<float> makeImage(uint32_t width, uint32_t height, uint32_t channels,
                                    const std::function<float(uint32_t, uint32_t, uint32_t)>& f) {
    std::vector<float> img(size_t(width) * height * channels);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            for (uint32_t c = 0; c < channels; ++c)
                img[(size_t(y) * width + x) * channels + c] = f(x, y, c);
    return img;
}

inline std::shared_ptr<const detail::PageSource> memoryTexture(
    const std::string& name, uint32_t width, uint32_t height, uint32_t channels,
    const std::function<float(uint32_t, uint32_t, uint32_t)>& f,
    WrapMode wrap = WrapMode::Periodic) {
    const std::vector<float> img = makeImage(width, height, channels, f);
    return detail::makeMemoryPageSource(name, img.data(), width, height, channels, wrap, wrap);
}

// A 1-channel page source whose every texel of page (level, px, py) holds a value that encodes
// the page, with optional failures, delays and a count of reads: a probe of the cache itself.
class ProbeSource final : public detail::PageSource {
public:
    ProbeSource(std::string name, uint32_t width, uint32_t height) : m_name(std::move(name)) {
        m_header.width = width;
        m_header.height = height;
        m_header.channels = 1;
        m_header.pixelType = PixelType::Float;
        for (uint32_t w = width, h = height;; w = std::max(1u, w / 2), h = std::max(1u, h / 2)) {
            BotLevel lv;
            lv.width = w;
            lv.height = h;
            lv.pagesX = (w + 7) / 8;
            lv.pagesY = (h + 7) / 8;
            m_header.levels.push_back(lv);
            if (w == 1 && h == 1) break;
        }
    }
    static float pageValue(uint32_t level, uint32_t px, uint32_t py) {
        return float(level * 1000000 + py * 1000 + px);
    }
    const BotHeader& header() const override { return m_header; }
    const std::filesystem::path& path() const override { return m_name; }
    bool needsFile() const override { return false; }
    uint64_t fileBytes() const override { return 0; }
    size_t memoryBytes() const override { return kMemoryBytes; }
    uint64_t readPage(const detail::PageFile&, uint32_t level, uint32_t px, uint32_t py, float* dst) const override {
        reads.fetch_add(1);
        if (delayMilliseconds > 0)
            std::this_thread::sleep_for(std::chrono::milliseconds(delayMilliseconds));
        if (level == failLevel && px == failPageX && py == failPageY)
            throw FormatError(m_name, "checksum mismatch in level " + std::to_string(level) +
                                          " page (" + std::to_string(px) + ", " +
                                          std::to_string(py) + ")");
        std::fill(dst, dst + 64, pageValue(level, px, py));
        return 64;
    }

    static constexpr size_t kMemoryBytes = 1000;  // what the probe claims to hold
    mutable std::atomic<uint64_t> reads{0};
    int delayMilliseconds = 0;
    uint32_t failLevel = ~0u, failPageX = ~0u, failPageY = ~0u;

private:
    std::filesystem::path m_name;
    BotHeader m_header;
};

// A fresh directory under the system temp folder, removed at scope exit.
class TempDir {
public:
    explicit TempDir(const std::string& tag) {
        std::random_device rd;
        m_path = std::filesystem::temp_directory_path() /
                 ("pushpin-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};

// Collects warnings (thread-safe) for TextureCacheOptions::warningHandler.
struct WarningLog {
    std::mutex mutex;
    std::vector<std::string> messages;
    std::function<void(const std::string&)> handler() {
        return [this](const std::string& m) {
            std::lock_guard lock(mutex);
            messages.push_back(m);
        };
    }
    size_t count() {
        std::lock_guard lock(mutex);
        return messages.size();
    }
};

}  // namespace pushpin::texture::testing
