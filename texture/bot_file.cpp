#include "texture/bot_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "cache/error.h"
#include "cache/output_file.h"
#include "cache/zstd_codec.h"
#include "texture/detail/bot_checksum.h"
#include "texture/detail/bot_layout.h"
#include "texture/detail/bot_page.h"
#include "texture/detail/bot_rans.h"
#include "texture/detail/mapped_file.h"
#include "texture/mipmap.h"

namespace pushpin::texture {

using detail::get16;
using detail::get32;
using detail::get64;
using detail::kPageTexels;
using detail::appendVarint;
using detail::readVarint;

uint32_t bytesPerSample(PixelType type) {
    switch (type) {
        case PixelType::U8: return 1;
        case PixelType::U16: return 2;
        case PixelType::Half: return 2;
        case PixelType::Float: return 4;
    }
    return 1;
}

const char* pixelTypeName(PixelType type) {
    switch (type) {
        case PixelType::U8: return "u8";
        case PixelType::U16: return "u16";
        case PixelType::Half: return "half";
        case PixelType::Float: return "float";
    }
    return "?";
}

const char* wrapModeName(WrapMode mode) {
    switch (mode) {
        case WrapMode::Black: return "black";
        case WrapMode::Clamp: return "clamp";
        case WrapMode::Periodic: return "periodic";
        case WrapMode::Mirror: return "mirror";
    }
    return "?";
}

const char* colorSpaceName(ColorSpace space) { return space == ColorSpace::SRGB ? "srgb" : "linear"; }

const char* pageFilterName(PageFilter filter) {
    switch (filter) {
        case PageFilter::None: return "none";
        case PageFilter::Med: return "med";
        case PageFilter::Mean: return "mean";
    }
    return "?";
}

std::optional<PageFilter> parsePageFilter(const std::string& name) {
    for (PageFilter f : {PageFilter::None, PageFilter::Med, PageFilter::Mean})
        if (name == pageFilterName(f)) return f;
    return std::nullopt;
}

const char* botDictionaryName(BotDictionary kind) {
    switch (kind) {
        case BotDictionary::Auto: return "auto";
        case BotDictionary::None: return "none";
        case BotDictionary::Trained: return "trained";
        case BotDictionary::Literal: return "literal";
    }
    return "?";
}

std::optional<BotDictionary> parseBotDictionary(const std::string& name) {
    for (BotDictionary k : {BotDictionary::Auto, BotDictionary::None, BotDictionary::Trained, BotDictionary::Literal})
        if (name == botDictionaryName(k)) return k;
    return std::nullopt;
}

const char* pageKindName(BotPageKind kind) {
    switch (kind) {
        case BotPageKind::Raw: return "raw";
        case BotPageKind::Frame: return "frame";
        case BotPageKind::Block: return "block";
        case BotPageKind::Literals: return "literals";
        case BotPageKind::Rans: return "rans";
        case BotPageKind::Constant: return "constant";
    }
    return "?";
}

namespace {

std::string pageName(uint32_t level, uint32_t pageX, uint32_t pageY) {
    return "level " + std::to_string(level) + " page (" + std::to_string(pageX) + ", " + std::to_string(pageY) + ")";
}

// Seeded with the page's index and kind, so that a page table pointing at another valid page, or
// naming the wrong kind, fails like damaged bytes.
uint32_t pageChecksum(const uint8_t* stored, size_t bytes, uint64_t pageIndex, BotPageKind kind) {
    return uint32_t(detail::xxh64(stored, bytes, pageIndex | uint64_t(kind) << 56));
}

// Version 3 stores the kind as 0 raw, 1 rANS, 2 constant, and keeps the low 16 bits of the checksum.
detail::Bot3Kind bot3KindOf(BotPageKind kind) {
    switch (kind) {
        case BotPageKind::Rans: return detail::Bot3Kind::Rans;
        case BotPageKind::Constant: return detail::Bot3Kind::Constant;
        default: return detail::Bot3Kind::Raw;
    }
}

// A raw page's checksum covers its stored bytes; a rANS page's covers the packed page it decodes to
// (after the channel coding) and rides in its rANS states (its low 15 bits), so that its entry needs
// none.
uint32_t page3Checksum(const uint8_t* bytes, size_t count, uint64_t pageIndex, BotPageKind kind) {
    return uint32_t(detail::xxh64(bytes, count, pageIndex | uint64_t(bot3KindOf(kind)) << 56) & 0xffffu);
}

cache::ZstdForm zstdFormOf(BotPageKind kind) {
    switch (kind) {
        case BotPageKind::Block: return cache::ZstdForm::Block;
        case BotPageKind::Literals: return cache::ZstdForm::Literals;
        default: return cache::ZstdForm::Frame;
    }
}

BotPageKind pageKindOf(cache::ZstdForm form) {
    switch (form) {
        case cache::ZstdForm::Block: return BotPageKind::Block;
        case cache::ZstdForm::Literals: return BotPageKind::Literals;
        case cache::ZstdForm::Frame: break;
    }
    return BotPageKind::Frame;
}

uint64_t pagesOf(uint32_t texels) { return (uint64_t(texels) + kPageSizeTexels - 1) / kPageSizeTexels; }

// The level table every valid file of this size has.
std::vector<BotLevel> levelsFor(uint32_t width, uint32_t height) {
    std::vector<BotLevel> levels;
    for (auto [w, h] : mipLevelSizes(width, height))
        levels.push_back({w, h, uint32_t(pagesOf(w)), uint32_t(pagesOf(h))});
    return levels;
}

// Reads exactly n bytes at offset; returns false on a short read (end of file), throws IoError on error.
bool preadAll(int fd, void* dst, size_t n, uint64_t offset, const std::filesystem::path& path) {
    uint8_t* p = static_cast<uint8_t*>(dst);
    while (n > 0) {
        const ssize_t r = ::pread(fd, p, n, off_t(offset));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw IoError(path, "read of " + std::to_string(n) + " bytes at offset " + std::to_string(offset), errno);
        }
        if (r == 0) return false;
        p += r;
        n -= size_t(r);
        offset += uint64_t(r);
    }
    return true;
}

void pwriteAll(int fd, const void* src, size_t n, uint64_t offset, const std::filesystem::path& path) {
    const uint8_t* p = static_cast<const uint8_t*>(src);
    while (n > 0) {
        const ssize_t r = ::pwrite(fd, p, n, off_t(offset));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw OutputError(path, "write of " + std::to_string(n) + " bytes at offset " + std::to_string(offset), errno);
        }
        p += r;
        n -= size_t(r);
        offset += uint64_t(r);
    }
}

// Per-thread buffers of readPage, allocated once at the size of the largest page any valid file can
// have, so reading a page never allocates.
struct PageScratch {
    static constexpr size_t kMaxRawBytes = size_t(kPageTexels) * kMaxChannels * 4;
    std::vector<uint8_t> stored, packed;
    std::optional<cache::ZstdDecompressor> decompressor;
    const cache::ZstdDictionary* dictionary = nullptr;
    PageScratch() : stored(cache::zstdCompressBound(kMaxRawBytes)), packed(kMaxRawBytes) {}
    cache::ZstdDecompressor& decompressorFor(const std::shared_ptr<const cache::ZstdDictionary>& d) {
        if (!decompressor) {
            decompressor.emplace();
            decompressor->reserve(kMaxRawBytes);
        }
        if (dictionary != d.get()) {
            decompressor->setDictionary(d);
            dictionary = d.get();
        }
        return *decompressor;
    }
};

PageScratch& pageScratch() {
    thread_local PageScratch scratch;
    return scratch;
}

}  // namespace

// ---------------------------------------------------------------------------------------- reading

struct BotFile::Source {
    int fd = -1;
    const uint8_t* bytes = nullptr;
    uint64_t size = 0;
    // Returns false when [offset, offset + n) is not inside the source.
    bool read(void* dst, size_t n, uint64_t offset, const std::filesystem::path& path) const {
        if (offset > size || n > size - offset) return false;
        if (bytes) {
            std::memcpy(dst, bytes + offset, n);
            return true;
        }
        return preadAll(fd, dst, n, offset, path);
    }
};

std::shared_ptr<const BotFile> BotFile::open(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(path, "cannot open BOT file", errno);
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        throw IoError(path, "cannot stat BOT file", e);
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        throw IoError(path, "not a regular file");
    }
    Source source;
    source.fd = fd;
    source.size = uint64_t(st.st_size);
    try {
        auto file = parseImpl(path, source);
        ::close(fd);
        return file;
    } catch (...) {
        ::close(fd);
        throw;
    }
}

std::shared_ptr<const BotFile> BotFile::parse(const uint8_t* bytes, size_t byteCount,
                                              const std::filesystem::path& path) {
    Source source;
    source.bytes = bytes;
    source.size = byteCount;
    return parseImpl(path, source);
}

