// core/render/framebuffer.h: the finished pixels of one frame: RGBA (colour as composited, see
// RenderSettings::composite; alpha = coverage) and, when asked for, camera distance per pixel.
// Plain data; the renderer writes disjoint tiles from several threads.
// Memory: renderFrame charges these buffers to the render's MemoryBudget (category "framebuffer",
// 16 B/pixel for rgba, 4 B/pixel for depth) before resize() and releases the charge when it
// returns; the caller that keeps the frame afterwards holds it uncharged.
#pragma once

#include <cstddef>
#include <vector>

namespace pushpin::render {

struct Framebuffer {
    int width = 0, height = 0;
    std::vector<float> rgba;   // width × height × 4, row 0 at the top
    std::vector<float> depth;  // width × height distances along the view axis; empty when not kept;
                               // +inf where no opaque surface is seen
    void resize(int w, int h, bool keepDepth);
    float* pixel(int x, int y) { return rgba.data() + (static_cast<size_t>(y) * width + x) * 4; }
    const float* pixel(int x, int y) const { return rgba.data() + (static_cast<size_t>(y) * width + x) * 4; }
};

}  // namespace pushpin::render
