#include "texture/detail/bot_page.h"

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pushpin::texture::detail {

float srgbToLinear(float v) {
    return v <= 0.04045f ? v * (1.0f / 12.92f) : std::pow((v + 0.055f) * (1.0f / 1.055f), 2.4f);
}

float linearToSrgb(float v) {
    return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

// Linear values from 2^-14 up to 1 fall into kSrgbBuckets buckets by their top 16 float bits (the
// exponent and 7 mantissa bits); every 8-bit code below 2^-14 is 0.
constexpr uint32_t kSrgbBucketBase = 0x38800000u;  // bits of 2^-14
constexpr uint32_t kSrgbBuckets = (0x3f800000u - kSrgbBucketBase) >> 16;

struct SrgbTables {
    std::array<float, 256> toLinear;
    // thresholds[k] is the linear value halfway (in sRGB code space) between codes k and k+1, so the
    // nearest 8-bit code of a linear value v is the number of thresholds <= v. Entry 255 is +inf so
    // that a scan over the table stops inside it.
    std::array<float, 256> thresholds;
    std::array<float, 256> unorm;  // k / 255
    // The code of each bucket's lowest value. A bucket is 1/128 of an octave wide, narrower than
    // the gap between two thresholds almost everywhere, so the code of a value is its bucket's code
    // or one of the next few.
    std::array<uint8_t, kSrgbBuckets> bucketCode;
    SrgbTables() {
        for (int k = 0; k < 256; ++k) {
            toLinear[k] = srgbToLinear(float(k) / 255.0f);
            unorm[k] = float(k) / 255.0f;
        }
        for (int k = 0; k < 255; ++k) thresholds[k] = float(srgbToLinear((double(k) + 0.5) / 255.0));
        thresholds[255] = std::numeric_limits<float>::infinity();
        for (uint32_t b = 0; b < kSrgbBuckets; ++b) {
            const uint32_t bits = kSrgbBucketBase + (b << 16);
            float lo;
            std::memcpy(&lo, &bits, 4);
            uint32_t code = 0;
            while (thresholds[code] <= lo) ++code;
            bucketCode[b] = uint8_t(code);
        }
        // linearToSrgbU8 steps at most twice past a bucket's code: check that the largest value of
        // every bucket needs no more.
        for (uint32_t b = 0; b < kSrgbBuckets; ++b) {
            const uint32_t bits = kSrgbBucketBase + ((b + 1) << 16) - 1;
            float hi;
            std::memcpy(&hi, &bits, 4);
            uint32_t code = bucketCode[b];
            while (thresholds[code] <= hi) ++code;
            if (code > bucketCode[b] + 2u) std::abort();
        }
    }
    static float srgbToLinear(double v) {
        return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
};

const SrgbTables& tables() {
    static const SrgbTables t;
    return t;
}

// Nearest sRGB 8-bit code of linear value v: the number of thresholds <= v, found from v's bucket.
inline uint8_t linearToSrgbU8(const SrgbTables& t, float v) {
    if (!(v > 0.0f)) return 0;  // also NaN
    if (!(v < 1.0f)) return 255;
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    uint32_t code = bits < kSrgbBucketBase ? 0 : t.bucketCode[(bits - kSrgbBucketBase) >> 16];
    // No bucket holds more than one threshold (the constructor checks two steps suffice), so two
    // conditional adds finish without a branch to mispredict. thresholds[255] is +inf.
    code += t.thresholds[code] <= v ? 1 : 0;
    code += t.thresholds[code] <= v ? 1 : 0;
    return uint8_t(code);
}

inline float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }  // NaN -> 0

int resolveAlpha(int alphaChannel, uint32_t channels) {
    if (alphaChannel == -2) return (channels == 2 || channels == 4) ? int(channels) - 1 : -1;
    return alphaChannel;
}

// Undoes the zigzag mapping of a residual (0, -1, 1, -2, ... were stored as 0, 1, 2, 3, ...).
template <typename T>
inline T unzigzag(T z) {
    return T(T(z >> 1) ^ T(T(0) - T(z & 1)));
}

// Median edge detector (LOCO-I) prediction from the left (a), upper (b) and upper-left (d) samples:
// d >= max(a, b) gives min(a, b), d <= min(a, b) gives max(a, b), otherwise a + b - d. That equals
// a + b - d clamped to [min(a, b), max(a, b)], computed here without branches (a branch on noisy
// texture data is mispredicted about half of the time).
template <typename T>
inline T medPredict(T a, T b, T d) {
    // Samples fit in Wide with room to spare, so each difference is exact and its sign is the top bit.
    using Wide = std::conditional_t<(sizeof(T) < 4), int32_t, int64_t>;
    constexpr int kSignShift = int(sizeof(Wide)) * 8 - 1;
    const Wide wa = Wide(a), wb = Wide(b);
    const Wide ab = wa - wb, abNeg = ab >> kSignShift;  // all ones when a < b
    const Wide lo = wb + (ab & abNeg), hi = wa - (ab & abNeg);
    Wide g = wa + wb - Wide(d);
    const Wide gl = g - lo;
    g -= gl & (gl >> kSignShift);  // max(g, lo)
    const Wide gh = g - hi;
    g = hi + (gh & (gh >> kSignShift));  // min(g, hi)
    return T(g);
}

constexpr uint32_t kCodedTexels = kPageTexels - 1;  // texels 1..63 of a grid; texel 0 is the prefix

template <typename T>
inline T zigzag(T cur, T pred) {
    using S = std::make_signed_t<T>;
    constexpr int kBits = int(sizeof(T)) * 8;
    const S r = S(T(cur - pred));
    return T(T(T(r) << 1) ^ T(r >> (kBits - 1)));
}

// MED prediction of texel (x, y) > (0, 0) from the samples before it in the grid: the left
// neighbour in row 0, the upper one in column 0.
template <typename T>
inline T medPredictAt(const T* s, uint32_t x, uint32_t y) {
    constexpr uint32_t n = kPageSizeTexels;
    if (y == 0) return s[x - 1];
    if (x == 0) return s[(y - 1) * n];
    return medPredict(s[y * n + x - 1], s[(y - 1) * n + x], s[(y - 1) * n + x - 1]);
}

// Mean prediction (PageFilter::Mean) of texel (x, y) > (0, 0): the rounded mean of the left,
// upper, upper-left and upper-right samples (the upper one twice in the last column); row 0 and
// column 0 average the two samples before them along the edge (the one sample next to texel 0).
// On noisy texels this halves MED's residual variance, because MED extrapolates a + b - c, which
// adds up the noise of three neighbours. Sums are formed in a wider unsigned type, so the mean of
// bit patterns is exact for every pixel type.
template <typename T>
inline T meanPredictAt(const T* s, uint32_t x, uint32_t y) {
    using U = std::conditional_t<(sizeof(T) < 4), uint32_t, uint64_t>;
    constexpr uint32_t n = kPageSizeTexels;
    if (y == 0) return x == 1 ? s[0] : T((U(s[x - 1]) + U(s[x - 2]) + 1) >> 1);
    if (x == 0) return y == 1 ? s[0] : T((U(s[(y - 1) * n]) + U(s[(y - 2) * n]) + 1) >> 1);
    const T* up = s + (y - 1) * n;
    const U d = x + 1 < n ? U(up[x + 1]) : U(up[x]);
    return T((U(s[y * n + x - 1]) + U(up[x]) + U(up[x - 1]) + d + 2) >> 2);
}

template <typename T>
void packT(const T* samples, uint32_t channels, PageFilter filter, uint8_t* out) {
    constexpr uint32_t kBytes = sizeof(T);
    constexpr uint32_t n = kPageSizeTexels;
    uint8_t* body = out + size_t(channels) * kBytes;
    T s[kPageTexels], z[kPageTexels];
    for (uint32_t c = 0; c < channels; ++c) {
        for (uint32_t i = 0; i < kPageTexels; ++i) s[i] = samples[i * channels + c];
        for (uint32_t b = 0; b < kBytes; ++b) out[c * kBytes + b] = uint8_t(s[0] >> (8 * b));
        // Every prediction reads original samples, so the residuals are independent of each other.
        switch (filter) {
            case PageFilter::None: std::memcpy(z, s, sizeof z); break;
            case PageFilter::Med:
                for (uint32_t y = 0; y < n; ++y)
                    for (uint32_t x = y == 0 ? 1 : 0; x < n; ++x) z[y * n + x] = zigzag(s[y * n + x], medPredictAt(s, x, y));
                break;
            case PageFilter::Mean: {
                // Row 0 and column 0 as meanPredictAt says; the interior without its edge tests.
                using U = std::conditional_t<(sizeof(T) < 4), uint32_t, uint64_t>;
                for (uint32_t x = 1; x < n; ++x) z[x] = zigzag(s[x], meanPredictAt(s, x, 0));
                for (uint32_t y = 1; y < n; ++y) {
                    const T* up = s + (y - 1) * n;
                    const T* row = s + y * n;
                    z[y * n] = zigzag(row[0], meanPredictAt(s, 0, y));
                    for (uint32_t x = 1; x + 1 < n; ++x)
                        z[y * n + x] = zigzag(row[x], T((U(row[x - 1]) + U(up[x - 1]) + U(up[x]) + U(up[x + 1]) + 2) >> 2));
                    z[y * n + n - 1] =
                        zigzag(row[n - 1], T((U(row[n - 2]) + U(up[n - 2]) + 2 * U(up[n - 1]) + 2) >> 2));
                }
                break;
            }
        }
        for (uint32_t b = 0; b < kBytes; ++b) {
            uint8_t* plane = body + (size_t(c) * kBytes + b) * kCodedTexels;
            for (uint32_t i = 1; i < kPageTexels; ++i) plane[i - 1] = uint8_t(z[i] >> (8 * b));
        }
    }
}

#if defined(__SSE2__)
// MED reconstruction of K 8-bit channels at once. Each channel's 8 rows sit in the 8 16-bit lanes of
// an SSE2 register, skewed so that lane y handles texel (t - y, y) at step t: its left neighbour is
// its own previous result, its upper and upper-left neighbours are lane y - 1's results of the
// previous two steps. 15 steps replace 64 dependent scalar predictions, and the K independent
// channels hide each other's latency. planes[k] holds channel k's zigzagged residuals (row-major)
// on entry and its samples on exit.
template <uint32_t K>
void unpredictU8(uint8_t* const* planes) {
    constexpr uint32_t n = kPageSizeTexels;
    uint8_t r[K][kPageTexels];
    for (uint32_t k = 0; k < K; ++k)
        for (uint32_t i = 0; i < kPageTexels; ++i) r[k][i] = unzigzag<uint8_t>(planes[k][i]);
    alignas(16) static constexpr int16_t kLaneMasks[n][n] = {
        {-1, 0, 0, 0, 0, 0, 0, 0}, {0, -1, 0, 0, 0, 0, 0, 0}, {0, 0, -1, 0, 0, 0, 0, 0}, {0, 0, 0, -1, 0, 0, 0, 0},
        {0, 0, 0, 0, -1, 0, 0, 0}, {0, 0, 0, 0, 0, -1, 0, 0}, {0, 0, 0, 0, 0, 0, -1, 0}, {0, 0, 0, 0, 0, 0, 0, -1}};
    const __m128i lane0 = _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneMasks[0]));
    const __m128i low8 = _mm_set1_epi16(0xff);
    __m128i prev[K], prev2[K];
    for (uint32_t k = 0; k < K; ++k) prev[k] = prev2[k] = _mm_setzero_si128();
    // The diagonals are gathered and scattered lane by lane in registers (pinsrw / pextrw): going
    // through memory would stall every vector load on eight narrow stores. Every step is expanded
    // at compile time, so the lane choices are constants.
    auto gather = [&]<size_t T, size_t... Y>(const uint8_t* src, std::index_sequence<Y...>) {
        __m128i v = _mm_setzero_si128();
        ((v = (T - Y < n) ? _mm_insert_epi16(v, src[Y * n + (T - Y) % n], int(Y)) : v), ...);
        return v;
    };
    auto scatter = [&]<size_t T, size_t... Y>(__m128i v, uint8_t* dst, std::index_sequence<Y...>) {
        ((T - Y < n ? void(dst[Y * n + (T - Y) % n] = uint8_t(_mm_extract_epi16(v, int(Y)))) : void()), ...);
    };
    auto step = [&]<size_t T>() {
        for (uint32_t k = 0; k < K; ++k) {
            __m128i a = prev[k];
            // Row 0 has no upper neighbours: b = d = a makes MED predict the left neighbour.
            __m128i b = _mm_or_si128(_mm_slli_si128(prev[k], 2), _mm_and_si128(a, lane0));
            __m128i d = _mm_or_si128(_mm_slli_si128(prev2[k], 2), _mm_and_si128(a, lane0));
            if constexpr (T < n) {
                // Column 0 of row T has no left neighbour: a = d = b makes MED predict the upper one.
                const __m128i m = _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneMasks[T]));
                a = _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, a));
                d = _mm_or_si128(_mm_and_si128(m, b), _mm_andnot_si128(m, d));
            }
            const __m128i lo = _mm_min_epi16(a, b), hi = _mm_max_epi16(a, b);
            __m128i g = _mm_sub_epi16(_mm_add_epi16(a, b), d);
            g = _mm_min_epi16(_mm_max_epi16(g, lo), hi);
            const __m128i res = gather.template operator()<T>(r[k], std::make_index_sequence<n>());
            const __m128i v = _mm_and_si128(_mm_add_epi16(g, res), low8);
            scatter.template operator()<T>(v, planes[k], std::make_index_sequence<n>());
            prev2[k] = prev[k];
            prev[k] = v;
        }
    };
    [&]<size_t... T>(std::index_sequence<T...>) {
        (step.template operator()<T>(), ...);
    }(std::make_index_sequence<2 * n - 1>());
}

