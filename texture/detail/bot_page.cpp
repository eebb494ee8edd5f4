#include "texture/detail/bot_page.h"

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace pushpin::texture::detail {

float srgbToLinear(float v) {
    return v <= 0.04045f ? v * (1.0f / 12.92f) : std::pow((v + 0.055f) * (1.0f / 1.055f), 2.4f);
}

float linearToSrgb(float v) {
    return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

struct SrgbTables {
    std::array<float, 256> toLinear;
    // thresholds[k] is the linear value halfway (in sRGB code space) between codes k and k+1, so the
    // nearest 8-bit code of a linear value v is the number of thresholds <= v.
    std::array<float, 255> thresholds;
    std::array<float, 256> unorm;  // k / 255
    SrgbTables() {
        for (int k = 0; k < 256; ++k) {
            toLinear[k] = srgbToLinear(float(k) / 255.0f);
            unorm[k] = float(k) / 255.0f;
        }
        for (int k = 0; k < 255; ++k) thresholds[k] = float(srgbToLinear((double(k) + 0.5) / 255.0));
    }
    static float srgbToLinear(double v) {
        return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
};

const SrgbTables& tables() {
    static const SrgbTables t;
    return t;
}

inline uint8_t linearToSrgbU8(float v) {
    const auto& t = tables().thresholds;
    if (!(v > 0.0f)) return 0;  // also NaN
    return uint8_t(std::upper_bound(t.begin(), t.end(), v) - t.begin());
}

inline float clamp01(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; }  // NaN -> 0

int resolveAlpha(int alphaChannel, uint32_t channels) {
    if (alphaChannel == -2) return (channels == 2 || channels == 4) ? int(channels) - 1 : -1;
    return alphaChannel;
}

template <typename T>
void packT(const T* samples, uint32_t channels, bool predict, uint8_t* out) {
    using S = std::make_signed_t<T>;
    constexpr int kBits = int(sizeof(T)) * 8;
    constexpr uint32_t kBytes = sizeof(T);
    T z[kPageTexels];
    for (uint32_t c = 0; c < channels; ++c) {
        if (predict) {
            for (uint32_t y = 0; y < kPageSizeTexels; ++y) {
                for (uint32_t x = 0; x < kPageSizeTexels; ++x) {
                    const uint32_t i = y * kPageSizeTexels + x;
                    const T cur = samples[i * channels + c];
                    T pred;
                    if (y == 0) {
                        pred = x == 0 ? T(0) : samples[(i - 1) * channels + c];
                    } else if (x == 0) {
                        pred = samples[(i - kPageSizeTexels) * channels + c];
                    } else {
                        // Median edge detector (LOCO-I): predicts across edges better than an average.
                        const T a = samples[(i - 1) * channels + c];
                        const T b = samples[(i - kPageSizeTexels) * channels + c];
                        const T d = samples[(i - kPageSizeTexels - 1) * channels + c];
                        const T lo = std::min(a, b), hi = std::max(a, b);
                        pred = d >= hi ? lo : (d <= lo ? hi : T(a + b - d));
                    }
                    const S r = S(T(cur - pred));
                    z[i] = T((T(r) << 1) ^ T(r >> (kBits - 1)));
                }
            }
        } else {
            for (uint32_t i = 0; i < kPageTexels; ++i) z[i] = samples[i * channels + c];
        }
        for (uint32_t b = 0; b < kBytes; ++b) {
            uint8_t* plane = out + (size_t(c) * kBytes + b) * kPageTexels;
            for (uint32_t i = 0; i < kPageTexels; ++i) plane[i] = uint8_t(z[i] >> (8 * b));
        }
    }
}

template <typename T>
void unpackT(const uint8_t* in, uint32_t channels, bool predict, T* samples) {
    constexpr uint32_t kBytes = sizeof(T);
    T z[kPageTexels];
    for (uint32_t c = 0; c < channels; ++c) {
        for (uint32_t i = 0; i < kPageTexels; ++i) z[i] = 0;
        for (uint32_t b = 0; b < kBytes; ++b) {
            const uint8_t* plane = in + (size_t(c) * kBytes + b) * kPageTexels;
            for (uint32_t i = 0; i < kPageTexels; ++i) z[i] = T(z[i] | T(T(plane[i]) << (8 * b)));
        }
        if (!predict) {
            for (uint32_t i = 0; i < kPageTexels; ++i) samples[i * channels + c] = z[i];
            continue;
        }
        for (uint32_t y = 0; y < kPageSizeTexels; ++y) {
            for (uint32_t x = 0; x < kPageSizeTexels; ++x) {
                const uint32_t i = y * kPageSizeTexels + x;
                const T r = T(T(z[i] >> 1) ^ T(T(0) - T(z[i] & 1)));  // undo zigzag
                T pred;
                if (y == 0) {
                    pred = x == 0 ? T(0) : samples[(i - 1) * channels + c];
                } else if (x == 0) {
                    pred = samples[(i - kPageSizeTexels) * channels + c];
                } else {
                    const T a = samples[(i - 1) * channels + c];
                    const T b = samples[(i - kPageSizeTexels) * channels + c];
                    const T d = samples[(i - kPageSizeTexels - 1) * channels + c];
                    const T lo = std::min(a, b), hi = std::max(a, b);
                    pred = d >= hi ? lo : (d <= lo ? hi : T(a + b - d));
                }
                samples[i * channels + c] = T(pred + r);
            }
        }
    }
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
                for (uint32_t i = 0; i < n; ++i) out[i] = uint8_t(clamp01(texels[i]) * 255.0f + 0.5f);
            } else {
                for (uint32_t i = 0; i < n; ++i) {
                    const bool isAlpha = int(i % channels) == alpha;
                    out[i] = isAlpha ? uint8_t(clamp01(texels[i]) * 255.0f + 0.5f) : linearToSrgbU8(texels[i]);
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

void packPage(const void* samples, uint32_t channels, PixelType type, bool predict, uint8_t* out) {
    switch (type) {
        case PixelType::U8: packT(static_cast<const uint8_t*>(samples), channels, predict, out); break;
        case PixelType::U16:
        case PixelType::Half: packT(static_cast<const uint16_t*>(samples), channels, predict, out); break;
        case PixelType::Float: packT(static_cast<const uint32_t*>(samples), channels, predict, out); break;
    }
}

void unpackPage(const uint8_t* in, uint32_t channels, PixelType type, bool predict, void* samples) {
    switch (type) {
        case PixelType::U8: unpackT(in, channels, predict, static_cast<uint8_t*>(samples)); break;
        case PixelType::U16:
        case PixelType::Half: unpackT(in, channels, predict, static_cast<uint16_t*>(samples)); break;
        case PixelType::Float: unpackT(in, channels, predict, static_cast<uint32_t*>(samples)); break;
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
            for (uint32_t i = 0; i < n; ++i) {
                Imath::half h;
                h.setBits(in[i]);
                texels[i] = float(h);
            }
            break;
        }
        case PixelType::Float: std::memcpy(texels, samples, size_t(n) * 4); break;
    }
}

}  // namespace pushpin::texture::detail
