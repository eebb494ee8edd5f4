#include "texture/mipmap.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>

#include "texture/detail/bot_page.h"

namespace pushpin::texture {

std::optional<MipFilter> parseMipFilter(std::string_view name) {
    if (name == "box") return MipFilter::Box;
    if (name == "triangle") return MipFilter::Triangle;
    if (name == "lanczos3") return MipFilter::Lanczos3;
    return std::nullopt;
}

const char* mipFilterName(MipFilter filter) {
    switch (filter) {
        case MipFilter::Box: return "box";
        case MipFilter::Triangle: return "triangle";
        case MipFilter::Lanczos3: return "lanczos3";
    }
    return "?";
}

std::vector<std::pair<uint32_t, uint32_t>> mipLevelSizes(uint32_t width, uint32_t height) {
    std::vector<std::pair<uint32_t, uint32_t>> sizes;
    if (width == 0 || height == 0) return sizes;
    sizes.emplace_back(width, height);
    while (width > 1 || height > 1) {
        width = std::max(1u, width / 2);
        height = std::max(1u, height / 2);
        sizes.emplace_back(width, height);
    }
    return sizes;
}

namespace {

double sinc(double x) {
    if (std::fabs(x) < 1e-12) return 1.0;
    const double px = M_PI * x;
    return std::sin(px) / px;
}

double kernel(MipFilter filter, double x) {
    const double ax = std::fabs(x);
    switch (filter) {
        case MipFilter::Box: return (x >= -0.5 && x < 0.5) ? 1.0 : 0.0;
        case MipFilter::Triangle: return ax < 1.0 ? 1.0 - ax : 0.0;
        case MipFilter::Lanczos3: {
            if (ax >= 3.0) return 0.0;
            // sinc vanishes at non-zero integers; snapping keeps an unscaled axis an exact identity.
            const double n = std::round(ax);
            if (n != 0.0 && std::fabs(ax - n) < 1e-9) return 0.0;
            return sinc(x) * sinc(x / 3.0);
        }
    }
    return 0.0;
}

}  // namespace

float mipFilterKernel(MipFilter filter, float x) { return float(kernel(filter, x)); }

float mipFilterRadius(MipFilter filter) {
    switch (filter) {
        case MipFilter::Box: return 0.5f;
        case MipFilter::Triangle: return 1.0f;
        case MipFilter::Lanczos3: return 3.0f;
    }
    return 0.5f;
}

FilterTaps computeFilterTaps(uint32_t srcSize, uint32_t dstSize, MipFilter filter) {
    if (srcSize == 0 || dstSize == 0 || dstSize > srcSize)
        throw std::invalid_argument("computeFilterTaps: bad sizes " + std::to_string(srcSize) + " -> " +
                                    std::to_string(dstSize));
    FilterTaps taps;
    taps.first.resize(dstSize);
    taps.count.resize(dstSize);
    taps.offsets.resize(dstSize);
    const double s = double(srcSize) / double(dstSize);
    std::vector<double> w;
    for (uint32_t i = 0; i < dstSize; ++i) {
        int64_t lo, hi;  // clamped source range
        w.clear();
        if (filter == MipFilter::Box) {
            // Exact coverage of [i s, (i + 1) s) by each source texel [j, j + 1).
            const double a = double(i) * s, b = double(i + 1) * s;
            lo = int64_t(std::floor(a));
            hi = std::min<int64_t>(int64_t(std::ceil(b)) - 1, int64_t(srcSize) - 1);
            for (int64_t j = lo; j <= hi; ++j) w.push_back(std::min(b, double(j + 1)) - std::max(a, double(j)));
        } else {
            const double c = (double(i) + 0.5) * s;
            const double r = double(mipFilterRadius(filter)) * s;
            const int64_t jlo = int64_t(std::floor(c - r)) - 1, jhi = int64_t(std::ceil(c + r)) + 1;
            lo = std::max<int64_t>(0, jlo);
            hi = std::min<int64_t>(int64_t(srcSize) - 1, jhi);
            w.assign(size_t(hi - lo + 1), 0.0);
            for (int64_t j = jlo; j <= jhi; ++j) {
                const double k = kernel(filter, (double(j) + 0.5 - c) / s);
                const int64_t jc = std::clamp<int64_t>(j, 0, int64_t(srcSize) - 1);  // edge texels repeat
                w[size_t(jc - lo)] += k;
            }
        }
        // Trim zero weights at both ends so loops touch only contributing texels.
        size_t b0 = 0, b1 = w.size();
        while (b0 + 1 < b1 && w[b0] == 0.0) ++b0;
        while (b1 - 1 > b0 && w[b1 - 1] == 0.0) --b1;
        double sum = 0.0;
        for (size_t k = b0; k < b1; ++k) sum += w[k];
        taps.first[i] = uint32_t(lo + int64_t(b0));
        taps.count[i] = uint32_t(b1 - b0);
        taps.offsets[i] = uint32_t(taps.weights.size());
        for (size_t k = b0; k < b1; ++k) taps.weights.push_back(float(w[k] / sum));
        taps.maxCount = std::max(taps.maxCount, taps.count[i]);
    }
    return taps;
}

namespace {

// Horizontal pass of one row: dst has taps.first.size() texels of C channels.
template <int C>
void filterRowFixed(const float* src, const FilterTaps& taps, float* dst) {
    const size_t n = taps.first.size();
    for (size_t x = 0; x < n; ++x) {
        float acc[C] = {};
        const float* w = taps.weights.data() + taps.offsets[x];
        const float* s = src + size_t(taps.first[x]) * C;
        for (uint32_t t = 0; t < taps.count[x]; ++t)
            for (int c = 0; c < C; ++c) acc[c] += w[t] * s[size_t(t) * C + c];
        for (int c = 0; c < C; ++c) dst[x * C + c] = acc[c];
    }
}

void filterRow(const float* src, uint32_t channels, const FilterTaps& taps, float* dst) {
    switch (channels) {
        case 1: filterRowFixed<1>(src, taps, dst); return;
        case 2: filterRowFixed<2>(src, taps, dst); return;
        case 3: filterRowFixed<3>(src, taps, dst); return;
        case 4: filterRowFixed<4>(src, taps, dst); return;
        default: break;
    }
    const size_t n = taps.first.size();
    for (size_t x = 0; x < n; ++x) {
        const float* w = taps.weights.data() + taps.offsets[x];
        for (uint32_t c = 0; c < channels; ++c) {
            float acc = 0.0f;
            for (uint32_t t = 0; t < taps.count[x]; ++t)
                acc += w[t] * src[(size_t(taps.first[x]) + t) * channels + c];
            dst[x * channels + c] = acc;
        }
    }
}

inline float sanitize(float v) {
    if (v != v) return 0.0f;
    return std::clamp(v, -1e30f, 1e30f);
}

// Nearest integer of k, ties to even: std::nearbyint in the default rounding mode, without a
// library call. Below 2^23 in magnitude, adding 2^23 leaves no fraction bits, so the addition itself
// rounds (2^23 is even, so ties keep their parity); from 2^23 up every float is an integer.
inline float roundToInteger(float k) {
    constexpr float kShift = 8388608.0f;  // 2^23
    if (!(std::fabs(k) < kShift)) return k;
    return k >= 0.0f ? (k + kShift) - kShift : -((kShift - k) - kShift);
}

}  // namespace

// Builds level `level` from the rows of level - 1.
struct MipCascade::Stage {
    uint32_t level, srcW, srcH, dstW, dstH, channels;
    FilterTaps hTaps, vTaps;
    std::deque<std::vector<float>> rows;  // horizontally filtered source rows [rowBase, rowBase + size)
    uint32_t rowBase = 0;
    uint32_t received = 0;
    uint32_t nextOut = 0;
    std::vector<std::vector<float>> pool;
    std::vector<float> out;

