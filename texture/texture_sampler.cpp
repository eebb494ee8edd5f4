// texture/texture_sampler.cpp: point, bilinear, trilinear, anisotropic and kernel filtering.
#include "texture/texture_sampler.h"

#include <algorithm>
#include <cmath>

#include "texture/lookup_trace.h"

namespace pushpin::texture {
namespace detail {

// The hot-path form of wrapTexel(), inlined into the filters.
inline int32_t wrapIndex(int64_t i, int32_t n, WrapMode mode) {
    if (i >= 0 && i < n) return int32_t(i);  // inside: every mode agrees
    switch (mode) {
    case WrapMode::Periodic: {
        const int64_t r = i % n;
        return int32_t(r < 0 ? r + n : r);
    }
    case WrapMode::Clamp:
        return i < 0 ? 0 : n - 1;
    case WrapMode::Mirror: {
        const int64_t period = 2 * int64_t(n);
        int64_t r = i % period;
        if (r < 0) r += period;
        return int32_t(r < n ? r : period - 1 - r);
    }
    case WrapMode::Black:
    default:
        return -1;
    }
}

}  // namespace detail

int32_t wrapTexel(int64_t i, int32_t n, WrapMode mode) { return detail::wrapIndex(i, n, mode); }

float kernelSupport(KernelShape shape) {
    switch (shape) {
    case KernelShape::Box: return 0.5f;
    case KernelShape::Quadratic: return 1.0f;
    case KernelShape::Quartic: return 1.0f;
    case KernelShape::Gaussian: return 1.5f;
    }
    return 0.5f;
}

void kernelWeights(KernelShape shape, float* weights) {
    const float R = kernelSupport(shape);
    constexpr uint32_t n = kKernelTaps;
    double sum = 0;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            const float x = R * (2.0f * (float(i) + 0.5f) / float(n) - 1.0f);
            const float y = R * (2.0f * (float(j) + 0.5f) / float(n) - 1.0f);
            const float r2 = x * x + y * y;
            float w = 1.0f;
            switch (shape) {
            case KernelShape::Box: w = 1.0f; break;
            case KernelShape::Quadratic: w = std::max(0.0f, 1.0f - r2); break;
            case KernelShape::Quartic: {
                const float q = std::max(0.0f, 1.0f - r2);
                w = q * q;
                break;
            }
            case KernelShape::Gaussian: w = std::exp(-r2 / (2.0f * 0.25f)); break;
            }
            weights[j * n + i] = w;
            sum += w;
        }
    for (uint32_t k = 0; k < n * n; ++k) weights[k] = float(weights[k] / sum);
}