#endif

// Loads channel c of a packed page into grid g: texel 0 from the prefix, texels 1..63 (residuals
// when predicted) merged from their byte planes.
template <typename T>
inline void loadGrid(const uint8_t* in, uint32_t channels, uint32_t c, T* g) {
    constexpr uint32_t kBytes = sizeof(T);
    T first = 0;
    for (uint32_t b = 0; b < kBytes; ++b) first = T(first | T(T(in[c * kBytes + b]) << (8 * b)));
    g[0] = first;
    const uint8_t* planes = in + size_t(channels) * kBytes + size_t(c) * kBytes * kCodedTexels;
    if constexpr (kBytes == 1) {
        std::memcpy(g + 1, planes, kCodedTexels);
    } else {
        for (uint32_t i = 0; i < kCodedTexels; ++i) {
            T v = 0;
            for (uint32_t b = 0; b < kBytes; ++b) v = T(v | T(T(planes[b * kCodedTexels + i]) << (8 * b)));
            g[i + 1] = v;
        }
    }
}

// Undoes the zigzag mapping of texels 1..63 of a grid (texel 0 is a sample).
template <typename T>
inline void unzigzagGrid(T* g) {
#if defined(__SSE2__)
    if constexpr (sizeof(T) == 1) {
        const T first = g[0];
        const __m128i one = _mm_set1_epi8(1), low7 = _mm_set1_epi8(0x7f), zero = _mm_setzero_si128();
        for (uint32_t i = 0; i < kPageTexels; i += 16) {
            __m128i* p = reinterpret_cast<__m128i*>(g + i);
            const __m128i z = _mm_loadu_si128(p);
            const __m128i half = _mm_and_si128(_mm_srli_epi16(z, 1), low7);
            _mm_storeu_si128(p, _mm_xor_si128(half, _mm_sub_epi8(zero, _mm_and_si128(z, one))));
        }
        g[0] = first;
        return;
    }
#endif
    for (uint32_t i = 1; i < kPageTexels; ++i) g[i] = unzigzag(g[i]);
}

