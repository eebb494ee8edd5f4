#include "core/render/adaptive_shading.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::render {

double contrastExcess(std::span<const glm::vec3> colors, const PixelRect& colorsRect, const PixelRect& region, int x,
                      int y, const double thresholds[3]) {
    static constexpr int kNeighbours[5][2] = {{-1, 0}, {-2, 0}, {-1, -1}, {0, -1}, {1, -1}};
    const int width = colorsRect.width();
    auto at = [&](int px, int py) -> const glm::vec3& {
        return colors[size_t(py - colorsRect.y0) * size_t(width) + size_t(px - colorsRect.x0)];
    };
    glm::vec3 lo = at(x, y), hi = lo;
    for (const auto& d : kNeighbours) {
        const int nx = x + d[0], ny = y + d[1];
        if (!region.contains(nx, ny) || !colorsRect.contains(nx, ny)) continue;
        const glm::vec3& c = at(nx, ny);
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
    }
    double excess = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double mx = std::max(0.0f, hi[k]), mn = std::max(0.0f, lo[k]);
        const double contrast = mx + mn > 0.0 ? (mx - mn) / (mx + mn) : 0.0;
        if (contrast > thresholds[k])
            excess = std::max(excess, thresholds[k] < 1.0 ? (contrast - thresholds[k]) / (1.0 - thresholds[k]) : 1.0);
    }
    return excess;
}

int adaptiveSampleCount(int shadingSamples, int maxShadingSamples, double excess, int visibleSubsamples) {
    const int want = shadingSamples + int(std::ceil((maxShadingSamples - shadingSamples) * excess - 1e-9));
    return std::min(want, visibleSubsamples);
}

}  // namespace pushpin::render
