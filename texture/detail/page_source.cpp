// texture/detail/page_source.cpp: the file-backed and memory-backed page sources.
#include "texture/detail/page_source.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace pushpin::texture::detail {
namespace {

class FilePageSource final : public PageSource {
public:
    explicit FilePageSource(std::shared_ptr<const BotFile> file) : m_file(std::move(file)) {}
    const BotHeader& header() const override { return m_file->header(); }
    const std::filesystem::path& path() const override { return m_file->path(); }
    bool needsFile() const override { return true; }
    uint64_t fileBytes() const override { return m_file->fileBytes(); }
    size_t memoryBytes() const override { return sizeof(*this) + m_file->memoryBytes(); }
    uint64_t readPage(const PageFile& file, uint32_t level, uint32_t pageX, uint32_t pageY,
                      float* dst) const override {
        if (file.bytes)
            return m_file->readPageFromMapping(file.bytes, file.byteCount, level, pageX, pageY, dst);
        return m_file->readPage(file.fd, level, pageX, pageY, dst);
    }

private:
    std::shared_ptr<const BotFile> m_file;
};

class MemoryPageSource final : public PageSource {
public:
    MemoryPageSource(std::filesystem::path name, BotHeader header,
                     std::vector<std::vector<float>> levels)
        : m_name(std::move(name)), m_header(std::move(header)), m_levels(std::move(levels)) {
        if (m_header.channels == 0 || m_header.levels.empty() ||
            m_levels.size() != m_header.levels.size())
            throw std::invalid_argument("memory texture '" + m_name.string() +
                                        "': level table does not match the levels given");
        for (size_t l = 0; l < m_levels.size(); ++l) {
            const BotLevel& lv = m_header.levels[l];
            if (lv.width == 0 || lv.height == 0 ||
                m_levels[l].size() != size_t(lv.width) * lv.height * m_header.channels)
                throw std::invalid_argument("memory texture '" + m_name.string() + "': level " +
                                            std::to_string(l) + " has the wrong size");
        }
    }
    const BotHeader& header() const override { return m_header; }
    const std::filesystem::path& path() const override { return m_name; }
    bool needsFile() const override { return false; }
    uint64_t fileBytes() const override { return 0; }
    size_t memoryBytes() const override {
        size_t n = sizeof(*this) + m_name.native().capacity() +
                   m_header.levels.capacity() * sizeof(BotLevel) +
                   m_levels.capacity() * sizeof(std::vector<float>);
        for (const std::vector<float>& l : m_levels) n += l.capacity() * sizeof(float);
        return n;
    }
    uint64_t readPage(const PageFile&, uint32_t level, uint32_t pageX, uint32_t pageY,
                      float* dst) const override {
        const BotLevel& lv = m_header.levels.at(level);
        const uint32_t c = m_header.channels;
        const float* src = m_levels[level].data();
        // Texels past the level's edge repeat the edge texel, as the BOT writer pads.
        for (uint32_t y = 0; y < kPageSizeTexels; ++y) {
            const uint32_t sy = std::min(pageY * kPageSizeTexels + y, lv.height - 1);
            for (uint32_t x = 0; x < kPageSizeTexels; ++x) {
                const uint32_t sx = std::min(pageX * kPageSizeTexels + x, lv.width - 1);
                const float* p = src + (size_t(sy) * lv.width + sx) * c;
                std::copy(p, p + c, dst + (y * kPageSizeTexels + x) * c);
            }
        }
        return 0;
    }

private:
    std::filesystem::path m_name;
    BotHeader m_header;
    std::vector<std::vector<float>> m_levels;
};

BotLevel makeLevel(uint32_t w, uint32_t h) {
    BotLevel lv;
    lv.width = w;
    lv.height = h;
    lv.pagesX = (w + kPageSizeTexels - 1) / kPageSizeTexels;
    lv.pagesY = (h + kPageSizeTexels - 1) / kPageSizeTexels;
    return lv;
}

}  // namespace

std::shared_ptr<const PageSource> makeFilePageSource(std::shared_ptr<const BotFile> file) {
    return std::make_shared<FilePageSource>(std::move(file));
}

std::shared_ptr<const PageSource> makeMemoryPageSource(std::filesystem::path name,
                                                       BotHeader header,
                                                       std::vector<std::vector<float>> levels) {
    return std::make_shared<MemoryPageSource>(std::move(name), std::move(header),
                                              std::move(levels));
}

std::shared_ptr<const PageSource> makeMemoryPageSource(std::filesystem::path name,
                                                       const float* pixels, uint32_t width,
                                                       uint32_t height, uint32_t channels,
                                                       WrapMode wrapS, WrapMode wrapT) {
    if (!pixels || width == 0 || height == 0 || channels == 0)
        throw std::invalid_argument("memory texture '" + name.string() + "' is empty");
    BotHeader header;
    header.width = width;
    header.height = height;
    header.channels = channels;
    header.pixelType = PixelType::Float;
    header.wrapS = wrapS;
    header.wrapT = wrapT;
    std::vector<std::vector<float>> levels;
    header.levels.push_back(makeLevel(width, height));
    levels.emplace_back(pixels, pixels + size_t(width) * height * channels);
    while (header.levels.back().width > 1 || header.levels.back().height > 1) {
        const BotLevel& prev = header.levels.back();
        const uint32_t pw = prev.width, ph = prev.height;
        const uint32_t w = std::max(1u, pw / 2), h = std::max(1u, ph / 2);
        const std::vector<float>& src = levels.back();
        std::vector<float> dst(size_t(w) * h * channels);
        // Each texel averages the 2×2 block above it (a 1-wide axis averages with itself).
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                for (uint32_t ch = 0; ch < channels; ++ch) {
                    const uint32_t x0 = std::min(2 * x, pw - 1), x1 = std::min(2 * x + 1, pw - 1);
                    const uint32_t y0 = std::min(2 * y, ph - 1), y1 = std::min(2 * y + 1, ph - 1);
                    auto at = [&](uint32_t xx, uint32_t yy) {
                        return src[(size_t(yy) * pw + xx) * channels + ch];
                    };
                    dst[(size_t(y) * w + x) * channels + ch] =
                        0.25f * (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1));
                }
        header.levels.push_back(makeLevel(w, h));
        levels.push_back(std::move(dst));
    }
    return makeMemoryPageSource(std::move(name), std::move(header), std::move(levels));
}

}  // namespace pushpin::texture::detail