// Undoes MED on one grid whose texel 0 is a sample and texels 1..63 zigzagged residuals.
template <typename T>
void unpredictMed(T* s) {
    constexpr uint32_t n = kPageSizeTexels;
    for (uint32_t x = 1; x < n; ++x) s[x] = T(s[x - 1] + unzigzag(s[x]));
    for (uint32_t y = 1; y < n; ++y) {
        const T* up = s + (y - 1) * n;
        T* row = s + y * n;
        T a = T(up[0] + unzigzag(row[0]));
        row[0] = a;
        for (uint32_t x = 1; x < n; ++x) {
            a = T(medPredict(a, up[x], up[x - 1]) + unzigzag(row[x]));
            row[x] = a;
        }
    }
}

// Undoes the mean prediction on K grids at once. Each grid is one chain of dependent texels (each
// needs its left neighbour); the K independent chains overlap in the pipeline, and each chain's
// last value stays in a register rather than going through memory.
template <typename T, uint32_t K>
void unpredictMean(T (*g)[kPageTexels]) {
    using U = std::conditional_t<(sizeof(T) < 4), uint32_t, uint64_t>;
    constexpr uint32_t n = kPageSizeTexels;
    for (uint32_t k = 0; k < K; ++k) unzigzagGrid(g[k]);
    T left[K], left2[K];
    // Row 0: texel 1 from texel 0, then the mean of the two texels before.
    for (uint32_t k = 0; k < K; ++k) {
        left2[k] = g[k][0];
        left[k] = g[k][1] = T(g[k][1] + g[k][0]);
    }
#pragma GCC unroll 8
    for (uint32_t x = 2; x < n; ++x)
#pragma GCC unroll 4
        for (uint32_t k = 0; k < K; ++k) {
            const T v = T(g[k][x] + T((U(left[k]) + U(left2[k]) + 1) >> 1));
            g[k][x] = v;
            left2[k] = left[k];
            left[k] = v;
        }
    for (uint32_t y = 1; y < n; ++y) {
        // The upper row's part of each sum, which does not depend on the chain.
        U above[K][n];
#pragma GCC unroll 4
        for (uint32_t k = 0; k < K; ++k) {
            const T* up = g[k] + (y - 1) * n;
            for (uint32_t x = 1; x + 1 < n; ++x) above[k][x] = U(up[x - 1]) + U(up[x]) + U(up[x + 1]) + 2;
            above[k][n - 1] = U(up[n - 2]) + 2 * U(up[n - 1]) + 2;
            // Column 0: the texel above, or the mean of the two above.
            const T pred = y == 1 ? up[0] : T((U(up[0]) + U(up[-int(n)]) + 1) >> 1);
            left[k] = g[k][y * n] = T(g[k][y * n] + pred);
        }
#pragma GCC unroll 8
        for (uint32_t x = 1; x < n; ++x)
#pragma GCC unroll 4
            for (uint32_t k = 0; k < K; ++k) {
                const T v = T(g[k][y * n + x] + T((U(left[k]) + above[k][x]) >> 2));
                g[k][y * n + x] = v;
                left[k] = v;
            }
    }
}

