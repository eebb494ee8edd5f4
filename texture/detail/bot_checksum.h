// texture/detail/bot_checksum.h: the 64-bit XXH64 hash (Yann Collet's published algorithm), used
// for BOT page and table checksums. Pure function, thread-safe, no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pushpin::texture::detail {

uint64_t xxh64(const void* data, size_t byteCount, uint64_t seed);

}  // namespace pushpin::texture::detail