std::shared_ptr<const BotFile> BotFile::parseImpl(const std::filesystem::path& path, const Source& source) {
    using namespace detail;
    auto fail = [&](const std::string& msg) -> FormatError { return FormatError(path, msg); };
    const uint64_t fileBytes = source.size;
    uint8_t h[kBotHeaderBytes];
    if (!source.read(h, kBotHeaderBytes, 0, path))
        throw fail("truncated BOT header (" + std::to_string(fileBytes) + " bytes, need " +
                   std::to_string(kBotHeaderBytes) + ")");
    if (std::memcmp(h, kBotMagic, sizeof kBotMagic) != 0) throw fail("not a BOT file (bad magic)");
    const uint32_t version = get32(h + kFieldVersion);
    if (version != kBotVersion2 && version != kBotVersion3)
        throw fail("unsupported BOT version " + std::to_string(version));
    if (get32(h + kFieldHeaderBytes) != kBotHeaderBytes)
        throw fail("bad header size " + std::to_string(get32(h + kFieldHeaderBytes)));

    std::shared_ptr<BotFile> file(new BotFile());
    file->m_path = path;
    file->m_fileBytes = fileBytes;
    file->m_version = version;
    BotHeader& hd = file->m_header;
    hd.width = get32(h + kFieldWidth);
    hd.height = get32(h + kFieldHeight);
    hd.channels = get32(h + kFieldChannels);
    if (hd.width == 0 || hd.height == 0 || hd.width > kMaxDimension || hd.height > kMaxDimension)
        throw fail("bad dimensions " + std::to_string(hd.width) + "x" + std::to_string(hd.height) + " (1.." +
                   std::to_string(kMaxDimension) + " allowed)");
    if (hd.channels == 0 || hd.channels > kMaxChannels)
        throw fail("bad channel count " + std::to_string(hd.channels) + " (1.." + std::to_string(kMaxChannels) +
                   " allowed)");
    if (h[kFieldPixelType] > 3) throw fail("bad pixel type " + std::to_string(h[kFieldPixelType]));
    if (h[kFieldColorSpace] > 1) throw fail("bad colour space " + std::to_string(h[kFieldColorSpace]));
    if (h[kFieldWrapS] > 3 || h[kFieldWrapT] > 3) throw fail("bad wrap mode");
    if (h[kFieldPageFilter] > 2) throw fail("bad page filter " + std::to_string(h[kFieldPageFilter]));
    if (h[kFieldMipFilter] > 2) throw fail("bad mip filter " + std::to_string(h[kFieldMipFilter]));
    hd.pixelType = PixelType(h[kFieldPixelType]);
    hd.colorSpace = ColorSpace(h[kFieldColorSpace]);
    hd.wrapS = WrapMode(h[kFieldWrapS]);
    hd.wrapT = WrapMode(h[kFieldWrapT]);
    file->m_pageFilter = PageFilter(h[kFieldPageFilter]);
    file->m_pageRawBytes = detail::pageRawBytes(hd.channels, hd.pixelType);

    const uint32_t levelCount = get32(h + kFieldLevelCount);
    hd.levels = levelsFor(hd.width, hd.height);
    if (levelCount != hd.levels.size())
        throw fail("bad level count " + std::to_string(levelCount) + " (a " + std::to_string(hd.width) + "x" +
                   std::to_string(hd.height) + " image has " + std::to_string(hd.levels.size()) + ")");
    if (version == kBotVersion3) {
        parseVersion3(*file, h, source);
        return file;
    }

    uint64_t pageCount = 0, rowCount = 0;
    for (const BotLevel& l : hd.levels) {
        file->m_levelFirstPage.push_back(pageCount);
        pageCount += uint64_t(l.pagesX) * l.pagesY;
        rowCount += l.pagesY;
    }
    const uint64_t levelTable = kBotHeaderBytes;
    const uint64_t rowTable = levelTable + uint64_t(levelCount) * kBotLevelEntryBytes;
    const uint64_t pageTable = rowTable + rowCount * kBotRowEntryBytes;
    const uint64_t dictOffset = pageTable + pageCount * kBotPageEntryBytes;
    const uint32_t dictBytes = get32(h + kFieldDictionaryBytes);
    if (get64(h + kFieldPageCount) != pageCount)
        throw fail("bad page count " + std::to_string(get64(h + kFieldPageCount)) + " (expected " +
                   std::to_string(pageCount) + ")");
    if (get64(h + kFieldLevelTable) != levelTable || get64(h + kFieldRowTable) != rowTable ||
        get64(h + kFieldPageTable) != pageTable || get64(h + kFieldDictionary) != dictOffset)
        throw fail("bad table offsets in header");
    if (get16(h + kFieldReserved0) != 0 || get32(h + kFieldReserved1) != 0) throw fail("reserved header fields not zero");
    if (dictBytes > kBotMaxDictionaryBytes) throw fail("bad dictionary size " + std::to_string(dictBytes));
    const uint64_t dataStart = dictOffset + dictBytes;
    if (dataStart > fileBytes)
        throw fail("tables extend past end of file (need " + std::to_string(dataStart) + " bytes, file has " +
                   std::to_string(fileBytes) + ")");

    // The whole table region is inside the file, so this allocation is bounded by the file size.
    std::vector<uint8_t> tables(size_t(dataStart - levelTable));
    if (!source.read(tables.data(), tables.size(), levelTable, path)) throw fail("truncated tables");
    const uint64_t metaChecksum = xxh64(tables.data(), tables.size(), xxh64(h, kFieldMetaChecksum, 0));
    if (metaChecksum != get64(h + kFieldMetaChecksum)) throw fail("header/page table checksum mismatch");

    const uint8_t* lt = tables.data();
    for (uint32_t l = 0; l < levelCount; ++l) {
        if (get32(lt + l * 8) != hd.levels[l].width || get32(lt + l * 8 + 4) != hd.levels[l].height)
            throw fail("level table entry " + std::to_string(l) + " does not match the image size");
    }
    const uint8_t* rt = tables.data() + (rowTable - levelTable);
    const uint8_t* pt = tables.data() + (pageTable - levelTable);
    const uint32_t rawBytes = file->m_pageRawBytes;
    const uint32_t prefixBytes = detail::pagePrefixBytes(hd.channels, hd.pixelType);
    file->m_pages.resize(size_t(pageCount));
    uint64_t row = 0, index = 0;
    for (uint32_t l = 0; l < levelCount; ++l) {
        const BotLevel& lv = hd.levels[l];
        for (uint32_t py = 0; py < lv.pagesY; ++py, ++row) {
            uint64_t offset = get64(rt + row * 8);
            for (uint32_t px = 0; px < lv.pagesX; ++px, ++index) {
                BotPageEntry& e = file->m_pages[index];
                const uint8_t* entry = pt + index * kBotPageEntryBytes;
                const uint32_t sizeField = get16(entry);
                e.checksum = get32(entry + 2);
                e.kind = BotPageKind(sizeField >> kBotPageKindShift);
                e.storedBytes = uint16_t(sizeField & kBotMaxStoredBytes);
                e.offsetBytes = offset;
                // A raw page has the packed page's size; any other holds the prefix, then at least one
                // byte of zstd data, and is smaller than the raw page.
                if (e.kind == BotPageKind::Raw) {
                    if (e.storedBytes != 0)
                        throw fail("bad size field " + std::to_string(sizeField) + " of raw " + pageName(l, px, py));
                    e.storedBytes = uint16_t(rawBytes);
                } else if (e.storedBytes <= prefixBytes || e.storedBytes >= rawBytes) {
                    throw fail("bad stored size " + std::to_string(e.storedBytes) + " of " + pageName(l, px, py) +
                               " (" + pageKindName(e.kind) + " pages hold " + std::to_string(prefixBytes + 1) +
                               " to " + std::to_string(rawBytes - 1) + " bytes)");
                }
                if (offset < dataStart || offset > fileBytes || e.storedBytes > fileBytes - offset)
                    throw fail(pageName(l, px, py) + " lies outside the file (offset " + std::to_string(offset) +
                               ", " + std::to_string(e.storedBytes) + " bytes, file has " +
                               std::to_string(fileBytes) + ")");
                offset += e.storedBytes;
            }
        }
    }
    file->m_dictionaryBytes = dictBytes;
    if (dictBytes > 0) {
        try {
            file->m_dictionary = std::make_shared<cache::ZstdDictionary>(
                tables.data() + (dictOffset - levelTable), dictBytes);
        } catch (const Error& e) {
            throw fail(std::string("invalid zstd dictionary: ") + e.what());
        }
    }
    return file;
}

