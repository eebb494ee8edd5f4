// texture/detail/bot_page.h: converting one 8x8 page between float texels and the stored bytes of a
// BOT file (sample quantisation, sRGB encoding of linear values, prediction, the first-texel prefix
// and byte planes; texture/BOT_FORMAT.md "Pages").
// Pure functions on caller-owned buffers: thread-safe, no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "texture/bot_file.h"

namespace pushpin::texture::detail {

constexpr uint32_t kPageTexels = kPageSizeTexels * kPageSizeTexels;

inline uint32_t pageRawBytes(uint32_t channels, PixelType type) {
    return kPageTexels * channels * bytesPerSample(type);
}
// The packed page starts with the first texel's samples, stored as they are; zstd codes the rest.
inline uint32_t pagePrefixBytes(uint32_t channels, PixelType type) { return channels * bytesPerSample(type); }

// sRGB transfer functions (IEC 61966-2-1), exact formulas.
float srgbToLinear(float v);
float linearToSrgb(float v);
// 256-entry table: srgbToLinear(k / 255).
const float* srgbU8ToLinearTable();

// Quantises kPageTexels*channels interleaved floats to samples of `type`, written as host-order
// integers into `samples` (uint8_t, uint16_t (half bits for Half) or uint32_t (float bits)).
// When `linearLight` is true and `space` is SRGB, colour channels (not `alphaChannel`) are encoded
// with the sRGB curve first. u8/u16 are clamped to [0,1] and rounded to nearest; NaN stores 0.
void quantizePage(const float* texels, uint32_t channels, PixelType type, ColorSpace space,
                  int alphaChannel, bool linearLight, void* samples);

// Turns host-order samples into the stored byte layout (pageRawBytes bytes): the prefix (texel 0 of
// every channel, little-endian), then texels 1..63 of each channel's 8x8 grid as zigzagged
// residuals of `filter`, laid out plane by plane (channel major, then byte significance from low to
// high, then texel).
void packPage(const void* samples, uint32_t channels, PixelType type, PageFilter filter, uint8_t* out);
// Inverse of packPage.
void unpackPage(const uint8_t* in, uint32_t channels, PixelType type, PageFilter filter, void* samples);

// unpackPage followed by samplesToFloat in one pass, without the intermediate sample buffer.
void unpackPageToFloat(const uint8_t* in, uint32_t channels, PixelType type, PageFilter filter, float* texels);

// Converts host-order samples to floats (u8/u16 normalised to [0,1], half widened, float as is).
void samplesToFloat(const void* samples, uint32_t channels, PixelType type, float* texels);

}  // namespace pushpin::texture::detail

namespace pushpin::texture::detail {

// Version 3's channel decorrelation (BOT_FORMAT.md "Version 3"): in a packed page, the residuals of
// channels 1 to lastChannel (2 or 3) are replaced by their difference from the residual of the
// channel before (modulo 2^bits, zigzagged), which is zero where the channels move together, as in
// grey images stored as RGB, masks whose alpha follows their colour, and along the edges of colour
// images. Texel 0 (the prefix) is kept. In place; nothing happens when lastChannel is 0 or the page
// has no channel lastChannel. recorrelateChannels undoes it.
void decorrelateChannels(uint8_t* packed, uint32_t channels, PixelType type, uint32_t lastChannel);
void recorrelateChannels(uint8_t* packed, uint32_t channels, PixelType type, uint32_t lastChannel);

}  // namespace pushpin::texture::detail
