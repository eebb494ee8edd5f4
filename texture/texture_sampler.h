// texture/texture_sampler.h: filtered texture lookups over batches of samples, through the
// shared TextureCache.
// Coordinates: s grows to the right, t grows downwards (t = 0 is the first row of the image);
// texel (i, j) of a level of width w and height h covers [i/w, (i+1)/w) × [j/h, (j+1)/h).
// Derivatives are of (s, t) with respect to screen x and y; (dsdx, dtdx) and (dsdy, dtdy) span
// the pixel's footprint in texture space.
// Thread safety: the functions are reentrant; each thread passes its own PerThread handle.
// Memory: no allocation; a lookup touches only cache pages.
#pragma once

#include <cstddef>
#include <cstdint>

#include "texture/texture_cache.h"

namespace pushpin::texture {

enum class FilterMode : uint8_t {
    Point,      // nearest texel of level 0
    Bilinear,   // bilinear at level 0
    Trilinear,  // bilinear at the two mip levels around the footprint width, blended
    Kernel,     // a kernel of shape KernelShape spread over the footprint (see below)
};

// Kernel shapes for FilterMode::Kernel. The kernel lives on normalised footprint coordinates
// (x, y) ∈ [-R, R]², mapped to texture space as centre + x·A + y·B with A = (dsdx, dtdx) and
// B = (dsdy, dtdy) after widthScale/widthOffset; r = sqrt(x² + y²):
//   Box        R = 0.5, w = 1                 (exactly the pixel's footprint)
//   Quadratic  R = 1,   w = max(0, 1 − r²)
//   Quartic    R = 1,   w = max(0, 1 − r²)²
//   Gaussian   R = 1.5, w = exp(−r² / (2 · 0.5²))
// It is evaluated at kKernelTaps × kKernelTaps points (cell centres of the [-R, R]² grid), each a
// bilinear tap at the two mip levels whose texel size matches the tap spacing, blended like
// trilinear. Weights are normalised to sum to 1.
enum class KernelShape : uint8_t { Box, Quadratic, Quartic, Gaussian };
constexpr uint32_t kKernelTaps = 4;

struct LookupOptions {
    FilterMode filter = FilterMode::Trilinear;
    KernelShape kernel = KernelShape::Box;
    // The footprint axis vectors are scaled so that their length becomes
    // length × widthScale + widthOffset (texture-space units; a zero axis becomes widthOffset long).
    float widthScale = 1.0f;
    float widthOffset = 0.0f;
    // Trilinear only: above 1, up to this many trilinear probes along the footprint's major axis,
    // each at the level of the minor width (or major/maxAnisotropy if wider).
    uint32_t maxAnisotropy = 1;
    // When set, these replace the texture's own wrap modes.
    bool overrideWrap = false;
    WrapMode wrapS = WrapMode::Periodic;
    WrapMode wrapT = WrapMode::Periodic;
};

// Struct-of-arrays input; derivative arrays may be null (treated as zero).
struct LookupBatch {
    size_t count = 0;
    const float* s = nullptr;
    const float* t = nullptr;
    const float* dsdx = nullptr;
    const float* dsdy = nullptr;
    const float* dtdx = nullptr;
    const float* dtdy = nullptr;
};

// Filters `texture` at every sample of `batch`. out[c][i] receives channel c of sample i for
// c < outChannels: texture channels where the texture has them, fill[c] (or 0 when fill is null)
// beyond. A broken or unusable texture, and samples with non-finite s or t, get fill for every
// channel. Returns false when any sample of the batch got fill because the texture is broken.
// Records the batch when the cache has a trace writer. Never throws.
bool sampleTexture(TextureCache::PerThread& thread, TextureHandle texture,
                   const LookupOptions& options, const LookupBatch& batch, const float* fill,
                   uint32_t outChannels, float* const* out);

// One sample; out receives outChannels floats, interleaved. Same contract as sampleTexture().
bool sampleTexture(TextureCache::PerThread& thread, TextureHandle texture,
                   const LookupOptions& options, float s, float t, float dsdx, float dsdy,
                   float dtdx, float dtdy, const float* fill, uint32_t outChannels, float* out);

// The kernel's support R (see KernelShape).
float kernelSupport(KernelShape shape);
// The normalised kKernelTaps² weights of `shape`, row-major (y outer), summing to 1.
void kernelWeights(KernelShape shape, float* weights);

// Maps integer texel index i onto [0, n) under `mode`; -1 means "outside, black".
int32_t wrapTexel(int64_t i, int32_t n, WrapMode mode);

}  // namespace pushpin::texture