// Version 3 (BOT_FORMAT.md "Version 3"): the tables follow the page data as one trailer. Every count
// that sizes an allocation is checked against the trailer's size first: a page entry takes at least
// a byte, a band at least its coding byte, a bit per context and its palette count, and a band
// holds at least 512 pages unless it is a level's last or the tail band, so nothing allocated here
// outgrows a small multiple of the file.
void BotFile::parseVersion3(BotFile& file, const uint8_t* h, const Source& source) {
    using namespace detail;
    const std::filesystem::path& path = file.m_path;
    auto fail = [&](const std::string& msg) -> FormatError { return FormatError(path, msg); };
    const uint64_t fileBytes = source.size;
    BotHeader& hd = file.m_header;
    const uint32_t levelCount = uint32_t(hd.levels.size());
    if (h[kFieldPageFilter] != 0) throw fail("bad page filter field " + std::to_string(h[kFieldPageFilter]) +
                                             " (version 3 names the filter per band)");
    if (get16(h + kFieldReserved0) != 0 || get64(h + kField3Reserved) != 0 || get64(h + kField3Reserved + 8) != 0)
        throw fail("reserved header fields not zero");
    const uint32_t rawBytes = file.m_pageRawBytes;
    const uint32_t prefixBytes = pagePrefixBytes(hd.channels, hd.pixelType);
    const uint32_t contexts = ransContextCount(hd.pixelType);
    uint64_t pageCount = 0, rowCount = 0, bandCount = 0;
    for (const BotLevel& l : hd.levels) {
        file.m_levelFirstPage.push_back(pageCount);
        pageCount += uint64_t(l.pagesX) * l.pagesY;
        rowCount += l.pagesY;
    }
    Bot3Bands layout = bot3Bands(hd.levels, rawBytes);
    file.m_levelFirstBand = std::move(layout.levelFirstBand);
    file.m_levelBandRows = std::move(layout.levelBandRows);
    bandCount = layout.count;
    if (get64(h + kFieldPageCount) != pageCount)
        throw fail("bad page count " + std::to_string(get64(h + kFieldPageCount)) + " (expected " +
                   std::to_string(pageCount) + ")");
    if (get64(h + kField3BandCount) != bandCount)
        throw fail("bad band count " + std::to_string(get64(h + kField3BandCount)) + " (expected " +
                   std::to_string(bandCount) + ")");
    const uint64_t trailerOffset = get64(h + kField3TrailerOffset);
    const uint64_t trailerBytes = get64(h + kField3TrailerBytes);
    if (trailerOffset < kBotHeaderBytes || trailerOffset > fileBytes || trailerBytes != fileBytes - trailerOffset)
        throw fail("bad trailer offset " + std::to_string(trailerOffset) + " or size " + std::to_string(trailerBytes) +
                   " (file has " + std::to_string(fileBytes) + " bytes)");
    const uint64_t leastTrailer = uint64_t(levelCount) * kBotLevelEntryBytes + rowCount * kBotRowEntryBytes +
                                  bandCount * (2 + (contexts + 7) / 8) + pageCount * kBot3MinPageEntryBytes;
    if (trailerBytes < leastTrailer)
        throw fail("trailer of " + std::to_string(trailerBytes) + " bytes cannot hold the tables of " +
                   std::to_string(pageCount) + " pages (at least " + std::to_string(leastTrailer) + " bytes)");

    // Bounded by the file size (checked above).
    std::vector<uint8_t> trailer{};
    trailer.resize(size_t(trailerBytes));
    if (!source.read(trailer.data(), trailer.size(), trailerOffset, path)) throw fail("truncated trailer");
    if (xxh64(trailer.data(), trailer.size(), xxh64(h, kFieldMetaChecksum, 0)) != get64(h + kFieldMetaChecksum))
        throw fail("header/trailer checksum mismatch");

    const uint8_t* at = trailer.data();
    const uint8_t* const end = trailer.data() + trailer.size();
    for (uint32_t l = 0; l < levelCount; ++l, at += kBotLevelEntryBytes)
        if (get32(at) != hd.levels[l].width || get32(at + 4) != hd.levels[l].height)
            throw fail("level table entry " + std::to_string(l) + " does not match the image size");
    const uint8_t* rowTable = at;
    at += rowCount * kBotRowEntryBytes;
    file.m_bands.resize(size_t(bandCount));
    for (uint32_t b = 0; b < bandCount; ++b) {
        {
            std::string name = "the tail band (levels " + std::to_string(layout.tailLevel) + " to " +
                               std::to_string(levelCount - 1) + ")";
            for (uint32_t l = 0; l < layout.tailLevel; ++l)
                if (b >= file.m_levelFirstBand[l] && (l + 1 == layout.tailLevel || b < file.m_levelFirstBand[l + 1]))
                    name = "band " + std::to_string(b - file.m_levelFirstBand[l]) + " of level " + std::to_string(l);
            // Bits 0-1: the page filter; bits 2-3: the last channel coded as a difference (0: none,
            // 1: channel 2, 2: channel 3), which the image must have.
            const uint32_t mode = at == end ? 0 : uint32_t(*at >> 2);
            if (at == end || (*at & 3) > 2 || mode > 2 || (mode && hd.channels <= mode + 1))
                throw fail("bad coding byte of " + name);
            file.m_bands[b].filter = PageFilter(*at++ & 3);
            file.m_bands[b].decorrelateTo = mode ? mode + 1 : 0;
            file.m_bands[b].tables = RansTableSet::parse(at, end, contexts);
            if (!file.m_bands[b].tables) throw fail("corrupt coding tables of " + name);
            // The band's constant colours: a count, then each colour's prefix bytes.
            uint32_t colours = 0;
            if (!readVarint(at, end, colours) || uint64_t(colours) * prefixBytes > uint64_t(end - at))
                throw fail("bad constant colours of " + name);
            file.m_bands[b].palette.assign(at, at + size_t(colours) * prefixBytes);
            at += size_t(colours) * prefixBytes;
        }
    }
    file.m_pages.resize(size_t(pageCount));
    const uint32_t leastRans = prefixBytes - ransPrefixInState(prefixBytes) + kRansStateBytes + kRansStateBytesB;
    uint64_t row = 0, index = 0;
    for (uint32_t l = 0; l < levelCount; ++l) {
        const BotLevel& lv = hd.levels[l];
        for (uint32_t py = 0; py < lv.pagesY; ++py, ++row) {
            uint64_t offset = get64(rowTable + row * kBotRowEntryBytes);
            for (uint32_t px = 0; px < lv.pagesX; ++px, ++index) {
                BotPageEntry& e = file.m_pages[index];
                auto truncated = [&] { return fail("truncated page table at " + pageName(l, px, py)); };
                if (at == end) throw truncated();
                const uint32_t first = *at++;
                auto next = [&](uint32_t bytes) {
                    if (uint64_t(end - at) < bytes) throw truncated();
                    uint32_t v = 0;
                    for (uint32_t k = 0; k < bytes; ++k) v |= uint32_t(*at++) << (8 * k);
                    return v;
                };
                if (first >= kBot3EntryConstant && first < kBot3EntryRaw) {
                    // No stored bytes: the entry names one of the band's constant colours, which the
                    // trailer's checksum covers.
                    uint32_t colour = 0;
                    if (first < kBot3EntryConstant2) {
                        colour = first - kBot3EntryConstant;
                    } else if (first < kBot3EntryConstant3) {
                        colour = kBot3ConstantShortColours + ((first & 0x0f) << 8 | next(1));
                    } else if (first < kBot3EntryConstant3 + 8) {
                        colour = kBot3ConstantShortColours + kBot3ConstantMidColours + ((first & 0x07) << 16 | next(2));
                    } else {
                        throw fail("bad page entry " + std::to_string(first) + " of " + pageName(l, px, py));
                    }
                    const Band& band = file.m_bands[file.m_levelFirstBand[l] + py / file.m_levelBandRows[l]];
                    if (uint64_t(colour) * prefixBytes >= band.palette.size())
                        throw fail("bad constant colour " + std::to_string(colour) + " of " + pageName(l, px, py));
                    e.kind = BotPageKind::Constant;
                    e.checksum = colour;  // the colour's index
                    e.storedBytes = 0;
                    e.offsetBytes = offset;
                    continue;
                }
                uint32_t stored = 0;
                if (first == kBot3EntryRaw) {
                    // Only a raw page has a checksum in its entry; a rANS page's rides in its states.
                    e.kind = BotPageKind::Raw;
                    stored = rawBytes;
                    e.checksum = next(2);
                } else {
                    e.kind = BotPageKind::Rans;
                    stored = leastRans + (first < kBot3EntryRansLong
                                              ? first
                                              : kBot3RansShortSizes + ((first & 0x3f) << 8 | next(1)));
                    if (stored >= rawBytes)
                        throw fail("bad stored size " + std::to_string(stored) + " of rans " + pageName(l, px, py));
                }
                e.storedBytes = uint16_t(stored);
                e.offsetBytes = offset;
                if (offset < kBotHeaderBytes || offset > trailerOffset || stored > trailerOffset - offset)
                    throw fail(pageName(l, px, py) + " lies outside the page data (offset " + std::to_string(offset) +
                               ", " + std::to_string(stored) + " bytes, page data ends at " +
                               std::to_string(trailerOffset) + ")");
                offset += stored;
            }
        }
    }
    if (at != end) throw fail(std::to_string(end - at) + " unexpected bytes at the end of the trailer");
    file.m_pageFilter = file.m_bands.empty() ? PageFilter::None : file.m_bands[0].filter;
}

uint64_t BotFile::pageIndex(uint32_t level, uint32_t pageX, uint32_t pageY) const {
    if (level >= m_header.levels.size() || pageX >= m_header.levels[level].pagesX ||
        pageY >= m_header.levels[level].pagesY)
        throw std::out_of_range(m_path.string() + ": no " + pageName(level, pageX, pageY));
    return m_levelFirstPage[level] + uint64_t(pageY) * m_header.levels[level].pagesX + pageX;
}

uint64_t BotFile::readPage(int fd, uint32_t level, uint32_t pageX, uint32_t pageY, float* dst) const {
    const uint64_t index = pageIndex(level, pageX, pageY);
    const BotPageEntry& e = m_pages[index];
    PageScratch& scratch = pageScratch();
    if (!preadAll(fd, scratch.stored.data(), e.storedBytes, e.offsetBytes, m_path))
        throw FormatError(m_path, pageName(level, pageX, pageY) + " extends past end of file (file truncated?)");
    return decodePage(index, level, pageX, pageY, scratch.stored.data(), dst);
}

const BotPageEntry& BotFile::entryWithin(uint64_t index, size_t byteCount, uint32_t level, uint32_t pageX,
                                         uint32_t pageY) const {
    const BotPageEntry& e = m_pages[index];
    if (e.offsetBytes > byteCount || e.storedBytes > byteCount - e.offsetBytes)
        throw FormatError(m_path, pageName(level, pageX, pageY) + " extends past end of file");
    return e;
}