namespace {

constexpr uint32_t kMaxOutChannels = 16;
constexpr uint32_t kPage = kPageSizeTexels;
static_assert(kPage == 8, "page index arithmetic below shifts by 3");

// Everything about one (texture, batch) that does not change per sample.
struct Context {
    TextureCache::PerThread* thread;
    TextureHandle handle;
    const TextureInfo* info;
    WrapMode wrapS, wrapT;
    uint32_t channels;
    uint32_t lastLevel;
    bool failed = false;
};

// Writes fill (or 0) to samples [first, count) of every output channel.
inline void fillRange(float* const* out, uint32_t outChannels, const float* fill, size_t first,
                      size_t count) {
    for (uint32_t ch = 0; ch < outChannels; ++ch)
        std::fill(out[ch] + first, out[ch] + count, fill ? fill[ch] : 0.0f);
}

// The channel count: the compile-time one when the batch was dispatched on it, else the texture's.
template <uint32_t C>
inline uint32_t channelsOf(const Context& c) {
    return C ? C : c.channels;
}

// Brings s into a range where s × width fits an int64 without changing the wrapped result.
inline float reduceCoord(float s, WrapMode mode) {
    switch (mode) {
    case WrapMode::Periodic: return s - std::floor(s);
    case WrapMode::Mirror: return s - 2.0f * std::floor(s * 0.5f);
    default: return std::clamp(s, -1.0f, 2.0f);
    }
}

// Adds weight × texel (x, y) of `level` (already wrapped, in range) to acc.
template <uint32_t C>
inline void addTexel(Context& c, uint32_t level, int32_t x, int32_t y, float weight, float* acc) {
    float v[kMaxOutChannels];
    const uint8_t off = uint8_t((y & (kPage - 1)) * kPage + (x & (kPage - 1)));
    if (!c.thread->template readTexelsN<C>(c.handle, level, uint32_t(x) / kPage,
                                           uint32_t(y) / kPage, &off, 1, v)) {
        c.failed = true;
        return;
    }
    for (uint32_t ch = 0; ch < channelsOf<C>(c); ++ch) acc[ch] += weight * v[ch];
}

// Adds wa × texel (xa, ya) + wb × texel (xb, yb) of `level` to acc; both texels lie in one page.
template <uint32_t C>
inline void addPair(Context& c, uint32_t level, int32_t xa, int32_t ya, int32_t xb, int32_t yb, float wa, float wb,
                    float* acc) {
    float v[2 * kMaxOutChannels];
    const uint32_t m = kPage - 1;
    const uint8_t off[2] = {uint8_t((uint32_t(ya) & m) * kPage + (uint32_t(xa) & m)),
                            uint8_t((uint32_t(yb) & m) * kPage + (uint32_t(xb) & m))};
    if (!c.thread->template readTexelsN<C>(c.handle, level, uint32_t(xa) / kPage, uint32_t(ya) / kPage, off, 2, v)) {
        c.failed = true;
        return;
    }
    const uint32_t n = channelsOf<C>(c);
    for (uint32_t ch = 0; ch < n; ++ch) acc[ch] += wa * v[ch] + wb * v[n + ch];
}

// Adds weight × the bilinear value at (s, t) of `level` to acc.
template <uint32_t C>
void addBilinear(Context& c, uint32_t level, float s, float t, float weight, float* acc) {
    const TextureLevelInfo& lv = c.info->levels[level];
    const float x = reduceCoord(s, c.wrapS) * lv.widthF - 0.5f;
    const float y = reduceCoord(t, c.wrapT) * lv.heightF - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float fx = x - fx0, fy = y - fy0;
    const int64_t ix = int64_t(fx0), iy = int64_t(fy0);
    const int32_t x0 = detail::wrapIndex(ix, int32_t(lv.width), c.wrapS);
    const int32_t x1 = detail::wrapIndex(ix + 1, int32_t(lv.width), c.wrapS);
    const int32_t y0 = detail::wrapIndex(iy, int32_t(lv.height), c.wrapT);
    const int32_t y1 = detail::wrapIndex(iy + 1, int32_t(lv.height), c.wrapT);
    const float w00 = (1 - fx) * (1 - fy) * weight, w10 = fx * (1 - fy) * weight;
    const float w01 = (1 - fx) * fy * weight, w11 = fx * fy * weight;
    const bool inside = (x0 | x1 | y0 | y1) >= 0;  // no black border texel
    const bool onePageX = (uint32_t(x0) ^ uint32_t(x1)) < kPage, onePageY = (uint32_t(y0) ^ uint32_t(y1)) < kPage;
    if (inside && onePageX && onePageY) {
        // The common case: the 2×2 footprint lies in one page (indices that agree above the low
        // three bits), read with one request.
        float v[4 * kMaxOutChannels];
        const uint32_t m = kPage - 1;
        const uint8_t off[4] = {uint8_t((uint32_t(y0) & m) * kPage + (uint32_t(x0) & m)),
                                uint8_t((uint32_t(y0) & m) * kPage + (uint32_t(x1) & m)),
                                uint8_t((uint32_t(y1) & m) * kPage + (uint32_t(x0) & m)),
                                uint8_t((uint32_t(y1) & m) * kPage + (uint32_t(x1) & m))};
        if (!c.thread->template readTexelsN<C>(c.handle, level, uint32_t(x0) >> 3,
                                               uint32_t(y0) >> 3, off, 4, v)) {
            c.failed = true;
            return;
        }
        const uint32_t n = channelsOf<C>(c);
        for (uint32_t ch = 0; ch < n; ++ch)
            acc[ch] += w00 * v[ch] + w10 * v[n + ch] + w01 * v[2 * n + ch] + w11 * v[3 * n + ch];
        return;
    }
    // Straddles two pages side by side or one above the other (about a fifth of all footprints
    // with 8x8 pages): one request per page.
    if (inside && onePageY) {
        addPair<C>(c, level, x0, y0, x0, y1, w00, w01, acc);
        addPair<C>(c, level, x1, y0, x1, y1, w10, w11, acc);
        return;
    }
    if (inside && onePageX) {
        addPair<C>(c, level, x0, y0, x1, y0, w00, w10, acc);
        addPair<C>(c, level, x0, y1, x1, y1, w01, w11, acc);
        return;
    }
    // Straddles four pages or touches black border texels: one request per texel inside.
    if (x0 >= 0 && y0 >= 0) addTexel<C>(c, level, x0, y0, w00, acc);
    if (x1 >= 0 && y0 >= 0) addTexel<C>(c, level, x1, y0, w10, acc);
    if (x0 >= 0 && y1 >= 0) addTexel<C>(c, level, x0, y1, w01, acc);
    if (x1 >= 0 && y1 >= 0) addTexel<C>(c, level, x1, y1, w11, acc);
}

template <uint32_t C>
void addPoint(Context& c, float s, float t, float* acc) {
    const TextureLevelInfo& lv = c.info->levels[0];
    const int64_t ix = int64_t(std::floor(reduceCoord(s, c.wrapS) * lv.widthF));
    const int64_t iy = int64_t(std::floor(reduceCoord(t, c.wrapT) * lv.heightF));
    const int32_t x = detail::wrapIndex(ix, int32_t(lv.width), c.wrapS);
    const int32_t y = detail::wrapIndex(iy, int32_t(lv.height), c.wrapT);
    if (x >= 0 && y >= 0) addTexel<C>(c, 0, x, y, 1.0f, acc);
}

// Bilinear at the two levels around `lod` (in level-0 texels, log2), blended.
template <uint32_t C>
inline void addTrilinear(Context& c, float lod, float s, float t, float weight, float* acc) {
    if (!(lod > 0.0f)) {
        addBilinear<C>(c, 0, s, t, weight, acc);
        return;
    }
    const float maxLod = float(c.lastLevel);
    if (lod >= maxLod) {
        addBilinear<C>(c, c.lastLevel, s, t, weight, acc);
        return;
    }
    const uint32_t l0 = uint32_t(lod);
    const float f = lod - float(l0);
    addBilinear<C>(c, l0, s, t, weight * (1.0f - f), acc);
    if (f > 0.0f) addBilinear<C>(c, l0 + 1, s, t, weight * f, acc);
}

inline float finiteOr0(const float* a, size_t i) {
    if (!a) return 0.0f;
    const float v = a[i];
    return std::isfinite(v) ? v : 0.0f;
}

// Scales an axis vector (in s,t units) to length × scale + offset.
inline void scaleAxis(float& ds, float& dt, float scale, float offset, bool firstAxis) {
    const float len = std::sqrt(ds * ds + dt * dt);
    if (len > 0.0f) {
        const float k = std::max(0.0f, scale + offset / len);
        ds *= k;
        dt *= k;
    } else if (firstAxis) {
        ds = std::max(0.0f, offset);
    } else {
        dt = std::max(0.0f, offset);
    }
}

template <uint32_t C>
void sampleOne(Context& c, const LookupOptions& o, const float* kernel, float s, float t,
               float dsdx, float dsdy, float dtdx, float dtdy, float* acc) {
    switch (o.filter) {
    case FilterMode::Point:
        addPoint<C>(c, s, t, acc);
        return;
    case FilterMode::Bilinear:
        addBilinear<C>(c, 0, s, t, 1.0f, acc);
        return;
    case FilterMode::Trilinear:
    case FilterMode::Kernel:
        break;
    }
    if (o.widthScale != 1.0f || o.widthOffset != 0.0f) {
        scaleAxis(dsdx, dtdx, o.widthScale, o.widthOffset, true);
        scaleAxis(dsdy, dtdy, o.widthScale, o.widthOffset, false);
    }
    const float W = c.info->levels[0].widthF, H = c.info->levels[0].heightF;
    // Footprint axes in level-0 texels.
    const float ax = dsdx * W, ay = dtdx * H, bx = dsdy * W, by = dtdy * H;
    const float lenA2 = ax * ax + ay * ay, lenB2 = bx * bx + by * by;
    if (o.filter == FilterMode::Trilinear) {
        const float major2 = std::max(lenA2, lenB2);
        if (o.maxAnisotropy <= 1 || major2 <= 1.0f) {
            // log2 of the major axis length, from its square (no square root).
            addTrilinear<C>(c, major2 > 1.0f ? 0.5f * std::log2(major2) : 0.0f, s, t, 1.0f, acc);
            return;
        }
        const float lenA = std::sqrt(lenA2), lenB = std::sqrt(lenB2);
        const float major = std::max(lenA, lenB), minor = std::min(lenA, lenB);
        if (major <= minor * 1.01f) {
            addTrilinear<C>(c, std::log2(major), s, t, 1.0f, acc);
            return;
        }
        // Anisotropic: n probes spread along the major axis, each filtering the width left
        // over, major / n, or the minor width if that is larger.
        const float ratio = minor > 0.0f ? major / minor : float(o.maxAnisotropy);
        const uint32_t n = std::clamp<uint32_t>(uint32_t(std::ceil(ratio)), 1u, o.maxAnisotropy);
        const float width = std::max(major / float(n), minor);
        const float lod = width > 1.0f ? std::log2(width) : 0.0f;
        const float ms = lenA >= lenB ? dsdx : dsdy, mt = lenA >= lenB ? dtdx : dtdy;
        const float w = 1.0f / float(n);
        for (uint32_t i = 0; i < n; ++i) {
            const float k = (float(i) + 0.5f) / float(n) - 0.5f;
            addTrilinear<C>(c, lod, s + k * ms, t + k * mt, w, acc);
        }
        return;
    }
    // Kernel: taps on a kKernelTaps² grid over [-R, R]² of the footprint; the mip level is the
    // one whose texels are as wide as the tap spacing, so the taps together cover every texel.
    const float R = kernelSupport(o.kernel);
    constexpr uint32_t n = kKernelTaps;
    const float spacing = 2.0f * R / float(n) * std::sqrt(std::max(lenA2, lenB2));
    const float lod = spacing > 1.0f ? std::log2(spacing) : 0.0f;
    for (uint32_t j = 0; j < n; ++j) {
        const float y = R * (2.0f * (float(j) + 0.5f) / float(n) - 1.0f);
        for (uint32_t i = 0; i < n; ++i) {
            const float w = kernel[j * n + i];
            if (w <= 0.0f) continue;
            const float x = R * (2.0f * (float(i) + 0.5f) / float(n) - 1.0f);
            addTrilinear<C>(c, lod, s + x * dsdx + y * dsdy, t + x * dtdx + y * dtdy, w, acc);
        }
    }
}

template <uint32_t C>
bool sampleBatch(Context& c, const LookupOptions& options, const float* kernel,
                 const LookupBatch& batch, const float* fill, uint32_t outChannels,
                 float* const* out) {
    const uint32_t texChannels = std::min(channelsOf<C>(c), outChannels);
    for (size_t i = 0; i < batch.count; ++i) {
        const float s = batch.s[i], t = batch.t[i];
        if (!std::isfinite(s) || !std::isfinite(t)) {
            for (uint32_t ch = 0; ch < outChannels; ++ch) out[ch][i] = fill ? fill[ch] : 0.0f;
            continue;
        }
        float acc[kMaxOutChannels] = {};
        sampleOne<C>(c, options, kernel, s, t, finiteOr0(batch.dsdx, i), finiteOr0(batch.dsdy, i),
                  finiteOr0(batch.dtdx, i), finiteOr0(batch.dtdy, i), acc);
        if (c.failed) {
            fillRange(out, outChannels, fill, i, batch.count);
            return false;
        }
        for (uint32_t ch = 0; ch < texChannels; ++ch) out[ch][i] = acc[ch];
        for (uint32_t ch = texChannels; ch < outChannels; ++ch) out[ch][i] = fill ? fill[ch] : 0.0f;
    }
    return true;
}

// The batch loop for a channel count, compiled once for the x86-64 baseline and, on x86-64, once
// more with SSE4.1, whose roundss makes each of a bilinear lookup's four floors one instruction
// instead of a sequence of conversions and compares. floor is exact either way (and neither
// build contracts multiplications and additions), so both give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SSE4_1__)
#define PUSHPIN_SAMPLER_SSE41 1
template <uint32_t C>
__attribute__((target("sse4.1"), flatten)) bool sampleBatchSse41(Context& c, const LookupOptions& options,
                                                                  const float* kernel, const LookupBatch& batch,
                                                                  const float* fill, uint32_t outChannels,
                                                                  float* const* out) {
    return sampleBatch<C>(c, options, kernel, batch, fill, outChannels, out);
}

bool hasSse41() {
    static const bool has = [] {
        __builtin_cpu_init();  // may run before the constructor that would call it
        return __builtin_cpu_supports("sse4.1") != 0;
    }();
    return has;
}
#endif

template <uint32_t C>
bool dispatchBatch(Context& c, const LookupOptions& options, const float* kernel, const LookupBatch& batch,
                   const float* fill, uint32_t outChannels, float* const* out) {
#ifdef PUSHPIN_SAMPLER_SSE41
    if (hasSse41()) return sampleBatchSse41<C>(c, options, kernel, batch, fill, outChannels, out);
#endif
    return sampleBatch<C>(c, options, kernel, batch, fill, outChannels, out);
}

}  // namespace