// Reconstructs the channels of a packed page in groups of up to four and hands each finished grid
// (64 samples, row-major) to sink(channel, grid).
template <typename T, typename Sink>
void unpackGrids(const uint8_t* in, uint32_t channels, PageFilter filter, Sink&& sink) {
    alignas(16) T g[4][kPageTexels];
    for (uint32_t c0 = 0; c0 < channels; c0 += 4) {
        const uint32_t k = std::min<uint32_t>(4, channels - c0);
        for (uint32_t j = 0; j < k; ++j) loadGrid(in, channels, c0 + j, g[j]);
        switch (filter) {
            case PageFilter::None: break;
            case PageFilter::Med:
#if defined(__SSE2__)
                if constexpr (sizeof(T) == 1) {
                    // The vector reconstruction takes texel 0 as a residual against 0.
                    for (uint32_t j = 0; j < k; ++j) g[j][0] = zigzag<T>(g[j][0], 0);
                    uint8_t* p[4] = {g[0], g[1], g[2], g[3]};
                    switch (k) {
                        case 1: unpredictU8<1>(p); break;
                        case 2: unpredictU8<2>(p); break;
                        case 3: unpredictU8<3>(p); break;
                        default: unpredictU8<4>(p); break;
                    }
                    break;
                }
#endif
                for (uint32_t j = 0; j < k; ++j) unpredictMed(g[j]);
                break;
            case PageFilter::Mean:
                switch (k) {
                    case 1: unpredictMean<T, 1>(g); break;
                    case 2: unpredictMean<T, 2>(g); break;
                    case 3: unpredictMean<T, 3>(g); break;
                    default: unpredictMean<T, 4>(g); break;
                }
                break;
        }
        for (uint32_t j = 0; j < k; ++j) sink(c0 + j, static_cast<const T*>(g[j]));
    }
}