uint64_t BotFile::readPageFromMemory(const uint8_t* bytes, size_t byteCount, uint32_t level, uint32_t pageX,
                                     uint32_t pageY, float* dst) const {
    const uint64_t index = pageIndex(level, pageX, pageY);
    const BotPageEntry& e = entryWithin(index, byteCount, level, pageX, pageY);
    return decodePage(index, level, pageX, pageY, bytes + e.offsetBytes, dst);
}

uint64_t BotFile::readPageFromMapping(const uint8_t* bytes, size_t byteCount, uint32_t level, uint32_t pageX,
                                      uint32_t pageY, float* dst) const {
    const uint64_t index = pageIndex(level, pageX, pageY);
    const BotPageEntry& e = entryWithin(index, byteCount, level, pageX, pageY);
    PageScratch& scratch = pageScratch();
    if (!detail::copyFromMapping(scratch.stored.data(), bytes + e.offsetBytes, e.storedBytes))
        throw IoError(m_path, pageName(level, pageX, pageY) + " lies past the end of the file, which became "
                              "shorter than its " + std::to_string(m_fileBytes) +
                              " bytes while mapped (truncated in place?)");
    return decodePage(index, level, pageX, pageY, scratch.stored.data(), dst);
}

size_t BotFile::memoryBytes() const {
    size_t bandBytes = m_bands.capacity() * sizeof(Band) +
                       (m_levelFirstBand.capacity() + m_levelBandRows.capacity()) * sizeof(uint32_t);
    for (const Band& b : m_bands) bandBytes += (b.tables ? b.tables->memoryBytes() : 0) + b.palette.capacity();
    return sizeof(BotFile) + m_path.native().capacity() + m_header.levels.capacity() * sizeof(BotLevel) +
           m_levelFirstPage.capacity() * sizeof(uint64_t) + m_pages.capacity() * sizeof(BotPageEntry) +
           (m_dictionary ? m_dictionary->memoryBytes() : 0) + bandBytes;
}

uint64_t BotFile::decodePage(uint64_t index, uint32_t level, uint32_t pageX, uint32_t pageY, const uint8_t* stored,
                             float* dst) const {
    const BotPageEntry& e = m_pages[index];
    PageScratch& scratch = pageScratch();
    if (m_version == detail::kBotVersion3) {
        const Band& band = m_bands[m_levelFirstBand[level] + pageY / m_levelBandRows[level]];
        const uint8_t* packed = stored;
        if (e.kind == BotPageKind::Constant) {
            const uint32_t prefix = detail::pagePrefixBytes(m_header.channels, m_header.pixelType);
            std::memcpy(scratch.packed.data(), band.palette.data() + size_t(e.checksum) * prefix, prefix);
            std::memset(scratch.packed.data() + prefix, 0, m_pageRawBytes - prefix);
            detail::unpackPageToFloat(scratch.packed.data(), m_header.channels, m_header.pixelType, band.filter, dst);
            return 0;
        }
        if (e.kind == BotPageKind::Rans) {
            uint16_t check = 0;
            if (!band.tables->decode(stored, e.storedBytes, m_header.channels, m_header.pixelType,
                                     scratch.packed.data(), check))
                throw FormatError(m_path, "corrupt rANS data in " + pageName(level, pageX, pageY));
            packed = scratch.packed.data();
            if ((page3Checksum(packed, m_pageRawBytes, index, e.kind) & ((1u << detail::kRansCheckBits) - 1)) != check)
                throw FormatError(m_path, "checksum mismatch in " + pageName(level, pageX, pageY));
        } else if (page3Checksum(stored, e.storedBytes, index, e.kind) != e.checksum) {
            throw FormatError(m_path, "checksum mismatch in " + pageName(level, pageX, pageY));
        }
        if (band.decorrelateTo) {
            if (packed != scratch.packed.data()) {
                std::memcpy(scratch.packed.data(), packed, m_pageRawBytes);
                packed = scratch.packed.data();
            }
            detail::recorrelateChannels(scratch.packed.data(), m_header.channels, m_header.pixelType, band.decorrelateTo);
        }
        detail::unpackPageToFloat(packed, m_header.channels, m_header.pixelType, band.filter, dst);
        return e.storedBytes;
    }
    if (pageChecksum(stored, e.storedBytes, index, e.kind) != e.checksum)
        throw FormatError(m_path, "checksum mismatch in " + pageName(level, pageX, pageY));
    const uint8_t* packed = stored;
    if (e.kind != BotPageKind::Raw) {
        // The prefix (texel 0 of every channel) is stored as it is; zstd codes the rest.
        const uint32_t prefix = detail::pagePrefixBytes(m_header.channels, m_header.pixelType);
        uint8_t* out = scratch.packed.data();
        std::memcpy(out, stored, prefix);
        if (!scratch.decompressorFor(m_dictionary)
                 .decompress(zstdFormOf(e.kind), stored + prefix, e.storedBytes - prefix, out + prefix,
                             m_pageRawBytes - prefix))
            throw FormatError(m_path, std::string("corrupt compressed data (") + pageKindName(e.kind) + " page) in " +
                                          pageName(level, pageX, pageY));
        packed = out;
    }
    detail::unpackPageToFloat(packed, m_header.channels, m_header.pixelType, m_pageFilter, dst);
    return e.storedBytes;
}

// ---------------------------------------------------------------------------------------- writing

struct BotWriter::Impl {
    std::filesystem::path target;
    std::unique_ptr<cache::OutputFile> out;  // the temporary file until finish() publishes it
    int fd = -1;                             // out's descriptor, for positioned writes
    bool finished = false;
    BotHeader header;
    BotWriteOptions options;
    MipFilter mipFilter = MipFilter::Box;
    uint32_t rawBytes = 0;
    std::vector<uint64_t> levelFirstPage, levelFirstRow;
    std::vector<uint64_t> rowOffsets;
    std::vector<uint32_t> pageSizes, pageChecksums;
    uint64_t rowTableOffset = 0, pageTableOffset = 0, dictOffset = 0, cursor = 0;

    struct LevelRows {
        std::vector<float> rows;  // up to kPageSizeTexels rows being gathered
        uint32_t filled = 0;      // rows in `rows`
        uint32_t nextRow = 0;     // next row expected
        bool linearLight = false;
    };
    std::vector<LevelRows> levels;

    // The page coding (filter, dictionary) is settled from the first pages: their rows are kept as
    // quantised samples until kDictionarySampleBytes of them exist (or the image ends).
    bool codingDecided = false;
    PageFilter pageFilter = PageFilter::None;
    uint32_t prefixBytes = 0;
    std::shared_ptr<const cache::ZstdDictionary> dictionary;
    BotDictionary dictionaryKind = BotDictionary::None;
    cache::ZstdTuning tuning;  // how pages are compressed (tuningFor(dictionaryKind))
    struct PendingRow {
        uint32_t level, pageY;
        std::vector<uint8_t> samples;  // pagesX pages of rawBytes bytes of host-order samples
    };
    std::vector<PendingRow> pending;
    size_t pendingBytes = 0;
    std::optional<tbb::enumerable_thread_specific<std::unique_ptr<cache::ZstdCompressor>>> compressors;
    std::vector<uint8_t> rowBuffer;
    std::vector<uint8_t> bandPacked, bandContexts;  // version 3: the band being coded (encodeBand)
    std::vector<uint32_t> rowSizes;

    // Gathers page (px) of a row band (nRows rows of level `level`) into a padded 8x8 block and
    // quantises it to host-order samples (rawBytes bytes).
    void quantizePage(uint32_t level, const float* rows, uint32_t nRows, uint32_t px, bool linear,
                      uint8_t* samples) const {
        const uint32_t ch = header.channels;
        const uint32_t w = header.levels[level].width;
        float texels[kPageTexels * kMaxChannels];
        for (uint32_t y = 0; y < kPageSizeTexels; ++y) {
            const float* src = rows + size_t(std::min(y, nRows - 1)) * w * ch;
            for (uint32_t x = 0; x < kPageSizeTexels; ++x) {
                const uint32_t sx = std::min(px * kPageSizeTexels + x, w - 1);
                std::memcpy(texels + (y * kPageSizeTexels + x) * ch, src + size_t(sx) * ch, ch * sizeof(float));
            }
        }
        detail::quantizePage(texels, ch, header.pixelType, header.colorSpace, options.alphaChannel, linear, samples);
    }

    cache::ZstdCompressor& compressor() {
        auto& slot = compressors->local();
        if (!slot) {
            slot = std::make_unique<cache::ZstdCompressor>(options.compressionLevel, dictionary);
            slot->tune(tuning);
        }
        return *slot;
    }

    // Stores one packed page into dst (capacity >= rawBytes): the prefix as it is, then zstd's output
    // in its smallest form; the raw page when that is not smaller. Returns the page-table size field
    // and sets `storedBytes`.
    uint32_t storePage(cache::ZstdCompressor& z, const uint8_t* packed, uint8_t* dst, uint32_t& storedBytes) const {
        std::memcpy(dst, packed, prefixBytes);
        cache::ZstdForm form = cache::ZstdForm::Frame;
        const size_t n = z.compressCompact(packed + prefixBytes, rawBytes - prefixBytes, dst + prefixBytes,
                                           rawBytes - 1 - prefixBytes, form);
        if (n == 0) {
            std::memcpy(dst, packed, rawBytes);
            storedBytes = rawBytes;
            return uint32_t(BotPageKind::Raw) << detail::kBotPageKindShift;
        }
        storedBytes = prefixBytes + uint32_t(n);
        return uint32_t(pageKindOf(form)) << detail::kBotPageKindShift | storedBytes;
    }