    Stage(uint32_t lvl, uint32_t sw, uint32_t sh, uint32_t dw, uint32_t dh, uint32_t ch, MipFilter f)
        : level(lvl), srcW(sw), srcH(sh), dstW(dw), dstH(dh), channels(ch), hTaps(computeFilterTaps(sw, dw, f)),
          vTaps(computeFilterTaps(sh, dh, f)) {}

    // Consumes n source rows; returns how many output rows are now in `out` (starting at the
    // returned first row through *firstOut).
    uint32_t push(const float* src, uint32_t n, uint32_t* firstOut) {
        const size_t srcStride = size_t(srcW) * channels, dstStride = size_t(dstW) * channels;
        const size_t base = rows.size();
        for (uint32_t r = 0; r < n; ++r) {
            if (!pool.empty()) {
                rows.push_back(std::move(pool.back()));
                pool.pop_back();
            } else {
                rows.emplace_back();
            }
            rows.back().resize(dstStride);
        }
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& rg) {
            for (uint32_t r = rg.begin(); r != rg.end(); ++r)
                filterRow(src + r * srcStride, channels, hTaps, rows[base + r].data());
        });
        received += n;
        uint32_t ready = nextOut;
        while (ready < dstH && vTaps.first[ready] + vTaps.count[ready] <= received) ++ready;
        const uint32_t count = ready - nextOut;
        *firstOut = nextOut;
        out.resize(size_t(count) * dstStride);
        const uint32_t first = nextOut;
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count), [&](const tbb::blocked_range<uint32_t>& rg) {
            for (uint32_t k = rg.begin(); k != rg.end(); ++k) {
                const uint32_t o = first + k;
                float* dst = out.data() + k * dstStride;
                const float* w = vTaps.weights.data() + vTaps.offsets[o];
                for (uint32_t t = 0; t < vTaps.count[o]; ++t) {
                    const float* s = rows[vTaps.first[o] + t - rowBase].data();
                    const float wt = w[t];
                    if (t == 0) {
                        for (size_t i = 0; i < dstStride; ++i) dst[i] = wt * s[i];
                    } else {
                        for (size_t i = 0; i < dstStride; ++i) dst[i] += wt * s[i];
                    }
                }
            }
        });
        nextOut = ready;
        const uint32_t keepFrom = nextOut < dstH ? vTaps.first[nextOut] : received;
        while (rowBase < keepFrom && !rows.empty()) {
            pool.push_back(std::move(rows.front()));
            rows.pop_front();
            ++rowBase;
        }
        return count;
    }
};