template <typename T>
void unpackT(const uint8_t* in, uint32_t channels, PageFilter filter, T* samples) {
    unpackGrids<T>(in, channels, filter, [&](uint32_t c, const T* grid) {
        for (uint32_t i = 0; i < kPageTexels; ++i) samples[i * channels + c] = grid[i];
    });
}

// Scatters one planar channel into interleaved floats through `convert`. The channel counts of
// ordinary images get a constant stride so the stores need no multiplication by a variable.
template <uint32_t kChannels, typename T, typename Convert>
inline void scatterFixed(const T* s, uint32_t c, float* texels, Convert convert) {
    for (uint32_t i = 0; i < kPageTexels; ++i) texels[i * kChannels + c] = convert(s[i]);
}

template <typename T, typename Convert>
inline void scatter(const T* s, uint32_t c, uint32_t channels, float* texels, Convert convert) {
    switch (channels) {
        case 1: scatterFixed<1>(s, c, texels, convert); break;
        case 2: scatterFixed<2>(s, c, texels, convert); break;
        case 3: scatterFixed<3>(s, c, texels, convert); break;
        case 4: scatterFixed<4>(s, c, texels, convert); break;
        default:
            for (uint32_t i = 0; i < kPageTexels; ++i) texels[i * channels + c] = convert(s[i]);
            break;
    }
}