    // Writes page rows whose packed pages are in `packedRows` (each pagesX * rawBytes).
    void writeRows(const std::vector<std::pair<uint32_t, uint32_t>>& rowsToWrite,
                   const std::vector<const uint8_t*>& packedRows) {
        // Index every page of every row, compress them all in parallel, then write row by row.
        std::vector<uint64_t> firstPageOfRow(rowsToWrite.size() + 1, 0);
        for (size_t r = 0; r < rowsToWrite.size(); ++r)
            firstPageOfRow[r + 1] = firstPageOfRow[r] + header.levels[rowsToWrite[r].first].pagesX;
        const uint64_t total = firstPageOfRow.back();
        const size_t slotBytes = rawBytes;
        rowBuffer.resize(size_t(total) * slotBytes);
        rowSizes.resize(size_t(total));
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, total, 16), [&](const tbb::blocked_range<uint64_t>& rg) {
            cache::ZstdCompressor& z = compressor();
            for (uint64_t k = rg.begin(); k != rg.end(); ++k) {
                const size_t r = size_t(std::upper_bound(firstPageOfRow.begin(), firstPageOfRow.end(), k) -
                                        firstPageOfRow.begin() - 1);
                const uint64_t px = k - firstPageOfRow[r];
                const uint8_t* packed = packedRows[r] + px * rawBytes;
                uint8_t* dst = rowBuffer.data() + k * slotBytes;
                uint32_t stored = 0;
                const uint32_t sizeField = storePage(z, packed, dst, stored);
                const auto [level, pageY] = rowsToWrite[r];
                const uint64_t index = levelFirstPage[level] + uint64_t(pageY) * header.levels[level].pagesX + px;
                rowSizes[k] = stored;
                pageSizes[index] = sizeField;
                pageChecksums[index] = pageChecksum(dst, stored, index, BotPageKind(sizeField >> detail::kBotPageKindShift));
            }
        });
        // Close the gaps between slots and write everything with one call.
        size_t packedEnd = 0;
        for (size_t r = 0; r < rowsToWrite.size(); ++r) {
            const auto [level, pageY] = rowsToWrite[r];
            rowOffsets[levelFirstRow[level] + pageY] = cursor + packedEnd;
            for (uint64_t k = firstPageOfRow[r]; k < firstPageOfRow[r + 1]; ++k) {
                const uint32_t n = rowSizes[k];
                std::memmove(rowBuffer.data() + packedEnd, rowBuffer.data() + k * slotBytes, n);
                packedEnd += n;
            }
        }
        pwriteAll(fd, rowBuffer.data(), packedEnd, cursor, target);
        cursor += packedEnd;
    }

    // ------------------------------------------------------------------------------ version 3

    // Each level's band being gathered: its page rows as quantised samples, until the band's last
    // row arrives; then the band is coded and written (encodeBand).
    std::vector<uint32_t> levelFirstBand, levelBandRows;
    std::vector<std::vector<uint8_t>> bandSamples;  // per level
    // The tail band (the small levels, BOT_FORMAT.md "Bands"): all their pages, level after level,
    // coded in finish().
    uint32_t tailLevel = 0;
    std::vector<size_t> tailLevelOffset;  // where each tail level's pages start in tailSamples
    std::vector<uint8_t> tailSamples;
    std::vector<std::vector<uint8_t>> bandTables;   // per band: filter byte and stored tables
    uint32_t contexts = 0;
    uint32_t symbolsPerPage = 0;

    void emitPageRow3(uint32_t level, uint32_t pageY, const float* rows, uint32_t nRows, bool linear) {
        const BotLevel& lv = header.levels[level];
        if (level >= tailLevel) {
            if (tailSamples.empty()) tailSamples.resize(tailLevelOffset.back());
            uint8_t* row = tailSamples.data() + tailLevelOffset[level - tailLevel] + size_t(pageY) * lv.pagesX * rawBytes;
            for (uint32_t px = 0; px < lv.pagesX; ++px)
                quantizePage(level, rows, nRows, px, linear, row + size_t(px) * rawBytes);
            return;
        }
        const uint32_t bandRows = levelBandRows[level];
        const uint32_t rowInBand = pageY % bandRows;
        const uint32_t rowsInBand = std::min(bandRows, lv.pagesY - (pageY - rowInBand));
        std::vector<uint8_t>& samples = bandSamples[level];
        if (rowInBand == 0) samples.resize(size_t(rowsInBand) * lv.pagesX * rawBytes);
        uint8_t* row = samples.data() + size_t(rowInBand) * lv.pagesX * rawBytes;
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, lv.pagesX, 8), [&](const tbb::blocked_range<uint32_t>& rg) {
            for (uint32_t px = rg.begin(); px != rg.end(); ++px)
                quantizePage(level, rows, nRows, px, linear, row + size_t(px) * rawBytes);
        });
        if (rowInBand + 1 == rowsInBand)
            encodeBand(levelFirstBand[level] + pageY / bandRows, {{level, pageY - rowInBand, rowsInBand}}, samples.data());
        if (pageY + 1 == lv.pagesY) {
            samples.clear();
            samples.shrink_to_fit();
        }
    }

    // Symbol counts of the band's pages (every `step`-th) packed with `filter`. Integer sums, so the
    // result does not depend on how the pages were split among threads.
    detail::RansHistogram bandHistogram(const uint8_t* samples, uint64_t pages, uint64_t step, PageFilter filter,
                                        uint32_t decorrelateTo, uint8_t* packedOut,
                                        uint8_t* contextsOut = nullptr) const {
        tbb::enumerable_thread_specific<detail::RansHistogram> partial(detail::RansHistogram{contexts});
        const uint64_t count = (pages + step - 1) / step;
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 64), [&](const tbb::blocked_range<uint64_t>& rg) {
            detail::RansHistogram& hist = partial.local();
            alignas(16) uint8_t local[kPageTexels * kMaxChannels * 4];
            for (uint64_t k = rg.begin(); k != rg.end(); ++k) {
                uint8_t* packed = packedOut ? packedOut + k * step * rawBytes : local;
                detail::packPage(samples + k * step * rawBytes, header.channels, header.pixelType, filter, packed);
                detail::decorrelateChannels(packed, header.channels, header.pixelType, decorrelateTo);
                detail::ransCount(packed, header.channels, header.pixelType, hist,
                                  contextsOut ? contextsOut + k * step * symbolsPerPage : nullptr);
            }
        });
        detail::RansHistogram total(contexts);
        for (const detail::RansHistogram& h : partial) total.add(h);
        return total;
    }

    // Page rows [firstRow, firstRow + rows) of a level.
    struct Segment {
        uint32_t level, firstRow, rows;
    };

    // Codes band `band`, the page rows of `segments` whose samples lie back to back in `samples`:
    // picks the filter and channel coding whose residuals code smaller (measured on a sample of the
    // pages of large bands), fits the band's tables to all its pages, codes every page (constant,
    // rANS or raw, whichever is smallest) and writes them row by row.
    void encodeBand(uint32_t band, const std::vector<Segment>& segments, const uint8_t* samples) {
        std::vector<uint64_t> segmentStart = {0};  // first page of each segment, then the total
        for (const Segment& g : segments)
            segmentStart.push_back(segmentStart.back() + uint64_t(g.rows) * header.levels[g.level].pagesX);
        const uint64_t pages = segmentStart.back();
        // The page index of the band's k-th page.
        auto indexOf = [&](uint64_t k) {
            const size_t g = size_t(std::upper_bound(segmentStart.begin(), segmentStart.end(), k) - segmentStart.begin() - 1);
            const Segment& seg = segments[g];
            const uint32_t pagesX = header.levels[seg.level].pagesX;
            const uint64_t inSegment = k - segmentStart[g];
            return levelFirstPage[seg.level] + (uint64_t(seg.firstRow) + inSegment / pagesX) * pagesX + inSegment % pagesX;
        };
        PageFilter filter = options.pageFilter.value_or(PageFilter::Med);
        uint32_t decorrelateTo = 0;
        std::vector<PageFilter> filters = {PageFilter::Med, PageFilter::Mean};
        if (options.pageFilter) filters = {*options.pageFilter};
        std::vector<uint32_t> modes = {0};
        if (header.channels >= 3) modes.push_back(2);
        if (header.channels >= 4) modes.push_back(3);
        if (filters.size() * modes.size() > 1) {
            // Every 16th page of a large band decides as well as every 4th (the same choices on the
            // 4096^2 suite images) in a quarter of the time.
            const uint64_t step = pages >= 4096 ? 16 : pages >= 1024 ? 4 : 1;
            double best = HUGE_VAL;
            for (PageFilter f : filters)
                for (uint32_t d : modes) {
                    const double bits = bandHistogram(samples, pages, step, f, d, nullptr).codedBits();
                    if (bits < best) {
                        best = bits;
                        filter = f;
                        decorrelateTo = d;
                    }
                }
        }
        // Kept from band to band (every byte is written before it is read), so that the pages of
        // each band are not faulted in and zeroed again.
        std::vector<uint8_t>& packed = bandPacked;
        std::vector<uint8_t>& pageContexts = bandContexts;
        packed.resize(std::max(packed.size(), size_t(pages) * rawBytes));
        pageContexts.resize(std::max(pageContexts.size(), size_t(pages) * symbolsPerPage));
        const auto tables = detail::RansTableSet::fit(
            bandHistogram(samples, pages, 1, filter, decorrelateTo, packed.data(), pageContexts.data()));
        std::vector<uint8_t>& stored = bandTables[band];
        stored.push_back(uint8_t(uint32_t(filter) | (decorrelateTo ? decorrelateTo - 1 : 0) << 2));
        tables->serialize(stored);

        rowBuffer.resize(size_t(pages) * rawBytes);
        rowSizes.resize(size_t(pages));
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, pages, 16), [&](const tbb::blocked_range<uint64_t>& rg) {
            for (uint64_t k = rg.begin(); k != rg.end(); ++k) {
                const uint8_t* page = packed.data() + k * rawBytes;
                uint8_t* dst = rowBuffer.data() + k * rawBytes;
                BotPageKind kind = BotPageKind::Rans;
                size_t n = 0;
                if (std::all_of(page + prefixBytes, page + rawBytes, [](uint8_t b) { return b == 0; })) {
                    kind = BotPageKind::Constant;  // its colour goes to the band's palette below
                    n = 0;
                } else {
                    const uint16_t check = uint16_t(page3Checksum(page, rawBytes, indexOf(k), kind));
                    n = tables->encode(page, header.channels, header.pixelType, check, dst, rawBytes - 1,
                                       pageContexts.data() + k * symbolsPerPage);
                    if (n == 0) {
                        kind = BotPageKind::Raw;
                        n = rawBytes;
                        std::memcpy(dst, page, n);
                    }
                }
                const uint64_t index = indexOf(k);
                rowSizes[k] = uint32_t(n);
                pageSizes[index] = uint32_t(n) << detail::kBot3KindBits | uint32_t(bot3KindOf(kind));
                pageChecksums[index] = kind == BotPageKind::Raw ? page3Checksum(dst, n, index, kind) : 0;
            }
        });
        // The band's constant colours in the order their first page comes, each stored once; a
        // constant page's entry names its colour.
        std::map<std::vector<uint8_t>, uint32_t> colours;
        std::vector<uint8_t> palette;
        for (uint64_t k = 0; k < pages; ++k) {
            const uint64_t index = indexOf(k);
            if ((pageSizes[index] & 3) != uint32_t(detail::Bot3Kind::Constant)) continue;
            const uint8_t* page = packed.data() + k * rawBytes;
            const auto [it, added] =
                colours.try_emplace(std::vector<uint8_t>(page, page + prefixBytes), uint32_t(colours.size()));
            if (added) palette.insert(palette.end(), page, page + prefixBytes);
            pageSizes[index] = it->second << detail::kBot3KindBits | uint32_t(detail::Bot3Kind::Constant);
        }
        appendVarint(stored, uint32_t(colours.size()));
        stored.insert(stored.end(), palette.begin(), palette.end());
        size_t packedEnd = 0;
        for (size_t g = 0; g < segments.size(); ++g) {
            const Segment& seg = segments[g];
            const uint32_t pagesX = header.levels[seg.level].pagesX;
            for (uint32_t r = 0; r < seg.rows; ++r) {
                rowOffsets[levelFirstRow[seg.level] + seg.firstRow + r] = cursor + packedEnd;
                const uint64_t first = segmentStart[g] + uint64_t(r) * pagesX;
                for (uint64_t k = first; k < first + pagesX; ++k) {
                    std::memmove(rowBuffer.data() + packedEnd, rowBuffer.data() + k * rawBytes, rowSizes[k]);
                    packedEnd += rowSizes[k];
                }
            }
        }
        pwriteAll(fd, rowBuffer.data(), packedEnd, cursor, target);
        cursor += packedEnd;
    }

    // The header fields both versions share (BOT_FORMAT.md: bytes 0–39 but the page filter).
    void putSharedHeader(uint8_t* h, uint32_t version) const {
        using namespace detail;
        std::memcpy(h, kBotMagic, sizeof kBotMagic);
        put32(h + kFieldVersion, version);
        put32(h + kFieldHeaderBytes, kBotHeaderBytes);
        put32(h + kFieldWidth, header.width);
        put32(h + kFieldHeight, header.height);
        put32(h + kFieldChannels, header.channels);
        h[kFieldPixelType] = uint8_t(header.pixelType);
        h[kFieldColorSpace] = uint8_t(header.colorSpace);
        h[kFieldWrapS] = uint8_t(header.wrapS);
        h[kFieldWrapT] = uint8_t(header.wrapT);
        h[kFieldMipFilter] = uint8_t(mipFilter);
        put32(h + kFieldLevelCount, uint32_t(header.levels.size()));
    }

    // The trailer (level, row, band and page tables) after the page data, then the header.
    void writeTables3() {
        using namespace detail;
        std::vector<uint8_t> trailer;
        uint8_t word[8];
        for (const BotLevel& l : header.levels) {
            put32(word, l.width);
            put32(word + 4, l.height);
            trailer.insert(trailer.end(), word, word + 8);
        }
        for (uint64_t offset : rowOffsets) {
            put64(word, offset);
            trailer.insert(trailer.end(), word, word + 8);
        }
        for (const std::vector<uint8_t>& band : bandTables) trailer.insert(trailer.end(), band.begin(), band.end());
        // Page entries (bot_layout.h): most rANS pages of up to 134 bytes (RGB 8-bit) and most
        // constant pages take one byte.
        const uint32_t leastRans = prefixBytes - ransPrefixInState(prefixBytes) + kRansStateBytes + kRansStateBytesB;
        for (size_t p = 0; p < pageSizes.size(); ++p) {
            const uint32_t v = pageSizes[p] >> kBot3KindBits;
            switch (Bot3Kind(pageSizes[p] & 3)) {
                case Bot3Kind::Raw:
                    trailer.push_back(uint8_t(kBot3EntryRaw));
                    put16(word, uint16_t(pageChecksums[p]));
                    trailer.insert(trailer.end(), word, word + 2);
                    break;
                case Bot3Kind::Rans: {
                    const uint32_t d = v - leastRans;
                    if (d < kBot3RansShortSizes) {
                        trailer.push_back(uint8_t(d));
                    } else {
                        trailer.push_back(uint8_t(kBot3EntryRansLong | (d - kBot3RansShortSizes) >> 8));
                        trailer.push_back(uint8_t(d - kBot3RansShortSizes));
                    }
                    break;
                }
                case Bot3Kind::Constant:
                    if (v < kBot3ConstantShortColours) {
                        trailer.push_back(uint8_t(kBot3EntryConstant + v));
                    } else if (v < kBot3ConstantShortColours + kBot3ConstantMidColours) {
                        const uint32_t d = v - kBot3ConstantShortColours;
                        trailer.push_back(uint8_t(kBot3EntryConstant2 | d >> 8));
                        trailer.push_back(uint8_t(d));
                    } else {
                        const uint32_t d = v - kBot3ConstantShortColours - kBot3ConstantMidColours;
                        trailer.push_back(uint8_t(kBot3EntryConstant3 | d >> 16));
                        trailer.push_back(uint8_t(d));
                        trailer.push_back(uint8_t(d >> 8));
                    }
                    break;
            }
        }
        uint8_t h[kBotHeaderBytes] = {};
        putSharedHeader(h, kBotVersion3);
        put64(h + kField3TrailerOffset, cursor);
        put64(h + kField3TrailerBytes, trailer.size());
        put64(h + kField3BandCount, bandTables.size());
        put64(h + kFieldPageCount, pageSizes.size());
        put64(h + kFieldMetaChecksum, xxh64(trailer.data(), trailer.size(), xxh64(h, kFieldMetaChecksum, 0)));
        pwriteAll(fd, trailer.data(), trailer.size(), cursor, target);
        cursor += trailer.size();
        pwriteAll(fd, h, kBotHeaderBytes, 0, target);
    }

    // ------------------------------------------------------------------------------ version 2

    void emitPageRow(uint32_t level, uint32_t pageY, const float* rows, uint32_t nRows, bool linear) {
        if (options.version == detail::kBotVersion3) return emitPageRow3(level, pageY, rows, nRows, linear);
        const uint32_t pagesX = header.levels[level].pagesX;
        std::vector<uint8_t> buffer(size_t(pagesX) * rawBytes);
        if (!codingDecided) {
            tbb::parallel_for(tbb::blocked_range<uint32_t>(0, pagesX, 8), [&](const tbb::blocked_range<uint32_t>& rg) {
                for (uint32_t px = rg.begin(); px != rg.end(); ++px)
                    quantizePage(level, rows, nRows, px, linear, buffer.data() + size_t(px) * rawBytes);
            });
            pendingBytes += buffer.size();
            pending.push_back({level, pageY, std::move(buffer)});
            if (pendingBytes >= kDictionarySampleBytes) decideCoding();
            return;
        }
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, pagesX, 8), [&](const tbb::blocked_range<uint32_t>& rg) {
            alignas(16) uint8_t samples[kPageTexels * kMaxChannels * 4];
            for (uint32_t px = rg.begin(); px != rg.end(); ++px) {
                quantizePage(level, rows, nRows, px, linear, samples);
                detail::packPage(samples, header.channels, header.pixelType, pageFilter,
                                 buffer.data() + size_t(px) * rawBytes);
            }
        });
        writeRows({{level, pageY}}, {buffer.data()});
    }

    // Every pending page packed with `filter`, back to back.
    std::vector<uint8_t> packPending(PageFilter filter) const {
        std::vector<uint8_t> out(pendingBytes);
        size_t at = 0;
        for (const PendingRow& row : pending) {
            const uint32_t pagesX = header.levels[row.level].pagesX;
            tbb::parallel_for(tbb::blocked_range<uint32_t>(0, pagesX, 8), [&](const tbb::blocked_range<uint32_t>& rg) {
                for (uint32_t px = rg.begin(); px != rg.end(); ++px)
                    detail::packPage(row.samples.data() + size_t(px) * rawBytes, header.channels, header.pixelType,
                                     filter, out.data() + at + size_t(px) * rawBytes);
            });
            at += row.samples.size();
        }
        return out;
    }

    // A dictionary of `kind` (Trained: zstd's trainer; Literal: cache::buildZstdLiteralDictionary)
    // built from the zstd-coded part of every `step`-th page of `pages`. Empty when zstd cannot build it.
    std::vector<uint8_t> buildDictionary(BotDictionary kind, const std::vector<uint8_t>& pages, size_t step) const {
        const size_t bodyBytes = rawBytes - prefixBytes;
        std::vector<uint8_t> bodies;
        for (size_t off = 0; off + rawBytes <= pages.size(); off += step * rawBytes)
            bodies.insert(bodies.end(), pages.begin() + ptrdiff_t(off + prefixBytes), pages.begin() + ptrdiff_t(off + rawBytes));
        const std::vector<size_t> sizes(bodies.size() / bodyBytes, bodyBytes);
        if (kind == BotDictionary::Trained)
            return cache::trainZstdDictionary(bodies.data(), sizes.data(), sizes.size(),
                                              std::clamp<size_t>(pendingBytes / 32, 2048, 16384));
        return cache::buildZstdLiteralDictionary(bodies.data(), sizes.data(), sizes.size(), bodyBytes,
                                                 options.compressionLevel);
    }

    // With the literal dictionary pages are residuals, which rarely repeat: short matches cost more
    // in sequence codes than they save, and zstd's fast level -7 with Huffman-coded literals codes
    // them as small as level 1 in half the time (BOT_FORMAT.md "Compression").
    cache::ZstdTuning tuningFor(BotDictionary kind) const {
        if (kind == BotDictionary::Literal) return {-7, 7, true};
        return {options.compressionLevel, 0, false};
    }

    std::shared_ptr<const cache::ZstdDictionary> digest(const std::vector<uint8_t>& bytes) const {
        if (bytes.empty()) return nullptr;
        try {
            return std::make_shared<cache::ZstdDictionary>(bytes.data(), bytes.size(), options.compressionLevel);
        } catch (const Error&) {
            return nullptr;  // zstd refused it: coded without
        }
    }

    // The file's expected page bytes when coded with `candidate` (or no dictionary) and
    // `candidateTuning`: the dictionary, plus the bytes stored for every `step`-th page of `pages`
    // from page `first`, scaled to the file's page count.
    double expectedBytesWith(const std::shared_ptr<const cache::ZstdDictionary>& candidate,
                             const cache::ZstdTuning& candidateTuning, const std::vector<uint8_t>& pages, size_t first,
                             size_t step) const {
        cache::ZstdCompressor z(options.compressionLevel, candidate);
        z.tune(candidateTuning);
        std::vector<uint8_t> dst(rawBytes);
        uint64_t stored = 0, count = 0;
        for (size_t off = first * rawBytes; off + rawBytes <= pages.size(); off += step * rawBytes, ++count) {
            uint32_t n = 0;
            storePage(z, pages.data() + off, dst.data(), n);
            stored += n;
        }
        const double perPage = count ? double(stored) / double(count) : 0.0;
        return double(candidate ? candidate->bytes().size() : 0) + perPage * double(pageSizes.size());
    }

    // Settles the page filter and the dictionary from the pending pages by coding them. Filters:
    // MED and the mean (unless the options name one). Dictionaries: none, zstd's trained one, or one
    // whose literal table is fitted to the residuals (cache::buildZstdLiteralDictionary), which
    // codes noisy 8-bit pages smaller. Each candidate dictionary is built from the even pages and
    // measured on the odd ones, so that one holding copies of its training pages is not credited
    // with matching them; the winner is used as measured. The trials run in parallel; each is a
    // pure function of the pending pages, so the choice does not depend on the thread count.
    void decideCoding() {
        codingDecided = true;
        const size_t pageCount = pendingBytes / rawBytes;
        std::vector<PageFilter> filters = {PageFilter::Med, PageFilter::Mean};
        if (options.pageFilter) filters = {*options.pageFilter};
        // Too few samples make a dictionary cost more than it saves.
        const bool enoughPages = pageCount >= 64 && pendingBytes >= 16 * 1024;
        std::vector<BotDictionary> kinds = {BotDictionary::None};
        if (enoughPages && options.dictionary == BotDictionary::Auto)
            kinds = {BotDictionary::None, BotDictionary::Trained, BotDictionary::Literal};
        else if (enoughPages && options.dictionary != BotDictionary::None)
            kinds = {options.dictionary};

        std::vector<std::vector<uint8_t>> packedByFilter(filters.size());
        tbb::parallel_for(size_t(0), filters.size(),
                          [&](size_t f) { packedByFilter[f] = packPending(filters[f]); });
        struct Trial {
            size_t filter;
            BotDictionary kind;
            std::shared_ptr<const cache::ZstdDictionary> dictionary;
            double bytes = HUGE_VAL;
        };
        std::vector<Trial> trials;
        for (size_t f = 0; f < filters.size(); ++f)
            for (BotDictionary kind : kinds) trials.push_back({f, kind, nullptr});
        if (trials.size() > 1) {
            const bool heldOut = kinds.size() > 1 || kinds[0] != BotDictionary::None;
            tbb::parallel_for(size_t(0), trials.size(), [&](size_t t) {
                Trial& trial = trials[t];
                const std::vector<uint8_t>& pages = packedByFilter[trial.filter];
                if (trial.kind != BotDictionary::None) {
                    trial.dictionary = digest(buildDictionary(trial.kind, pages, 2));
                    if (!trial.dictionary) return;  // zstd could not build it: not a candidate
                }
                trial.bytes = heldOut ? expectedBytesWith(trial.dictionary, tuningFor(trial.kind), pages, 1, 2)
                                      : expectedBytesWith(trial.dictionary, tuningFor(trial.kind), pages, 0, 1);
            });
        } else if (trials[0].kind != BotDictionary::None) {
            trials[0].dictionary = digest(buildDictionary(trials[0].kind, packedByFilter[0], 1));
        }
        size_t best = 0;
        for (size_t t = 1; t < trials.size(); ++t)
            if (trials[t].bytes < trials[best].bytes) best = t;
        pageFilter = filters[trials[best].filter];
        const std::vector<uint8_t> bestPages = std::move(packedByFilter[trials[best].filter]);
        dictionary = trials[best].dictionary;
        dictionaryKind = dictionary ? trials[best].kind : BotDictionary::None;
        tuning = tuningFor(dictionaryKind);
        if (dictionary) {
            pwriteAll(fd, dictionary->bytes().data(), dictionary->bytes().size(), cursor, target);
            cursor += dictionary->bytes().size();
        }
        compressors.emplace();
        std::vector<std::pair<uint32_t, uint32_t>> rows;
        std::vector<const uint8_t*> packed;
        size_t at = 0;
        for (const PendingRow& r : pending) {
            rows.emplace_back(r.level, r.pageY);
            packed.push_back(bestPages.data() + at);
            at += r.samples.size();
        }
        if (!rows.empty()) writeRows(rows, packed);
        pending.clear();
        pending.shrink_to_fit();
        pendingBytes = 0;
    }

    void writeTables() {
        using namespace detail;
        const uint32_t levelCount = uint32_t(header.levels.size());
        const uint32_t dictBytes = dictionary ? uint32_t(dictionary->bytes().size()) : 0;
        std::vector<uint8_t> tables(size_t(dictOffset + dictBytes - kBotHeaderBytes));
        uint8_t* lt = tables.data();
        for (uint32_t l = 0; l < levelCount; ++l) {
            put32(lt + l * 8, header.levels[l].width);
            put32(lt + l * 8 + 4, header.levels[l].height);
        }
        uint8_t* rt = tables.data() + (rowTableOffset - kBotHeaderBytes);
        for (size_t r = 0; r < rowOffsets.size(); ++r) put64(rt + r * 8, rowOffsets[r]);
        uint8_t* pt = tables.data() + (pageTableOffset - kBotHeaderBytes);
        for (size_t p = 0; p < pageSizes.size(); ++p) {
            put16(pt + p * kBotPageEntryBytes, uint16_t(pageSizes[p]));
            put32(pt + p * kBotPageEntryBytes + 2, pageChecksums[p]);
        }
        if (dictBytes) std::memcpy(tables.data() + (dictOffset - kBotHeaderBytes), dictionary->bytes().data(), dictBytes);

        uint8_t h[kBotHeaderBytes] = {};
        putSharedHeader(h, kBotVersion2);
        h[kFieldPageFilter] = uint8_t(pageFilter);
        put64(h + kFieldLevelTable, kBotHeaderBytes);
        put64(h + kFieldRowTable, rowTableOffset);
        put64(h + kFieldPageTable, pageTableOffset);
        put64(h + kFieldDictionary, dictOffset);
        put32(h + kFieldDictionaryBytes, dictBytes);
        put64(h + kFieldPageCount, pageSizes.size());
        put64(h + kFieldMetaChecksum, xxh64(tables.data(), tables.size(), xxh64(h, kFieldMetaChecksum, 0)));
        // The dictionary bytes were already written where they belong; rewriting them is harmless.
        pwriteAll(fd, tables.data(), tables.size(), kBotHeaderBytes, target);
        pwriteAll(fd, h, kBotHeaderBytes, 0, target);
    }
};

