// texture/bot_file.h: the BOT texture file (see texture/BOT_FORMAT.md): reading its header, level
// table and page table, reading single 8x8 pages, and writing whole files (streaming BotWriter, or
// writeBot for an image already in memory).
// Thread safety: a BotFile is immutable after open(); all its const methods may be called
// concurrently. A BotWriter belongs to one thread (it parallelises page encoding internally with
// oneTBB).
// Memory: a BotFile holds 16 bytes per page plus the file's dictionary (version 2) or its bands'
// coding tables and palettes (version 3: 3 KiB of decoding tables per context, 14 contexts a byte of
// a sample, and 1 KiB per context in use; a band holds up to 16384 pages); readPage uses
// thread-local buffers bounded by the largest possible page (64 channels of float: 16 KiB raw). A BotWriter holds 8 rows per level, 8
// bytes per page for its tables, and while it trains its dictionary (version 2) at most
// kDictionarySampleBytes of pending pages; version 3 holds one band per level as samples (at most
// 8 MiB each) and, while coding it, its packed pages and their contexts, plus the tail band's levels
// (at most 8 MiB).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pushpin::cache {
class ZstdDictionary;
}
namespace pushpin::texture::detail {
class RansTableSet;
}

namespace pushpin::texture {

enum class PixelType : uint8_t { U8 = 0, U16 = 1, Half = 2, Float = 3 };
enum class WrapMode : uint8_t { Black = 0, Clamp = 1, Periodic = 2, Mirror = 3 };
enum class ColorSpace : uint8_t { Linear = 0, SRGB = 1 };
// How the samples of a page are predicted before zstd codes them (BOT_FORMAT.md "Pages").
enum class PageFilter : uint8_t {
    None = 0,  // samples as they are
    Med = 1,   // LOCO-I median edge detector: best where edges are sharp
    Mean = 2,  // mean of the left, upper, upper-left and upper-right samples: best where texels are noisy
};
// Which zstd dictionary a writer builds from the first pages (BOT_FORMAT.md "Compression").
enum class BotDictionary : uint8_t { Auto = 0, None = 1, Trained = 2, Literal = 3 };
// How a page is stored (the top two bits of its page-table size field).
enum class BotPageKind : uint8_t {
    Raw = 0,       // the packed page as it is (incompressible)
    Frame = 1,     // prefix, then a whole compact zstd frame
    Block = 2,     // prefix, then the body of the frame's one compressed block
    Literals = 3,  // prefix, then the Huffman stream of a literals-only block
    // Version 3:
    Rans = 4,      // the band's rANS coding of the page (prefix bytes past the third, state, bytes)
    Constant = 5,  // no stored bytes: every residual is zero, texel 0 is a colour of the band's palette
};
constexpr uint32_t kBotPageKinds = 6;

constexpr uint32_t kPageSizeTexels = 8;  // pages are 8x8 texels
constexpr uint32_t kMaxChannels = 64;
constexpr uint32_t kMaxDimension = 1u << 24;  // widest or tallest level 0 a BOT file may declare

struct BotLevel {
    uint32_t width = 0, height = 0, pagesX = 0, pagesY = 0;
};

struct BotHeader {
    uint32_t width = 0, height = 0, channels = 0;
    PixelType pixelType = PixelType::U8;
    ColorSpace colorSpace = ColorSpace::Linear;
    WrapMode wrapS = WrapMode::Periodic, wrapT = WrapMode::Periodic;
    std::vector<BotLevel> levels;  // level 0 = full resolution
};

// Bytes per stored sample of `type` (1, 2, 2, 4).
uint32_t bytesPerSample(PixelType type);
const char* pixelTypeName(PixelType type);
const char* wrapModeName(WrapMode mode);
const char* colorSpaceName(ColorSpace space);
const char* pageFilterName(PageFilter filter);
const char* pageKindName(BotPageKind kind);
const char* botDictionaryName(BotDictionary kind);
std::optional<BotDictionary> parseBotDictionary(const std::string& name);  // auto, none, trained, literal
std::optional<PageFilter> parsePageFilter(const std::string& name);  // none, med, mean

// Where one page lives in the file (plain data). 16 bytes: a texture of 16384^2 texels has 5.6
// million pages, and every registered texture keeps its table in memory.
struct BotPageEntry {
    uint64_t offsetBytes = 0;
    // Low 32 (version 3: 16) bits of XXH64(stored bytes, seed = page index | kind << 56); for a
    // version-3 constant page, the index of its colour in its band's palette; 0 for a version-3
    // rANS page, whose checksum rides in its stored bytes.
    uint32_t checksum = 0;
    uint16_t storedBytes = 0;  // bytes on disk (at most 16384)
    BotPageKind kind = BotPageKind::Raw;
};
static_assert(sizeof(BotPageEntry) == 16);

// A parsed BOT file: header, level table and page table in memory; no file descriptor is kept open.
// Thread safety: all const methods may be called concurrently.
class BotFile {
public:
    // Reads and validates header and page table. Throws IoError / FormatError naming the file.
    static std::shared_ptr<const BotFile> open(const std::filesystem::path& path);
    // Parses a whole BOT file held in memory (`path` only names it in messages). Same checks as open().
    static std::shared_ptr<const BotFile> parse(const uint8_t* bytes, size_t byteCount,
                                                const std::filesystem::path& path);