template <typename T, typename Convert>
void unpackToFloatT(const uint8_t* in, uint32_t channels, PageFilter filter, float* texels, Convert convert) {
    unpackGrids<T>(in, channels, filter,
                   [&](uint32_t c, const T* grid) { scatter(grid, c, channels, texels, convert); });
}

float halfBitsToFloat(uint16_t bits) {
    Imath::half h;
    h.setBits(bits);
    return float(h);
}

}  // namespace

const float* srgbU8ToLinearTable() { return tables().toLinear.data(); }


void quantizePage(const float* texels, uint32_t channels, PixelType type, ColorSpace space,
                  int alphaChannel, bool linearLight, void* samples) {
    const uint32_t n = kPageTexels * channels;
    const bool encode = linearLight && space == ColorSpace::SRGB;
    const int alpha = resolveAlpha(alphaChannel, channels);
    switch (type) {
        case PixelType::U8: {
            uint8_t* out = static_cast<uint8_t*>(samples);
            if (!encode) {
#if defined(__SSE2__)
                // n is a multiple of 64. maxps returns its second operand for NaN, so NaN stores 0.
                const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), scale = _mm_set1_ps(255.0f),
                             half = _mm_set1_ps(0.5f);
                auto code = [&](uint32_t i) {
                    const __m128 v = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(texels + i), zero), one);
                    return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(v, scale), half));
                };
                for (uint32_t i = 0; i < n; i += 16) {
                    const __m128i lo = _mm_packs_epi32(code(i), code(i + 4)), hi = _mm_packs_epi32(code(i + 8), code(i + 12));
                    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(lo, hi));
                }
#else
                for (uint32_t i = 0; i < n; ++i) out[i] = uint8_t(clamp01(texels[i]) * 255.0f + 0.5f);