BotWriter::BotWriter(const std::filesystem::path& path, uint32_t width, uint32_t height, uint32_t channels,
                     const BotWriteOptions& options)
    : m_impl(std::make_unique<Impl>()) {
    Impl& m = *m_impl;
    if (width == 0 || height == 0 || width > kMaxDimension || height > kMaxDimension)
        throw std::invalid_argument(path.string() + ": unsupported image size " + std::to_string(width) + "x" +
                                    std::to_string(height));
    if (channels == 0 || channels > kMaxChannels)
        throw std::invalid_argument(path.string() + ": unsupported channel count " + std::to_string(channels));
    const auto filter = parseMipFilter(options.filter);
    if (!filter) throw std::invalid_argument("unknown mip filter '" + options.filter + "'");
    if (options.version != detail::kBotVersion2 && options.version != detail::kBotVersion3)
        throw std::invalid_argument("cannot write BOT version " + std::to_string(options.version));
    if (options.alphaChannel < -2 || options.alphaChannel >= int(channels))
        throw std::invalid_argument("bad alpha channel " + std::to_string(options.alphaChannel));
    m.target = path;
    m.options = options;
    m.mipFilter = *filter;
    m.header.width = width;
    m.header.height = height;
    m.header.channels = channels;
    m.header.pixelType = options.pixelType;
    m.header.colorSpace = options.colorSpace;
    m.header.wrapS = options.wrapS;
    m.header.wrapT = options.wrapT;
    m.header.levels = levelsFor(width, height);
    m.rawBytes = detail::pageRawBytes(channels, options.pixelType);
    m.prefixBytes = detail::pagePrefixBytes(channels, options.pixelType);
    uint64_t pages = 0, rows = 0;
    for (const BotLevel& l : m.header.levels) {
        m.levelFirstPage.push_back(pages);
        m.levelFirstRow.push_back(rows);
        pages += uint64_t(l.pagesX) * l.pagesY;
        rows += l.pagesY;
    }
    m.rowOffsets.assign(size_t(rows), 0);
    m.pageSizes.assign(size_t(pages), 0);
    m.pageChecksums.assign(size_t(pages), 0);
    m.levels.resize(m.header.levels.size());
    m.rowTableOffset = detail::kBotHeaderBytes + uint64_t(m.header.levels.size()) * detail::kBotLevelEntryBytes;
    m.pageTableOffset = m.rowTableOffset + rows * detail::kBotRowEntryBytes;
    m.dictOffset = m.pageTableOffset + pages * detail::kBotPageEntryBytes;
    m.cursor = m.dictOffset;
    if (options.version == detail::kBotVersion3) {
        // Page data follows the header; the tables go after it (writeTables3).
        m.cursor = detail::kBotHeaderBytes;
        m.contexts = detail::ransContextCount(options.pixelType);
        m.symbolsPerPage = detail::ransSymbolsPerPage(channels, options.pixelType);
        detail::Bot3Bands bands = detail::bot3Bands(m.header.levels, m.rawBytes);
        m.levelFirstBand = std::move(bands.levelFirstBand);
        m.levelBandRows = std::move(bands.levelBandRows);
        m.tailLevel = bands.tailLevel;
        m.tailLevelOffset = {0};
        for (uint32_t l = m.tailLevel; l < m.header.levels.size(); ++l)
            m.tailLevelOffset.push_back(m.tailLevelOffset.back() + size_t(m.header.levels[l].pagesX) *
                                                                       m.header.levels[l].pagesY * m.rawBytes);
        m.bandTables.resize(bands.count);
        m.bandSamples.resize(m.header.levels.size());
        m.codingDecided = true;
    }

    // A random, exclusively created temporary name in the target's folder, so the final rename is
    // atomic and SIGINT or SIGTERM remove it (cache/output_file.h).
    m.out = std::make_unique<cache::OutputFile>(path);
    m.fd = m.out->fd();
}

