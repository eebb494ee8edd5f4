// texture/detail/page_source.h: where TextureCache gets the texels of one page on a miss.
// A source is either a BOT file on disk (pages read from a read-only mapping of the file, or with
// pread where the file cannot be mapped, through the handle the cache's file pool holds) or an
// image held in memory (the fallback when a texture cannot be converted, and tests).
// Thread safety: every method is const and may be called from several threads at once.
// Memory: a file source holds only the BOT header, page table and dictionary; a memory source
// holds its pyramid. memoryBytes() reports either, for the cache to charge.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture::detail {

// How a file source reaches its file, as the cache's file pool opened it: a read-only mapping of
// at least fileBytes() bytes (bytes != nullptr) or else a descriptor for pread (fd >= 0).
struct PageFile {
    int fd = -1;
    const uint8_t* bytes = nullptr;
    size_t byteCount = 0;
};

class PageSource {
public:
    virtual ~PageSource() = default;
    // Width, height, channels, wrap modes and the level table (level 0 = full resolution).
    virtual const BotHeader& header() const = 0;
    // Names the texture in messages; for a file source it is also the file the cache opens.
    virtual const std::filesystem::path& path() const = 0;
    // True when readPage() needs path() opened (a PageFile).
    virtual bool needsFile() const = 0;
    // The size of the file the tables were read from (0 for a memory source). The cache maps
    // this many bytes and refuses a file that has become shorter.
    virtual uint64_t fileBytes() const = 0;
    // Heap bytes the source holds (tables, dictionary, or the in-memory pyramid).
    virtual size_t memoryBytes() const = 0;
    // Writes kPageSizeTexels² × channels floats (row-major, channels interleaved) of page
    // (pageX, pageY) of `level` to dst. `file` reaches path() when needsFile(); else it is empty.
    // Returns the number of compressed bytes read (0 for memory). Throws FormatError or IoError.
    virtual uint64_t readPage(const PageFile& file, uint32_t level, uint32_t pageX, uint32_t pageY,
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