MipCascade::MipCascade(uint32_t width, uint32_t height, uint32_t channels, MipFilter filter, ColorSpace colorSpace,
                       int alphaChannel, Sink sink)
    : m_width(width), m_height(height), m_channels(channels), m_colorSpace(colorSpace), m_sink(std::move(sink)) {
    if (width == 0 || height == 0 || channels == 0)
        throw std::invalid_argument("MipCascade: empty image " + std::to_string(width) + "x" +
                                    std::to_string(height) + "x" + std::to_string(channels));
    m_alpha = alphaChannel == -2 ? ((channels == 2 || channels == 4) ? int(channels) - 1 : -1) : alphaChannel;
    const auto sizes = mipLevelSizes(width, height);
    for (size_t l = 1; l < sizes.size(); ++l)
        m_stages.push_back(std::make_unique<Stage>(uint32_t(l), sizes[l - 1].first, sizes[l - 1].second,
                                                   sizes[l].first, sizes[l].second, channels, filter));
}

MipCascade::~MipCascade() = default;

void MipCascade::pushRows(const float* rows, uint32_t rowCount) {
    if (rowCount == 0) return;
    if (rowCount > m_height - m_nextRow)
        throw std::logic_error("MipCascade: more rows pushed than the image has");
    const uint32_t first = m_nextRow;
    m_nextRow += rowCount;
    m_sink(0, first, rowCount, rows, false);
    if (m_stages.empty()) return;

    // Decode to linear light (and sanitise) before filtering.
    const size_t stride = size_t(m_width) * m_channels;
    m_linear.resize(stride * rowCount);
    const bool srgb = m_colorSpace == ColorSpace::SRGB;
    const float* lut = detail::srgbU8ToLinearTable();
    const uint32_t channels = m_channels;
    const int alpha = m_alpha;
    float* lin = m_linear.data();
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, rowCount), [&](const tbb::blocked_range<uint32_t>& rg) {
        for (uint32_t r = rg.begin(); r != rg.end(); ++r) {
            const float* s = rows + r * stride;
            float* d = lin + r * stride;
            if (!srgb) {
                for (size_t i = 0; i < stride; ++i) d[i] = sanitize(s[i]);
                continue;
            }
            // 8-bit inputs arrive as exact k/255 values: use the table for them.
            auto decode = [lut](float raw) __attribute__((always_inline)) {
                const float v = sanitize(raw);
                const float k = v * 255.0f;
                const float kr = roundToInteger(k);
                if (kr >= 0.0f && kr <= 255.0f && std::fabs(k - kr) < 1e-3f) return lut[int(kr)];
                return detail::srgbToLinear(v);
            };
            if (alpha < 0 || alpha >= int(channels)) {
                for (size_t i = 0; i < stride; ++i) d[i] = decode(s[i]);
                continue;
            }
            for (size_t i = 0; i < stride; i += channels)
                for (uint32_t c = 0; c < channels; ++c)
                    d[i + c] = int(c) == alpha ? sanitize(s[i + c]) : decode(s[i + c]);
        }
    });

    const float* band = m_linear.data();
    uint32_t bandRows = rowCount;
    for (auto& stage : m_stages) {
        uint32_t firstOut = 0;
        const uint32_t produced = stage->push(band, bandRows, &firstOut);
        if (produced == 0) break;
        m_sink(stage->level, firstOut, produced, stage->out.data(), true);
        band = stage->out.data();
        bandRows = produced;
    }
}

bool MipCascade::done() const {
    if (m_nextRow != m_height) return false;
    for (const auto& stage : m_stages)
        if (stage->nextOut != stage->dstH) return false;
    return true;
}

}  // namespace pushpin::texture