    const std::filesystem::path& path() const { return m_path; }
    const BotHeader& header() const { return m_header; }
    uint64_t fileBytes() const { return m_fileBytes; }

    // Reads one page with pread() on an fd the caller opened on path() (O_RDONLY), verifies its
    // checksum, decompresses and converts it to float (u8/u16 normalised to [0,1]; sRGB-tagged data
    // is returned as stored, not linearised), writing kPageSizeTexels*kPageSizeTexels*channels
    // floats, row-major, channels interleaved. Texels past the level's edge hold the padding the
    // writer stored (edge texels repeated). Returns the number of compressed bytes read. Throws
    // FormatError naming file, level and page on corruption, IoError on a failed read,
    // std::out_of_range for a level or page that does not exist. Never allocates more than a
    // bounded page buffer.
    uint64_t readPage(int fd, uint32_t level, uint32_t pageX, uint32_t pageY, float* dst) const;
    // The same for a file held in memory (the bytes parse() was given, or a copy of the file).
    uint64_t readPageFromMemory(const uint8_t* bytes, size_t byteCount, uint32_t level, uint32_t pageX,
                                uint32_t pageY, float* dst) const;
    // The same for a read-only mapping of the file (detail::mapFile) of `byteCount` bytes, which
    // must be at least fileBytes(). The stored bytes are copied out under a SIGBUS guard, so a file
    // truncated in place while mapped gives an IoError naming the file and page instead of a
    // crash (see texture/detail/mapped_file.h).
    uint64_t readPageFromMapping(const uint8_t* bytes, size_t byteCount, uint32_t level, uint32_t pageX,
                                 uint32_t pageY, float* dst) const;
    // Heap bytes this object holds: tables, path and the digested dictionary.
    size_t memoryBytes() const;

    // Page table access (for botinfo and tests).
    uint64_t pageCount() const { return m_pages.size(); }
    uint64_t pageIndex(uint32_t level, uint32_t pageX, uint32_t pageY) const;  // throws out_of_range
    const BotPageEntry& pageEntry(uint64_t index) const { return m_pages[index]; }
    uint32_t pageRawBytes() const { return m_pageRawBytes; }  // decompressed bytes of one page
    uint32_t dictionaryBytes() const { return m_dictionaryBytes; }
    // The page filter (version 3: of the first band of level 0).
    PageFilter pageFilter() const { return m_pageFilter; }
    uint32_t version() const { return m_version; }  // 2 or 3
    uint64_t bandCount() const { return m_bands.size(); }  // version 3; 0 for version 2

private:
    struct Source;  // where parseImpl reads from: a file descriptor or a memory buffer
    BotFile() = default;
    static std::shared_ptr<const BotFile> parseImpl(const std::filesystem::path& path, const Source& source);
    static void parseVersion3(BotFile& file, const uint8_t* header, const Source& source);
    // The entry of page `index`, checked to lie within the first `byteCount` bytes of the file;
    // throws FormatError naming the page otherwise.
    const BotPageEntry& entryWithin(uint64_t index, size_t byteCount, uint32_t level, uint32_t pageX,
                                    uint32_t pageY) const;
    uint64_t decodePage(uint64_t index, uint32_t level, uint32_t pageX, uint32_t pageY,
                        const uint8_t* stored, float* dst) const;

