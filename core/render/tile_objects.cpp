#include "core/render/tile_objects.h"

#include "core/render/visibility.h"
#include "core/util/release.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pushpin::render {

PixelRect reachOf(const ScreenBox& box, const PixelRect& base) {
    PixelRect r;
    r.x0 = box.x0 <= base.x0 ? base.x0 : int(std::floor(box.x0));
    r.y0 = box.y0 <= base.y0 ? base.y0 : int(std::floor(box.y0));
    r.x1 = box.x1 >= base.x1 ? base.x1 : std::min(base.x1, int(std::floor(box.x1)) + 1);
    r.y1 = box.y1 >= base.y1 ? base.y1 : std::min(base.y1, int(std::floor(box.y1)) + 1);
    return r;
}

uint64_t overlapArea(const PixelRect& a, const PixelRect& b) {
    const PixelRect o{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
    return uint64_t(o.width()) * uint64_t(o.height());
}

bool NearOccluders::mayHide(const PixelRect& reach, double nearKey) const {
    if (!std::isfinite(nearKey) || reach.empty()) return false;
    uint64_t covered = 0;
    for (size_t k = 0; k < m_count; ++k)
        if (m_occluders[k].farKey < nearKey) covered += overlapArea(m_occluders[k].reach, reach);
    return covered >= uint64_t(reach.width()) * uint64_t(reach.height());
}

void NearOccluders::add(const PixelRect& reach, double farKey) {
    if (!std::isfinite(farKey) || reach.empty()) return;
    const Occluder o{reach, uint64_t(reach.width()) * uint64_t(reach.height()), farKey};
    if (m_count < kCount) {
        m_occluders[m_count++] = o;
        return;
    }
    size_t smallest = 0;
    for (size_t k = 1; k < kCount; ++k)
        if (m_occluders[k].area < m_occluders[smallest].area) smallest = k;
    if (m_occluders[smallest].area < o.area) m_occluders[smallest] = o;
}

void OcclusionMap::reset(const PixelRect& region) {
    m_region = region;
    m_depth.assign(size_t(region.width()) * size_t(region.height()), std::numeric_limits<float>::infinity());
    m_blocksX = (region.width() + kBlock - 1) / kBlock;
    m_blockSeal.clear();
}

void OcclusionMap::finish() {
    const int w = m_region.width(), h = m_region.height();
    const int blocksY = (h + kBlock - 1) / kBlock;
    m_blockSeal.assign(size_t(m_blocksX) * size_t(blocksY), -std::numeric_limits<float>::infinity());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float& seal = m_blockSeal[size_t(y / kBlock) * m_blocksX + size_t(x / kBlock)];
            seal = std::max(seal, m_depth[size_t(y) * w + x]);
        }
}

bool OcclusionMap::hides(const PixelRect& reach, double nearKey) const {
    const PixelRect r{std::max(reach.x0, m_region.x0), std::max(reach.y0, m_region.y0), std::min(reach.x1, m_region.x1),
                      std::min(reach.y1, m_region.y1)};
    if (r.empty()) return false;
    float seal = -std::numeric_limits<float>::infinity();
    for (int by = (r.y0 - m_region.y0) / kBlock; by <= (r.y1 - 1 - m_region.y0) / kBlock; ++by)
        for (int bx = (r.x0 - m_region.x0) / kBlock; bx <= (r.x1 - 1 - m_region.x0) / kBlock; ++bx)
            seal = std::max(seal, m_blockSeal[size_t(by) * m_blocksX + size_t(bx)]);
    if (occludedBehind(seal, nearKey)) return true;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x)
            if (!occludedBehind(m_depth[index(x, y)], nearKey)) return false;
    return true;
}

uint64_t OcclusionMap::bytes() const {
    return uint64_t(m_depth.capacity() + m_blockSeal.capacity()) * sizeof(float);
}

void OcclusionMap::release() {
    util::release(m_depth);
    util::release(m_blockSeal);
}

}  // namespace pushpin::render