bool sampleTexture(TextureCache::PerThread& thread, TextureHandle texture,
                   const LookupOptions& options, const LookupBatch& batch, const float* fill,
                   uint32_t outChannels, float* const* out) {
    TextureCache& cache = thread.cache();
    thread.countFilteredLookups(batch.count);
    const TextureInfo* info = cache.info(texture);
    if (LookupTraceWriter* trace = cache.traceWriter(); trace && info)
        trace->record(texture.id, info->path, options, batch);
    if (!info || cache.broken(texture)) {
        fillRange(out, outChannels, fill, 0, batch.count);
        return false;
    }
    Context c{&thread,
              texture,
              info,
              options.overrideWrap ? options.wrapS : info->wrapS,
              options.overrideWrap ? options.wrapT : info->wrapT,
              std::min<uint32_t>(info->channels, kMaxOutChannels),
              uint32_t(info->levels.size() - 1)};
    float kernel[kKernelTaps * kKernelTaps];
    if (options.filter == FilterMode::Kernel) kernelWeights(options.kernel, kernel);
    // Dispatch once per batch on the channel count, so the per-texel loops unroll.
    switch (c.channels) {
    case 1: return dispatchBatch<1>(c, options, kernel, batch, fill, outChannels, out);
    case 2: return dispatchBatch<2>(c, options, kernel, batch, fill, outChannels, out);
    case 3: return dispatchBatch<3>(c, options, kernel, batch, fill, outChannels, out);
    case 4: return dispatchBatch<4>(c, options, kernel, batch, fill, outChannels, out);
    default: return dispatchBatch<0>(c, options, kernel, batch, fill, outChannels, out);
    }
}

bool sampleTexture(TextureCache::PerThread& thread, TextureHandle texture,
                   const LookupOptions& options, float s, float t, float dsdx, float dsdy,
                   float dtdx, float dtdy, const float* fill, uint32_t outChannels, float* out) {
    float tmp[kMaxOutChannels];
    float* outs[kMaxOutChannels] = {};
    const uint32_t n = std::min(outChannels, kMaxOutChannels);
    for (uint32_t ch = 0; ch < n; ++ch) outs[ch] = &tmp[ch];
    LookupBatch b;
    b.count = 1;
    b.s = &s;
    b.t = &t;
    b.dsdx = &dsdx;
    b.dsdy = &dsdy;
    b.dtdx = &dtdx;
    b.dtdy = &dtdy;
    const bool ok = sampleTexture(thread, texture, options, b, fill, n, outs);
    std::copy(tmp, tmp + n, out);
    return ok;
}

}  // namespace pushpin::texture