    std::filesystem::path m_path;
    BotHeader m_header;
    uint64_t m_fileBytes = 0;
    uint32_t m_pageRawBytes = 0;
    uint32_t m_dictionaryBytes = 0;
    PageFilter m_pageFilter = PageFilter::None;
    std::vector<uint64_t> m_levelFirstPage;
    std::vector<BotPageEntry> m_pages;
    std::shared_ptr<const cache::ZstdDictionary> m_dictionary;
    // Version 3: bands of page rows, each with its filter and coding tables.
    struct Band {
        PageFilter filter = PageFilter::None;
        uint32_t decorrelateTo = 0;  // channels 1 to this one coded as differences (0: none; 2 or 3)
        std::vector<uint8_t> palette;  // the band's constant colours, each a page prefix
        std::shared_ptr<const detail::RansTableSet> tables;
    };
    uint32_t m_version = 0;
    std::vector<Band> m_bands;
    std::vector<uint32_t> m_levelFirstBand, m_levelBandRows;
};

// How a BOT file is written. Fields after `threads` are tuning knobs with sensible defaults.
struct BotWriteOptions {
    PixelType pixelType = PixelType::U8;
    ColorSpace colorSpace = ColorSpace::Linear;
    WrapMode wrapS = WrapMode::Periodic, wrapT = WrapMode::Periodic;
    std::string filter = "box";  // mip filter: box, triangle or lanczos3
    int threads = 0;             // 0: all hardware threads
    int alphaChannel = -2;       // -2: last channel of 2- and 4-channel images; -1: none
    // zstd level for pages with a trained or no dictionary (1 measured best on 8x8 pages); pages with
    // the literal dictionary use zstd's fast level -7 with Huffman literals (BOT_FORMAT.md).
    int compressionLevel = 1;
    // The per-file zstd dictionary: auto (the smallest of none, trained and literal on the first
    // pages), none, trained (zstd's trainer) or literal (a literal table fitted to the residuals).
    BotDictionary dictionary = BotDictionary::Auto;
    // Page prediction; unset: version 2, the filter whose residuals of the first pages have the lower
    // entropy; version 3, the one whose residuals of each band code smaller.
    std::optional<PageFilter> pageFilter;
    // The file version: 3 (rANS-coded pages in bands, BOT_FORMAT.md "Version 3"; the default) or 2
    // (zstd pages: files about 1.6 times the size, pages decoding in about 0.97 of the time).
    // compressionLevel and dictionary apply to version 2 only.
    uint32_t version = 3;
};

// Figures about one written file.
struct BotWriteStats {
    uint64_t pages = 0;
    uint64_t rawBytes = 0;    // decompressed page bytes
    uint64_t fileBytes = 0;   // whole file
    uint32_t dictionaryBytes = 0;
    PageFilter pageFilter = PageFilter::None;
    BotDictionary dictionary = BotDictionary::None;  // the kind used: None, Trained or Literal
    uint64_t pagesOfKind[kBotPageKinds] = {};  // indexed by BotPageKind
    uint32_t version = 0;
    uint64_t bands = 0;                        // version 3
};

// Writes a BOT file from a float image already in memory (used by tests and by makebot's
// small-image path). `pixels` is width*height*channels floats, row-major, interleaved. Builds the
// whole mip chain with `filter`. Writes a temporary name and renames; throws IoError (naming the
// path) on IO failure and std::invalid_argument on bad dimensions or options.
void writeBot(const std::filesystem::path& path, const float* pixels, uint32_t width, uint32_t height,
              uint32_t channels, const BotWriteOptions& options);

// Streams pages into a BOT file. Rows of each level arrive in increasing order (levels may
// interleave); every 8 rows (or the level's last rows, padded by repeating the last row and the
// last column) become a row of pages. The file is written under a temporary name in the target's
// folder and renamed over `path` by finish(); a writer destroyed before finish() removes its
// temporary file and leaves `path` untouched.
class BotWriter {
public:
    // Throws std::invalid_argument for unsupported dimensions/channels, IoError if the temporary
    // file cannot be created.
    BotWriter(const std::filesystem::path& path, uint32_t width, uint32_t height, uint32_t channels,
              const BotWriteOptions& options);
    ~BotWriter();
    BotWriter(const BotWriter&) = delete;
    BotWriter& operator=(const BotWriter&) = delete;

    const BotHeader& header() const;
    // Adds rows [firstRow, firstRow + rowCount) of `level` (width*channels floats per row).
    // `linearLight`: the values are linear and are encoded to the file's colour space when stored
    // (mip levels); otherwise they are stored as given (level 0). Throws IoError on write failure,
    // std::logic_error on out-of-order rows.
    void addRows(uint32_t level, uint32_t firstRow, uint32_t rowCount, const float* rows, bool linearLight);
    // Writes the tables and renames the file into place. Throws IoError, or std::logic_error if
    // some level is incomplete.
    BotWriteStats finish();

    static constexpr size_t kDictionarySampleBytes = size_t(1) << 19;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace pushpin::texture