#endif
            } else {
                const SrgbTables& t = tables();
                for (uint32_t i = 0; i < n; i += channels) {
                    for (uint32_t c = 0; c < channels; ++c) {
                        const float v = texels[i + c];
                        out[i + c] = int(c) == alpha ? uint8_t(clamp01(v) * 255.0f + 0.5f) : linearToSrgbU8(t, v);
                    }
                }
            }
            break;
        }
        case PixelType::U16: {
            uint16_t* out = static_cast<uint16_t*>(samples);
            for (uint32_t i = 0; i < n; ++i) {
                float v = texels[i];
                if (encode && int(i % channels) != alpha) v = linearToSrgb(clamp01(v));
                out[i] = uint16_t(clamp01(v) * 65535.0f + 0.5f);
            }
            break;
        }
        case PixelType::Half: {
            uint16_t* out = static_cast<uint16_t*>(samples);
            for (uint32_t i = 0; i < n; ++i) {
                float v = texels[i];
                if (encode && int(i % channels) != alpha) v = v > 0.0f ? linearToSrgb(v) : v;
                out[i] = Imath::half(v).bits();
            }
            break;
        }
        case PixelType::Float: {
            uint32_t* out = static_cast<uint32_t*>(samples);
            for (uint32_t i = 0; i < n; ++i) {
                float v = texels[i];
                if (encode && int(i % channels) != alpha) v = v > 0.0f ? linearToSrgb(v) : v;
                std::memcpy(&out[i], &v, 4);
            }
            break;
        }
    }
}

void packPage(const void* samples, uint32_t channels, PixelType type, PageFilter filter, uint8_t* out) {
    switch (type) {
        case PixelType::U8: packT(static_cast<const uint8_t*>(samples), channels, filter, out); break;
        case PixelType::U16:
        case PixelType::Half: packT(static_cast<const uint16_t*>(samples), channels, filter, out); break;
        case PixelType::Float: packT(static_cast<const uint32_t*>(samples), channels, filter, out); break;
    }
}

void unpackPage(const uint8_t* in, uint32_t channels, PixelType type, PageFilter filter, void* samples) {
    switch (type) {
        case PixelType::U8: unpackT(in, channels, filter, static_cast<uint8_t*>(samples)); break;
        case PixelType::U16:
        case PixelType::Half: unpackT(in, channels, filter, static_cast<uint16_t*>(samples)); break;
        case PixelType::Float: unpackT(in, channels, filter, static_cast<uint32_t*>(samples)); break;
    }
}

void samplesToFloat(const void* samples, uint32_t channels, PixelType type, float* texels) {
    const uint32_t n = kPageTexels * channels;
    switch (type) {
        case PixelType::U8: {
            const uint8_t* in = static_cast<const uint8_t*>(samples);
            const float* unorm = tables().unorm.data();
            for (uint32_t i = 0; i < n; ++i) texels[i] = unorm[in[i]];
            break;
        }
        case PixelType::U16: {
            const uint16_t* in = static_cast<const uint16_t*>(samples);
            for (uint32_t i = 0; i < n; ++i) texels[i] = float(in[i]) / 65535.0f;
            break;
        }
        case PixelType::Half: {
            const uint16_t* in = static_cast<const uint16_t*>(samples);
            for (uint32_t i = 0; i < n; ++i) texels[i] = halfBitsToFloat(in[i]);
            break;
        }
        case PixelType::Float: std::memcpy(texels, samples, size_t(n) * 4); break;
    }
}

void unpackPageToFloat(const uint8_t* in, uint32_t channels, PixelType type, PageFilter filter, float* texels) {
    switch (type) {
        case PixelType::U8: {
            const float* unorm = tables().unorm.data();
            unpackToFloatT<uint8_t>(in, channels, filter, texels, [unorm](uint8_t v) { return unorm[v]; });
            break;
        }
        case PixelType::U16:
            unpackToFloatT<uint16_t>(in, channels, filter, texels, [](uint16_t v) { return float(v) / 65535.0f; });
            break;
        case PixelType::Half:
            unpackToFloatT<uint16_t>(in, channels, filter, texels, halfBitsToFloat);
            break;
        case PixelType::Float:
            unpackToFloatT<uint32_t>(in, channels, filter, texels, [](uint32_t v) {
                float f;
                std::memcpy(&f, &v, 4);
                return f;
            });
            break;
    }
}

}  // namespace pushpin::texture::detail

