// texture/detail/bot_layout.h: byte layout of the BOT header (see texture/BOT_FORMAT.md) and
// explicit little-endian field access. Pure functions, thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture::detail {

constexpr uint8_t kBotMagic[8] = {'P', 'P', 'B', 'O', 'T', '\r', '\n', 0x1a};
constexpr uint32_t kBotVersion = 3;           // the version writers produce by default
constexpr uint32_t kBotVersion2 = 2;
constexpr uint32_t kBotVersion3 = 3;
constexpr uint32_t kBotHeaderBytes = 96;
constexpr uint32_t kBotLevelEntryBytes = 8;   // u32 width, u32 height
constexpr uint32_t kBotRowEntryBytes = 8;     // u64 offset of a row of pages
constexpr uint32_t kBotPageEntryBytes = 6;    // u16 kind and stored size, u32 checksum
constexpr uint32_t kBotPageKindShift = 14;    // kind in bits 14-15, stored size in bits 0-13
constexpr uint32_t kBotMaxStoredBytes = (1u << kBotPageKindShift) - 1;
constexpr uint32_t kBotMaxDictionaryBytes = 1u << 20;

// Version 3 (BOT_FORMAT.md "Version 3"): pages are grouped into bands of whole page rows, each with
// its own filter and tables. A page entry is 1 to 3 bytes, by its first byte b:
//   0x00-0x7f  rANS page of (least size + b) bytes
//   0x80-0xbf  rANS page of (least size + 128 + ((b & 0x3f) << 8 | next byte)) bytes
//   0xc0-0xdf  constant page of colour b - 0xc0
//   0xe0-0xef  constant page of colour 32 + ((b & 0x0f) << 8 | next byte)
//   0xf0-0xf7  constant page of colour 4128 + ((b & 0x07) << 16 | next two bytes, little-endian)
//   0xff       raw page, then its u16 checksum
// The least size of a rANS page is its states' 7 bytes and the prefix bytes they do not carry.
constexpr uint32_t kBot3KindBits = 2;  // the writer keeps stored size << 2 | kind per page
constexpr uint32_t kBot3MinPageEntryBytes = 1;
constexpr uint32_t kBot3EntryRansLong = 0x80;
constexpr uint32_t kBot3EntryConstant = 0xc0;
constexpr uint32_t kBot3EntryConstant2 = 0xe0;
constexpr uint32_t kBot3EntryConstant3 = 0xf0;
constexpr uint32_t kBot3EntryRaw = 0xff;
constexpr uint32_t kBot3RansShortSizes = 128;                      // sizes coded in one byte
constexpr uint32_t kBot3RansLongSizes = 1u << 14;                  // ... and in two more
constexpr uint32_t kBot3ConstantShortColours = 32;
constexpr uint32_t kBot3ConstantMidColours = 1u << 12;
constexpr uint32_t kBot3ConstantLongColours = 1u << 19;
constexpr uint32_t kBot3BandMaxPages = 16384;        // a band holds at most this many pages...
constexpr uint32_t kBot3BandMaxRawBytes = 8u << 20;  // ...and at most this many raw page bytes
enum class Bot3Kind : uint8_t { Raw = 0, Rans = 1, Constant = 2 };

// Page rows per band of a level `pagesX` pages wide, for pages of `rawBytes` raw bytes.
inline uint32_t bot3BandRows(uint32_t pagesX, uint32_t rawBytes) {
    uint32_t bandPages = kBot3BandMaxRawBytes / rawBytes;
    if (bandPages > kBot3BandMaxPages) bandPages = kBot3BandMaxPages;
    const uint32_t rows = bandPages / pagesX;
    return rows ? rows : 1;
}

// A level of fewer pages than this (and every level after it) belongs to the tail band, which
// holds all of them: at most 8 MiB of raw pages, and one set of tables instead of one per small
// level.
constexpr uint32_t kBot3TailMaxPages = 4096;
inline uint32_t bot3TailPages(uint32_t rawBytes) {
    const uint32_t pages = kBot3BandMaxRawBytes / 2 / rawBytes;
    return pages < 1 ? 1 : pages > kBot3TailMaxPages ? kBot3TailMaxPages : pages;
}

// How the pages of a version-3 file fall into bands: page row y of level l is in band
// levelFirstBand[l] + y / levelBandRows[l].
struct Bot3Bands {
    std::vector<uint32_t> levelFirstBand, levelBandRows;
    uint32_t tailLevel = 0;  // the first level of the tail band (levels.size(): no tail band)
    uint32_t count = 0;
};
inline Bot3Bands bot3Bands(const std::vector<BotLevel>& levels, uint32_t rawBytes) {
    Bot3Bands b;
    b.tailLevel = uint32_t(levels.size());
    for (uint32_t l = 0; l < levels.size(); ++l)
        if (uint64_t(levels[l].pagesX) * levels[l].pagesY < bot3TailPages(rawBytes)) {
            b.tailLevel = l;
            break;
        }
    for (uint32_t l = 0; l < levels.size(); ++l) {
        b.levelFirstBand.push_back(b.count);
        if (l >= b.tailLevel) {
            b.levelBandRows.push_back(levels[l].pagesY);  // every row in the one tail band
            continue;
        }
        b.levelBandRows.push_back(bot3BandRows(levels[l].pagesX, rawBytes));
        b.count += (levels[l].pagesY + b.levelBandRows.back() - 1) / b.levelBandRows.back();
    }
    if (b.tailLevel < levels.size()) ++b.count;
    return b;
}

// Header field offsets.
enum BotHeaderField : uint32_t {
    kFieldMagic = 0,
    kFieldVersion = 8,
    kFieldHeaderBytes = 12,
    kFieldWidth = 16,
    kFieldHeight = 20,
    kFieldChannels = 24,
    kFieldPixelType = 28,
    kFieldColorSpace = 29,
    kFieldWrapS = 30,
    kFieldWrapT = 31,
    kFieldPageFilter = 32,
    kFieldMipFilter = 33,
    kFieldReserved0 = 34,  // u16, zero
    kFieldLevelCount = 36,
    kFieldLevelTable = 40,
    kFieldRowTable = 48,
    kFieldPageTable = 56,
    kFieldDictionary = 64,
    kFieldDictionaryBytes = 72,
    kFieldReserved1 = 76,  // u32, zero
    kFieldPageCount = 80,
    kFieldMetaChecksum = 88,
};

// Version 3 header fields that differ from version 2 (the others keep their offsets; byte 32, the
// page filter, is 0: each band names its own).
enum Bot3HeaderField : uint32_t {
    kField3TrailerOffset = 40,  // u64: where the trailer (tables) starts, the end of page data
    kField3TrailerBytes = 48,   // u64: trailer size; trailer offset + size = file size
    kField3BandCount = 56,      // u64: bands of all levels (follows from the sizes)
    kField3Reserved = 64,       // u64, u32, u32: zero
};

inline void put16(uint8_t* p, uint16_t v) {
    p[0] = uint8_t(v);
    p[1] = uint8_t(v >> 8);
}
inline void put32(uint8_t* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
}
inline void put64(uint8_t* p, uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = uint8_t(v >> (8 * i));
}
inline uint16_t get16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }
inline uint32_t get32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline uint64_t get64(const uint8_t* p) {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

}  // namespace pushpin::texture::detail
