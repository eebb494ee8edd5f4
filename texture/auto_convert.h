// texture/auto_convert.h: converts a non-BOT image into a BOT file in TMPDIR once, so file
// textures can go through the page cache (Maya's useTextureCache).
// The BOT file is named after a hash of the image's bytes and of the conversion options, so the
// same image converts once however many file nodes, frames or renders use it. Each converter
// writes a name private to it and rename()s it into place, which is atomic: several processes
// converting the same image at once all end up using one complete file, and a converter that
// finds the final name already there uses it.
// Thread safety: convertToBot() may run in several threads and processes at once.
// Memory: a conversion holds the whole decoded image as float while it writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture {

// Writes a BOT file from a float image (the signature of writeBot).
using BotImageWriter = std::function<void(const std::filesystem::path& path, const float* pixels,
                                          uint32_t width, uint32_t height, uint32_t channels,
                                          const BotWriteOptions& options)>;

struct AutoConvertOptions {
    std::filesystem::path tmpDir;  // empty: $TMPDIR, or /tmp when unset
    BotWriteOptions bot;           // pixelType is replaced by the source's when matchSourcePixelType
    bool matchSourcePixelType = true;  // 8-bit → U8, 16-bit → U16, half → Half, else Float
    uint32_t maxChannels = 4;      // channels past this are dropped (the cache's slot width)
    BotImageWriter writer;         // empty: writeBot
};

struct AutoConvertResult {
    std::filesystem::path botPath;  // the converted file, when ok()
    bool reused = false;            // an earlier conversion (any process) was found and used
    std::string error;              // why conversion failed (then botPath is empty)
    bool ok() const { return error.empty(); }
};

// True when the file starts with the BOT magic bytes. False for unreadable files.
bool isBotFile(const std::filesystem::path& path);

// The folder conversions go to: options.tmpDir, else $TMPDIR, else /tmp; plus "pushpin-bot".
std::filesystem::path conversionDir(const AutoConvertOptions& options);

// 64-bit key of the image's bytes and the options that change the converted file.
// Throws IoError naming the path if the file cannot be read.
uint64_t conversionKey(const std::filesystem::path& image, const AutoConvertOptions& options);

// Converts `image` (anything OpenImageIO reads) unless a conversion with the same key exists.
// Never throws: an unreadable image, a full or unwritable TMPDIR, or a failed writer give a
// result with `error` set, and no partial file is left behind.
AutoConvertResult convertToBot(const std::filesystem::path& image, const AutoConvertOptions& options);

// A float image in memory (width × height × channels, interleaved).
struct LoadedImage {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<float> pixels;
};
// Reads subimage 0 of `image` with OpenImageIO, keeping at most maxChannels channels.
// Throws IoError naming the path and OpenImageIO's message.
LoadedImage loadImage(const std::filesystem::path& image, uint32_t maxChannels);

}  // namespace pushpin::texture
