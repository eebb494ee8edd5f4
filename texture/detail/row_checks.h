// texture/detail/row_checks.h: what both row readers (texture/row_source.h) say about rows and
// refuse in sizes, inline so that each reader can be built on its own.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "cache/error.h"
#include "texture/bot_file.h"

namespace pushpin::texture::detail {

inline std::string rowsText(uint32_t y0, uint32_t rows) {
    return "rows " + std::to_string(y0) + "-" + std::to_string(y0 + rows - 1);
}

// Throws FormatError for sizes a BOT file cannot hold.
inline void requireConvertibleSize(const std::filesystem::path& path, int64_t width, int64_t height, int64_t channels) {
    if (width <= 0 || height <= 0 || uint64_t(width) > kMaxDimension || uint64_t(height) > kMaxDimension)
        throw FormatError(path, "unsupported image size " + std::to_string(width) + "x" + std::to_string(height));
    if (channels <= 0 || uint64_t(channels) > kMaxChannels)
        throw FormatError(path, "unsupported channel count " + std::to_string(channels));
}

}  // namespace pushpin::texture::detail
