// texture/mipmap.h: mip chain construction. Level sizes, separable resampling filters (box,
// triangle, Lanczos-3) and MipCascade, which turns a stream of level-0 rows into the rows of every
// smaller level while keeping only a few rows per level in memory.
//
// Level sizes follow the floor rule: level n+1 is max(1, floor(w/2)) x max(1, floor(h/2)) of level
// n, down to 1x1. For odd sizes the filter footprint is scaled by the exact ratio src/dst (e.g.
// 13 -> 6 uses a scale of 13/6), so every source texel is weighted by how much of it each
// destination texel covers; nothing is dropped. Texels past the image edge repeat the edge texel
// (clamp), whatever the wrap mode of the texture.
// sRGB data is filtered in linear light: MipCascade decodes level-0 colour channels (not alpha)
// to linear before filtering and hands mip rows to its sink in linear light.
// Thread safety: the free functions are pure; a MipCascade belongs to one thread and parallelises
// internally with oneTBB.
// Memory: per level, one band of incoming rows plus the rows the vertical filter still needs
// (about filter radius x 2 + band rows), each width x channels floats.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::texture {

enum class MipFilter : uint8_t { Box = 0, Triangle = 1, Lanczos3 = 2 };

// "box", "triangle", "lanczos3" (nullopt for anything else).
std::optional<MipFilter> parseMipFilter(std::string_view name);
const char* mipFilterName(MipFilter filter);

// (width, height) of every level, level 0 first, ending with 1x1. Empty for a zero dimension.
std::vector<std::pair<uint32_t, uint32_t>> mipLevelSizes(uint32_t width, uint32_t height);

// The continuous filter kernel at x, in destination-texel units (box: 1 on [-0.5, 0.5); triangle:
// 1-|x| on [-1, 1]; Lanczos-3: sinc(x) sinc(x/3) on [-3, 3]). Zero outside its radius.
float mipFilterKernel(MipFilter filter, float x);
float mipFilterRadius(MipFilter filter);

// Weights for resampling one axis from srcSize to dstSize texels (dstSize <= srcSize). Destination
// texel i covers source interval [i*s, (i+1)*s) with s = srcSize/dstSize; its taps are source texels
// first[i] .. first[i]+count[i]-1 (already clamped into [0, srcSize)) with weights summing to 1.
// Box weights are exact coverage fractions; triangle and Lanczos-3 sample the kernel at source texel
// centres, (j + 0.5 - (i + 0.5) s) / s, and are normalised.
struct FilterTaps {
    std::vector<uint32_t> first;
    std::vector<uint32_t> count;
    std::vector<float> weights;  // count[i] weights per destination texel, at offsets[i]
    std::vector<uint32_t> offsets;
    uint32_t maxCount = 0;
};
FilterTaps computeFilterTaps(uint32_t srcSize, uint32_t dstSize, MipFilter filter);

// Streams level-0 rows through the whole chain. The sink receives every level's rows in increasing
// row order, level 0 as given (linearLight = false) and mip levels as linear-light values
// (linearLight = true; for a Linear colour space the flag only says the values were filtered).
class MipCascade {
public:
    using Sink = std::function<void(uint32_t level, uint32_t firstRow, uint32_t rowCount, const float* rows,
                                    bool linearLight)>;
    // alphaChannel: channel left out of sRGB decoding (-1 none, -2: last of 2- or 4-channel images).
    MipCascade(uint32_t width, uint32_t height, uint32_t channels, MipFilter filter, ColorSpace colorSpace,
               int alphaChannel, Sink sink);
    ~MipCascade();
    MipCascade(const MipCascade&) = delete;
    MipCascade& operator=(const MipCascade&) = delete;

    // Pushes the next rowCount level-0 rows (width*channels floats each). NaN inputs are filtered
    // as 0 and infinities as +-1e30 (level 0 itself is passed to the sink unchanged).
    void pushRows(const float* rows, uint32_t rowCount);
    // True when all level-0 rows were pushed and every level has been emitted.
    bool done() const;

private:
    struct Stage;
    uint32_t m_width, m_height, m_channels;
    ColorSpace m_colorSpace;
    int m_alpha;
    uint32_t m_nextRow = 0;
    Sink m_sink;
    std::vector<std::unique_ptr<Stage>> m_stages;  // m_stages[k] builds level k + 1
    std::vector<float> m_linear;
};

}  // namespace pushpin::texture
