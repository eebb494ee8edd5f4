// core/render/adaptive_shading.h: the contrast test of adaptive shading (DESIGN.md step 6c;
// reference/algorithms.md). At the Highest edge anti-aliasing quality a pixel whose base colour
// contrasts with its already-shaded neighbours — in scanline order W, WW, NW, N and NE — by more
// than the per-channel thresholds (redThreshold, greenThreshold, blueThreshold) gets extra
// shading samples: contrast (max − min) / (max + min) per channel over the pixel and those
// neighbours, colours clamped at 0; how far the worst channel passes its threshold, scaled to
// 0..1, sets how many of the samples between shadingSamples and maxShadingSamples are added.
// Pure functions: reentrant and thread-safe; no allocation.
#pragma once

#include "core/render/fragment.h"

#include <glm/vec3.hpp>

#include <span>

namespace pushpin::render {

// How far past its threshold the contrast of pixel (x, y) runs, in 0..1 (0: under every
// threshold), over the pixel and those of its neighbours W, WW, NW, N, NE that lie inside both
// `region` (the pixels rendered) and `colorsRect`. `colors` holds the base colours of the pixels
// of `colorsRect`, row by row; (x, y) must lie inside it.
double contrastExcess(std::span<const glm::vec3> colors, const PixelRect& colorsRect, const PixelRect& region, int x,
                      int y, const double thresholds[3]);

// Shading samples a surface should have for a contrast excess `excess`: shadingSamples plus the
// share `excess` of the way to maxShadingSamples (rounded up), at most the sub-samples it holds.
int adaptiveSampleCount(int shadingSamples, int maxShadingSamples, double excess, int visibleSubsamples);

}  // namespace pushpin::render
