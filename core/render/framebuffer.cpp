#include "core/render/framebuffer.h"

#include <algorithm>
#include <limits>

namespace pushpin::render {

void Framebuffer::resize(int w, int h, bool keepDepth) {
    width = std::max(w, 0);
    height = std::max(h, 0);
    const size_t count = static_cast<size_t>(width) * height;
    rgba.assign(count * 4, 0.0f);
    if (keepDepth) depth.assign(count, std::numeric_limits<float>::infinity());
    else depth.clear();
}

}  // namespace pushpin::render
