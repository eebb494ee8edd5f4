// texture/auto_convert.cpp: content-keyed, race-safe conversion of images into BOT files.
#include "texture/auto_convert.h"

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>

#include "cache/error.h"
#include "texture/image_input.h"
#include "texture/detail/bot_layout.h"

namespace pushpin::texture {
namespace {

// A 64-bit hash of a byte stream, 8 bytes at a time (multiply-xorshift mixing). It only has to
// tell different images apart; it is not a cryptographic hash.
class ContentHash {
public:
    void add(const uint8_t* p, size_t n) {
        m_length += n;
        while (n > 0) {
            const size_t take = std::min(n, size_t(8) - m_pending);
            std::memcpy(m_buffer + m_pending, p, take);
            m_pending += take;
            p += take;
            n -= take;
            if (m_pending == 8) {
                uint64_t w;
                std::memcpy(&w, m_buffer, 8);
                mixWord(w);
                m_pending = 0;
            }
        }
    }
    void addWord(uint64_t w) { add(reinterpret_cast<const uint8_t*>(&w), 8); }
    uint64_t finish() {
        uint64_t w = 0;
        std::memcpy(&w, m_buffer, m_pending);
        mixWord(w ^ (uint64_t(m_pending) << 56));
        uint64_t h = m_state ^ m_length;
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        h *= 0xc4ceb9fe1a85ec53ull;
        return h ^ (h >> 33);
    }

private:
    void mixWord(uint64_t w) {
        w *= 0x87c37b91114253d5ull;
        w = (w << 31) | (w >> 33);
        w *= 0x4cf5ad432745937full;
        m_state ^= w;
        m_state = ((m_state << 27) | (m_state >> 37)) * 5 + 0x52dce729;
    }
    uint64_t m_state = 0x9E3779B97F4A7C15ull;
    uint64_t m_length = 0;
    uint8_t m_buffer[8] = {};
    size_t m_pending = 0;
};

std::string uniqueSuffix() {
    static std::atomic<uint64_t> counter{0};
    std::random_device rd;
    return std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1)) + "-" +
           std::to_string(rd());
}

}  // namespace

bool isBotFile(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    uint8_t magic[sizeof detail::kBotMagic] = {};
    const ssize_t n = ::pread(fd, magic, sizeof magic, 0);
    ::close(fd);
    return n == ssize_t(sizeof magic) && std::memcmp(magic, detail::kBotMagic, sizeof magic) == 0;
}

std::filesystem::path conversionDir(const AutoConvertOptions& options) {
    std::filesystem::path base = options.tmpDir;
    if (base.empty()) {
        const char* env = std::getenv("TMPDIR");
        base = (env && *env) ? env : "/tmp";
    }
    return base / "pushpin-bot";
}

uint64_t conversionKey(const std::filesystem::path& image, const AutoConvertOptions& options) {
    const int fd = ::open(image.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(image, "open image to convert", errno);
    ContentHash h;
    std::vector<uint8_t> buf(size_t(1) << 20);
    for (;;) {
        const ssize_t n = ::read(fd, buf.data(), buf.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            throw IoError(image, "read image to convert", err);
        }
        if (n == 0) break;
        h.add(buf.data(), size_t(n));
    }
    ::close(fd);
    // Everything that changes the converted file, and the BOT version, goes into the key.
    const BotWriteOptions& b = options.bot;
    h.addWord(detail::kBotVersion);
    h.addWord(options.matchSourcePixelType ? 0xff : uint64_t(b.pixelType));
    h.addWord(uint64_t(b.colorSpace) | uint64_t(b.wrapS) << 8 | uint64_t(b.wrapT) << 16);
    h.add(reinterpret_cast<const uint8_t*>(b.filter.data()), b.filter.size());
    h.addWord(uint64_t(int64_t(b.alphaChannel)) ^ uint64_t(b.compressionLevel) << 32);
    h.addWord(uint64_t(b.dictionary) | uint64_t(b.pageFilter ? 1 + unsigned(*b.pageFilter) : 0) << 8);
    h.addWord(options.maxChannels);
    return h.finish();
}

LoadedImage loadImage(const std::filesystem::path& image, uint32_t maxChannels) {
    auto in = openImageInput(image);
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw IoError(image, "image has no pixels");
    LoadedImage out;
    out.width = uint32_t(spec.width);
    out.height = uint32_t(spec.height);
    out.channels = std::min<uint32_t>(uint32_t(spec.nchannels), std::max(1u, maxChannels));
    out.pixels.resize(size_t(out.width) * out.height * out.channels);
    const bool ok = in->read_image(0, 0, 0, int(out.channels), OIIO::TypeDesc::FLOAT, out.pixels.data());
    requireCleanRead(*in, ok, image, "the pixels");
    return out;
}

AutoConvertResult convertToBot(const std::filesystem::path& image, const AutoConvertOptions& options) {
    AutoConvertResult result;
    std::filesystem::path temp;
    try {
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx",
                      static_cast<unsigned long long>(conversionKey(image, options)));
        const std::filesystem::path dir = conversionDir(options);
        // Named by content alone: the same image under two names converts once.
        const std::filesystem::path final = dir / (std::string(hex) + ".bot");
        // Someone (this or another render) converted it already. The name only ever appears by
        // rename() of a complete file, so opening it is enough to trust it.
        std::error_code ec;
        if (std::filesystem::exists(final, ec)) {
            try {
                BotFile::open(final);
                result.botPath = final;
                result.reused = true;
                return result;
            } catch (const std::exception&) {
                // Not a readable BOT file after all (damaged on disk): convert again over it.
            }
        }
        std::filesystem::create_directories(dir, ec);
        if (ec) throw IoError(dir, "create conversion folder", ec.value());
        LoadedImage img = loadImage(image, options.maxChannels);
        BotWriteOptions bot = options.bot;
        if (options.matchSourcePixelType) {
            auto in = OIIO::ImageInput::open(image.string());
            bot.pixelType = in ? pixelTypeOf(in->spec().format) : PixelType::Float;
        }
        temp = dir / (final.filename().string() + ".tmp-" + uniqueSuffix());
        if (options.writer)
            options.writer(temp, img.pixels.data(), img.width, img.height, img.channels, bot);
        else
            writeBot(temp, img.pixels.data(), img.width, img.height, img.channels, bot);
        if (::rename(temp.c_str(), final.c_str()) != 0)
            throw IoError(final, "rename converted texture into place", errno);
        result.botPath = final;
        return result;
    } catch (const std::exception& ex) {
        if (!temp.empty()) {
            std::error_code ec;
            std::filesystem::remove(temp, ec);
        }
        result.botPath.clear();
        result.error = ex.what();
        if (result.error.empty()) result.error = "conversion failed";
        return result;
    }
}

}  // namespace pushpin::texture