namespace pushpin::texture::detail {

namespace {

constexpr uint32_t kResiduals = kPageTexels - 1;

// Residual `i` (texels 1..63) of channel c, as the zigzagged value its byte planes hold.
inline uint32_t planeValue(const uint8_t* planes, uint32_t c, uint32_t bytes, uint32_t i) {
    uint32_t v = 0;
    for (uint32_t b = 0; b < bytes; ++b) v |= uint32_t(planes[(c * bytes + b) * kResiduals + i]) << (8 * b);
    return v;
}

inline void setPlaneValue(uint8_t* planes, uint32_t c, uint32_t bytes, uint32_t i, uint32_t v) {
    for (uint32_t b = 0; b < bytes; ++b) planes[(c * bytes + b) * kResiduals + i] = uint8_t(v >> (8 * b));
}

// Zigzag of a `bits`-wide two's complement value and its inverse (0, -1, 1, -2 ... to 0, 1, 2, 3 ...).
inline uint32_t zig(uint32_t v, uint32_t bits, uint32_t mask) {
    const uint32_t negative = (v >> (bits - 1)) & 1;
    return ((v << 1) ^ (0u - negative)) & mask;
}
inline uint32_t unzig(uint32_t z, uint32_t mask) { return ((z >> 1) ^ (0u - (z & 1))) & mask; }

template <bool kForward>
void correlate(uint8_t* packed, uint32_t channels, PixelType type, uint32_t lastChannel) {
    if (lastChannel == 0 || channels <= lastChannel) return;
    uint32_t r[4];
    if (type == PixelType::U8) {  // the common case, one byte a residual: no plane assembly
        uint8_t* planes = packed + channels;
        for (uint32_t i = 0; i < kResiduals; ++i) {
            for (uint32_t c = 0; c <= lastChannel; ++c) r[c] = unzig(planes[c * kResiduals + i], 0xff);
            if (kForward) {
                for (uint32_t c = lastChannel; c >= 1; --c)
                    planes[c * kResiduals + i] = uint8_t(zig((r[c] - r[c - 1]) & 0xff, 8, 0xff));
            } else {
                for (uint32_t c = 1; c <= lastChannel; ++c) {
                    r[c] = (r[c] + r[c - 1]) & 0xff;
                    planes[c * kResiduals + i] = uint8_t(zig(r[c], 8, 0xff));
                }
            }
        }
        return;
    }
    const uint32_t bytes = bytesPerSample(type), bits = 8 * bytes;
    const uint32_t mask = bits == 32 ? ~0u : (1u << bits) - 1;
    uint8_t* planes = packed + pagePrefixBytes(channels, type);
    for (uint32_t i = 0; i < kResiduals; ++i) {
        for (uint32_t c = 0; c <= lastChannel; ++c) r[c] = unzig(planeValue(planes, c, bytes, i), mask);
        if (kForward) {
            for (uint32_t c = lastChannel; c >= 1; --c)
                setPlaneValue(planes, c, bytes, i, zig((r[c] - r[c - 1]) & mask, bits, mask));
        } else {
            for (uint32_t c = 1; c <= lastChannel; ++c) {
                r[c] = (r[c] + r[c - 1]) & mask;
                setPlaneValue(planes, c, bytes, i, zig(r[c], bits, mask));
            }
        }
    }
}

}  // namespace

void decorrelateChannels(uint8_t* packed, uint32_t channels, PixelType type, uint32_t lastChannel) {
    correlate<true>(packed, channels, type, lastChannel);
}
void recorrelateChannels(uint8_t* packed, uint32_t channels, PixelType type, uint32_t lastChannel) {
    correlate<false>(packed, channels, type, lastChannel);
}

}  // namespace pushpin::texture::detail