BotWriter::~BotWriter() = default;  // an unfinished OutputFile removes its temporary file

const BotHeader& BotWriter::header() const { return m_impl->header; }

void BotWriter::addRows(uint32_t level, uint32_t firstRow, uint32_t rowCount, const float* rows, bool linearLight) {
    Impl& m = *m_impl;
    if (m.finished) throw std::logic_error("BotWriter::addRows after finish");
    if (level >= m.header.levels.size()) throw std::logic_error("BotWriter::addRows: no level " + std::to_string(level));
    Impl::LevelRows& lr = m.levels[level];
    const BotLevel& lv = m.header.levels[level];
    if (firstRow != lr.nextRow || rowCount > lv.height - firstRow)
        throw std::logic_error("BotWriter::addRows: rows of level " + std::to_string(level) + " out of order");
    const size_t stride = size_t(lv.width) * m.header.channels;
    uint32_t done = 0;
    while (done < rowCount) {
        const uint32_t row = firstRow + done;
        const uint32_t pageY = row / kPageSizeTexels;
        const uint32_t rowsInPage = std::min(kPageSizeTexels, lv.height - pageY * kPageSizeTexels);
        if (lr.filled == 0 && rowCount - done >= rowsInPage) {
            // A whole page row is available in the caller's buffer: no copy.
            m.emitPageRow(level, pageY, rows + done * stride, rowsInPage, linearLight);
            done += rowsInPage;
            continue;
        }
        const uint32_t take = std::min(rowsInPage - lr.filled, rowCount - done);
        lr.rows.resize(size_t(kPageSizeTexels) * stride);
        std::memcpy(lr.rows.data() + lr.filled * stride, rows + done * stride, take * stride * sizeof(float));
        lr.filled += take;
        done += take;
        if (lr.filled == rowsInPage) {
            m.emitPageRow(level, pageY, lr.rows.data(), rowsInPage, linearLight);
            lr.filled = 0;
        }
    }
    lr.nextRow = firstRow + rowCount;
    if (lr.nextRow == lv.height) {
        lr.rows.clear();
        lr.rows.shrink_to_fit();
    }
}

