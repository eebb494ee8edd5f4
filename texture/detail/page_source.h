// texture/detail/page_source.h: where TextureCache gets the texels of one page on a miss.
// A source is either a BOT file on disk (pages read with pread through BotFile::readPage on a
// descriptor the cache's file pool owns) or an image held in memory (the fallback when a texture
// cannot be converted, and tests).
// Thread safety: every method is const and may be called from several threads at once.
// Memory: a file source holds only the BOT header and page table; a memory source holds its pyramid.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture::detail {

class PageSource {
public:
    virtual ~PageSource() = default;
    // Width, height, channels, wrap modes and the level table (level 0 = full resolution).
    virtual const BotHeader& header() const = 0;
    // Names the texture in messages; for a file source it is also the file the cache opens.
    virtual const std::filesystem::path& path() const = 0;
    // True when readPage() needs an O_RDONLY descriptor on path().
    virtual bool needsFile() const = 0;
    // Writes kPageSizeTexels² × channels floats (row-major, channels interleaved) of page
    // (pageX, pageY) of `level` to dst. `fd` is a descriptor on path() when needsFile(), else -1.
    // Returns the number of bytes read from disk (0 for memory). Throws FormatError or IoError.
    virtual uint64_t readPage(int fd, uint32_t level, uint32_t pageX, uint32_t pageY,
                              float* dst) const = 0;
};

// A source over a parsed BOT file.
std::shared_ptr<const PageSource> makeFilePageSource(std::shared_ptr<const BotFile> file);

// A source over a float image in memory (width × height × channels, row-major, interleaved).
// Builds a box-filtered pyramid down to 1×1 (each level halves, rounding down, never below 1).
// `name` only labels the texture in messages. Throws std::invalid_argument on empty input.
std::shared_ptr<const PageSource> makeMemoryPageSource(std::filesystem::path name,
                                                       const float* pixels, uint32_t width,
                                                       uint32_t height, uint32_t channels,
                                                       WrapMode wrapS, WrapMode wrapT);

// The same, from levels the caller already built (level l is levels[l], sized as in `header`).
// Used to give each level distinct content in tests of level selection.
std::shared_ptr<const PageSource> makeMemoryPageSource(std::filesystem::path name,
                                                       BotHeader header,
                                                       std::vector<std::vector<float>> levels);

}  // namespace pushpin::texture::detail
