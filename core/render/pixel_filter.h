// core/render/pixel_filter.h: the multi-pixel filter (DESIGN.md step 6d; reference/algorithms.md
// §4). Each visible surface of a pixel hands its colour and alpha to the pixels within the
// filter's reach, weighted by the kernel at the offset from the surface's centroid to each target
// pixel's centre and normalised over the targets inside the image, so that every surface gives
// out exactly its own colour and alpha (the image keeps its energy at the borders too).
// Kernels: box (0), triangle (2), Gaussian (4), quadratic B-spline (5) over
// pixelFilterWidthX × pixelFilterWidthY (each clamped to 1..3 pixels), and the 3×3 cubic B-spline
// (6) at its natural scale, cut to the 3×3 neighbourhood. Without useMultiPixelFilter each pixel
// keeps its own surfaces.
// Pure value types and functions: reentrant and thread-safe; no allocation.
#pragma once

#include "core/render/fragment.h"
#include "core/render/render_settings.h"

namespace pushpin::render {

struct PixelFilter {
    int type = -1;                        // -1: no multi-pixel filter (each pixel keeps its own surfaces)
    double radiusX = 0.5, radiusY = 0.5;  // support half-widths in pixels
    int reach = 0;                        // neighbour pixels a surface can reach in each direction

    // The kernel at offset (dx, dy) pixels from a surface's centroid (unnormalised; 0 outside
    // the support and for type -1).
    double weight(double dx, double dy) const;
};

// The filter that `settings` asks for: type -1 without useMultiPixelFilter; an unknown type is
// taken as the triangle filter (2).
PixelFilter makePixelFilter(const RenderSettings& settings);

// The sum of the kernel over the pixels inside `image` within the filter's reach of pixel (x, y),
// for a surface of that pixel whose centroid lies at (cu, cv) inside it (0..1 from its corner;
// pixel + centroid is summed in float, as the renderer always has): what that surface's weights
// are divided by. 0 when the filter has no reach.
double filterNorm(const PixelFilter& filter, const PixelRect& image, int x, int y, float cu, float cv);

// The share of a surface of pixel (sx, sy), centroid (cu, cv) and norm `norm` (filterNorm) that
// pixel (x, y) receives. A surface whose norm is not positive stays whole in its own pixel.
double filterShare(const PixelFilter& filter, double norm, int sx, int sy, float cu, float cv, int x, int y);

}  // namespace pushpin::render