BotWriteStats BotWriter::finish() {
    Impl& m = *m_impl;
    if (m.finished) throw std::logic_error("BotWriter::finish called twice");
    for (size_t l = 0; l < m.levels.size(); ++l)
        if (m.levels[l].nextRow != m.header.levels[l].height)
            throw std::logic_error("BotWriter::finish: level " + std::to_string(l) + " has " +
                                   std::to_string(m.levels[l].nextRow) + " of " +
                                   std::to_string(m.header.levels[l].height) + " rows");
    if (m.options.version == detail::kBotVersion3) {
        if (m.tailLevel < m.header.levels.size()) {
            std::vector<Impl::Segment> segments;
            for (uint32_t l = m.tailLevel; l < m.header.levels.size(); ++l)
                segments.push_back({l, 0, m.header.levels[l].pagesY});
            m.encodeBand(uint32_t(m.bandTables.size() - 1), segments, m.tailSamples.data());
            m.tailSamples.clear();
            m.tailSamples.shrink_to_fit();
        }
        m.writeTables3();
    } else {
        if (!m.codingDecided) m.decideCoding();
        m.writeTables();
    }
    m.fd = -1;
    m.out->commit();  // fsync, close, rename, each checked: throws OutputError
    m.out.reset();
    m.finished = true;
    BotWriteStats stats;
    stats.pages = m.pageSizes.size();
    stats.rawBytes = stats.pages * m.rawBytes;
    stats.fileBytes = m.cursor;
    stats.dictionaryBytes = m.dictionary ? uint32_t(m.dictionary->bytes().size()) : 0;
    stats.pageFilter = m.pageFilter;
    stats.dictionary = m.dictionaryKind;
    stats.version = m.options.version;
    if (m.options.version == detail::kBotVersion3) {
        constexpr BotPageKind kinds[] = {BotPageKind::Raw, BotPageKind::Rans, BotPageKind::Constant};
        for (uint32_t field : m.pageSizes) ++stats.pagesOfKind[unsigned(kinds[field & 3])];
        stats.bands = m.bandTables.size();
        stats.pageFilter = m.bandTables.empty() ? PageFilter::None : PageFilter(m.bandTables[0][0] & 3);
    } else {
        for (uint32_t field : m.pageSizes) ++stats.pagesOfKind[field >> detail::kBotPageKindShift];
    }
    return stats;
}

void writeBot(const std::filesystem::path& path, const float* pixels, uint32_t width, uint32_t height,
              uint32_t channels, const BotWriteOptions& options) {
    auto run = [&] {
        BotWriter writer(path, width, height, channels, options);
        MipCascade cascade(width, height, channels, *parseMipFilter(options.filter), options.colorSpace,
                           options.alphaChannel,
                           [&](uint32_t level, uint32_t firstRow, uint32_t rowCount, const float* rows, bool linear) {
                               writer.addRows(level, firstRow, rowCount, rows, linear);
                           });
        const size_t stride = size_t(width) * channels;
        constexpr uint32_t kBand = 64;
        for (uint32_t y = 0; y < height; y += kBand) cascade.pushRows(pixels + y * stride, std::min(kBand, height - y));
        writer.finish();
    };
    if (options.threads > 0) {
        tbb::task_arena arena(options.threads);
        arena.execute(run);
    } else {
        run();
    }
}

}  // namespace pushpin::texture
