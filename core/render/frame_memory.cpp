#include "core/render/frame_memory.h"

#include "core/render/contrast_borders.h"
#include "core/render/detail/tile_worker.h"

#include "cache/error.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <unordered_set>
#include <utility>

namespace pushpin::render {

using detail::ObjectView;
using detail::SampleResult;
using detail::TileWorker;
using detail::UnitView;

FrameLayout frameLayout(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings) {
    FrameLayout l;
    l.region = {0, 0, camera.width, camera.height};
    if (settings.useRenderRegion) {
        // Maya's region counts rows from the bottom, inclusive.
        PixelRect r{settings.left, camera.height - 1 - settings.top, settings.rght + 1, camera.height - settings.bot};
        l.region = {std::clamp(r.x0, 0, camera.width), std::clamp(r.y0, 0, camera.height),
                    std::clamp(r.x1, 0, camera.width), std::clamp(r.y1, 0, camera.height)};
    }
    l.adaptive = settings.edgeAntiAliasing == 0 && settings.maxShadingSamples > settings.shadingSamples;
    for (const RenderObject& o : scene.objects)
        if (settings.edgeAntiAliasing == 0 && o.shadingSamplesOverride && o.maxShadingSamples > o.shadingSamples)
            l.adaptive = true;
    l.marginLeft = l.adaptive ? ContrastBorders::kLeft : 0;
    l.marginRight = l.adaptive ? ContrastBorders::kRight : 0;
    l.marginTop = l.adaptive ? ContrastBorders::kTop : 0;
    l.marginBottom = 0;
    return l;
}

uint64_t tileBytesPerCrossing(const RenderSettings& settings) {
    // The fragment of each crossing held twice (the rasterizer's list, which becomes the tile's
    // surface members, and the resolver's scratch), its surface group, and a shading result per
    // sample it may take (the adaptive maximum at the Highest level).
    const bool adaptive = settings.edgeAntiAliasing == 0 && settings.maxShadingSamples > settings.shadingSamples;
    const int samples = std::max(1, adaptive ? settings.maxShadingSamples : settings.shadingSamples);
    uint64_t bytes = 2 * sizeof(Fragment) + sizeof(SurfaceGroup) + sizeof(SurfaceShade) + sizeof(SurfaceContribution) +
                     uint64_t(samples) * sizeof(SampleResult);
    // A multi-pixel filter keeps the surfaces of the pixels near the tile's edges for the end
    // (FilterBorders); counted for every crossing, as if every pixel were near an edge.
    if (makePixelFilter(settings).reach > 0) bytes += sizeof(FilterSurface);
    return bytes;
}

double maxTileCost(uint64_t bytesPerTile, const RenderSettings& settings, int tallestTile) {
    if (tallestTile < 1) return 0.0;
    const double crossings = double(bytesPerTile) / double(tileBytesPerCrossing(settings));
    return std::max(1.0, crossings / double(tallestTile));
}

uint64_t imageOutputBytes(int width, int height) {
    return uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0)) * 5 * sizeof(float);
}

FrameMemory frameMemory(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        const RenderOptions& options, int threads) {
    FrameMemory m;
    const FrameLayout layout = frameLayout(scene, camera, settings);
    const uint64_t pixels = uint64_t(std::max(camera.width, 0)) * uint64_t(std::max(camera.height, 0));
    m.framebufferBytes = pixels * 4 * sizeof(float) + (settings.depth.value_or(false) ? pixels * sizeof(float) : 0) +
                         (options.adaptiveMask ? pixels : 0) + imageOutputBytes(camera.width, camera.height);

    const int tw = std::max(1, settings.tileWidth), th = std::max(1, settings.tileHeight);
    const PixelRect& region = layout.region;
    const uint64_t tiles = uint64_t((region.width() + tw - 1) / tw) * uint64_t((region.height() + th - 1) / th);
    m.tileBytes = tiles * (sizeof(PixelRect) + sizeof(std::vector<uint32_t>));
    if (tiles > 0) {
        // One tile's base region (renderTile): the tile and its apron, per thread.
        const uint64_t basePixels = uint64_t(std::min(tw, region.width()) + layout.marginLeft + layout.marginRight) *
                                    uint64_t(std::min(th, region.height()) + layout.marginTop + layout.marginBottom);
        const uint64_t perBasePixel = sizeof(uint32_t) /* pixelGroupStart */ + sizeof(float) /* nearestDepth */ +
                                      sizeof(glm::vec3) /* baseColor */ + sizeof(uint8_t) /* adaptive */ +
                                      sizeof(uint32_t) /* the rasterizer's pixel starts */;
        const uint64_t perThread = basePixels * perBasePixel + sizeof(TileWorker) + sizeof(shade::ShadingBatch) +
                                   sizeof(shade::ShadingResult);
        m.tileBytes += uint64_t(std::max(1, threads)) * perThread;
        m.perThreadBytes = perThread;
    }

    // Kept sources once each. What making a tessellation needs beyond them is charged while it
    // is made; the largest such need must fit beside the frame's buffers.
    std::unordered_set<const void*> sources;
    for (const RenderObject& o : scene.objects) {
        const geom::GeometryHandle& h = *o.geometry;
        const size_t pieces = h.pieceCount();
        for (size_t k = 0; k < pieces; ++k) {
            m.largestTransientBytes = std::max(m.largestTransientBytes, transientBytes(h, k));
            m.largestTessellationBytes = std::max(m.largestTessellationBytes, h.pieceBytesEstimate(k));
        }
        if (h.keepsSource() && sources.insert(h.sourceId()).second) m.sourceBytes += h.sourceBytes();
        // The object's view, its units, and their entries in every thread's tile tables.
        m.geometryBytes += sizeof(ObjectView) + o.materials.size() * sizeof(std::vector<shade::Light>) +
                           pieces * sizeof(UnitView) +
                           uint64_t(std::max(1, threads)) *
                               (pieces * (sizeof(const geom::Tessellation*) + sizeof(const std::vector<uint32_t>*)) +
                                sizeof(ObjectTopology) + sizeof(std::vector<TopologyPiece>) +
                                (pieces > 1 ? pieces * sizeof(TopologyPiece) : 0));
    }
    return m;
}

