// texture/detail/bot_layout.h: byte layout of the BOT header (see texture/BOT_FORMAT.md) and
// explicit little-endian field access. Pure functions, thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pushpin::texture::detail {

constexpr uint8_t kBotMagic[8] = {'P', 'P', 'B', 'O', 'T', '\r', '\n', 0x1a};
constexpr uint32_t kBotVersion = 2;
constexpr uint32_t kBotHeaderBytes = 96;
constexpr uint32_t kBotLevelEntryBytes = 8;   // u32 width, u32 height
constexpr uint32_t kBotRowEntryBytes = 8;     // u64 offset of a row of pages
constexpr uint32_t kBotPageEntryBytes = 6;    // u16 kind and stored size, u32 checksum
constexpr uint32_t kBotPageKindShift = 14;    // kind in bits 14-15, stored size in bits 0-13
constexpr uint32_t kBotMaxStoredBytes = (1u << kBotPageKindShift) - 1;
constexpr uint32_t kBotMaxDictionaryBytes = 1u << 20;

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
