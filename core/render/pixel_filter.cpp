#include "core/render/pixel_filter.h"

#include <algorithm>
#include <cmath>

namespace pushpin::render {

namespace {

double cubicBSpline(double x) {
    x = std::fabs(x);
    if (x < 1.0) return (3.0 * x * x * x - 6.0 * x * x + 4.0) / 6.0;
    if (x < 2.0) return (2.0 - x) * (2.0 - x) * (2.0 - x) / 6.0;
    return 0.0;
}

double quadraticBSpline(double x) {
    x = std::fabs(x);
    if (x <= 0.5) return 0.75 - x * x;
    if (x <= 1.5) return 0.5 * (x - 1.5) * (x - 1.5);
    return 0.0;
}

double weight1d(int type, double x, double r) {
    switch (type) {
    case 0: return std::fabs(x) <= r ? 1.0 : 0.0;
    case 2: return std::max(0.0, 1.0 - std::fabs(x) / r);
    case 4: {
        // Gaussian with sigma = r/2, shifted to reach 0 at the support edge.
        const double s2 = 2.0 * (0.5 * r) * (0.5 * r);
        return std::fabs(x) >= r ? 0.0 : std::exp(-x * x / s2) - std::exp(-r * r / s2);
    }
    case 5: return quadraticBSpline(x * 1.5 / r);
    case 6: return cubicBSpline(x);  // the 3×3 cubic B-spline at its natural scale
    default: return 0.0;
    }
}

}  // namespace

double PixelFilter::weight(double dx, double dy) const {
    return weight1d(type, dx, radiusX) * weight1d(type, dy, radiusY);
}

PixelFilter makePixelFilter(const RenderSettings& settings) {
    PixelFilter f;
    if (!settings.useMultiPixelFilter) return f;
    f.type = settings.pixelFilterType;
    if (f.type == 6) {
        // Carpenter/Maya 1.0 style: the kernel is cut to the 3×3 neighbourhood and renormalised.
        f.radiusX = f.radiusY = 2.0;
        f.reach = 1;
        return f;
    }
    if (f.type != 0 && f.type != 2 && f.type != 4 && f.type != 5) f.type = 2;
    f.radiusX = std::clamp(settings.pixelFilterWidthX, 1.0, 3.0) * 0.5;
    f.radiusY = std::clamp(settings.pixelFilterWidthY, 1.0, 3.0) * 0.5;
    f.reach = int(std::ceil(std::max(f.radiusX, f.radiusY) + 0.5));
    return f;
}

double filterNorm(const PixelFilter& filter, const PixelRect& image, int x, int y, float cu, float cv) {
    double sum = 0.0;
    for (int ty = y - filter.reach; ty <= y + filter.reach; ++ty)
        for (int tx = x - filter.reach; tx <= x + filter.reach; ++tx)
            if (filter.reach > 0 && image.contains(tx, ty)) sum += filter.weight(tx + 0.5 - (x + cu), ty + 0.5 - (y + cv));
    return sum;
}

double filterShare(const PixelFilter& filter, double norm, int sx, int sy, float cu, float cv, int x, int y) {
    if (norm > 0.0) return filter.weight(x + 0.5 - (sx + cu), y + 0.5 - (sy + cv)) / norm;
    return (sx == x && sy == y) ? 1.0 : 0.0;
}

}  // namespace pushpin::render