std::string formatBytes(uint64_t bytes) {
    char text[64];
    if (bytes >= (uint64_t(1) << 30))
        std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / double(uint64_t(1) << 30));
    else
        std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / double(uint64_t(1) << 20));
    return text;
}

std::string formatCap(uint64_t cap) {
    return cap % (uint64_t(1) << 20) == 0 ? std::to_string(cap >> 20) + " MB" : formatBytes(cap);
}

// On refusal the charges made so far are released by the vector's destructor.
std::vector<cache::MemoryCharge> chargeFrame(cache::MemoryBudget& budget, const FrameMemory& need,
                                             const RenderCamera& camera, const std::string& capSource) {
    const uint64_t inUse = budget.usedBytes();
    const std::pair<cache::MemoryCategory, uint64_t> parts[] = {
        {cache::MemoryCategory::Framebuffer, need.framebufferBytes},
        {cache::MemoryCategory::Fragments, need.tileBytes},
        {cache::MemoryCategory::Tessellation, need.geometryBytes},
        {cache::MemoryCategory::Geometry, need.sourceBytes},
    };
    std::vector<cache::MemoryCharge> charges;
    for (const auto& [category, bytes] : parts) {
        std::optional<cache::MemoryCharge> charge = cache::MemoryCharge::tryCharge(budget, category, bytes);
        if (!charge) {
            const uint64_t cap = budget.capBytes();
            const std::string capText = formatCap(cap);
            throw MemoryCapError("the " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                     " frame needs " + formatBytes(need.totalBytes()) + " of buffers" +
                                     (inUse > 0 ? " (with " + formatBytes(inUse) + " already in use)" : "") +
                                     ", over the memory cap of " + capText +
                                     (capSource.empty() ? "" : " (" + capSource + ")"),
                                 need.totalBytes() + inUse, cap);
        }
        charges.push_back(std::move(*charge));
    }
    // The tessellation cache charges what it makes as tiles need it; the largest single shape
    // must fit beside the buffers, or no tile that sees it can render.
    if (budget.availableBytes() < need.largestTessellationBytes + need.largestTransientBytes) {
        const uint64_t cap = budget.capBytes();
        const std::string capText = formatCap(cap);
        throw MemoryCapError("the " + std::to_string(camera.width) + "x" + std::to_string(camera.height) + " frame needs " +
                                 formatBytes(need.totalBytes()) + " of buffers and " +
                                 formatBytes(need.largestTessellationBytes + need.largestTransientBytes) +
                                 " to make its largest shape's triangles" +
                                 (inUse > 0 ? " (with " + formatBytes(inUse) + " already in use)" : "") +
                                 ", over the memory cap of " + capText + (capSource.empty() ? "" : " (" + capSource + ")"),
                             need.totalBytes() + need.largestTessellationBytes + need.largestTransientBytes + inUse, cap);
    }
    return charges;
}

cache::MemoryCharge chargeScene(cache::MemoryBudget& budget, uint64_t storedBytes, const RenderSettings& settings) {
    std::optional<cache::MemoryCharge> charge =
        cache::MemoryCharge::tryCharge(budget, cache::MemoryCategory::Scene, storedBytes);
    if (charge) return std::move(*charge);
    const MemoryCap cap = memoryCap(settings);
    const std::string source = budget.capBytes() == cap.bytes ? cap.source : std::string();
    throw MemoryCapError("the loaded scene holds " + formatBytes(storedBytes) + ", over the memory cap of " +
                             formatCap(budget.capBytes()) + (source.empty() ? "" : " (" + source + ")"),
                         storedBytes, budget.capBytes());
}

}  // namespace pushpin::render
