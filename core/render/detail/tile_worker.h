// core/render/detail/tile_worker.h: the renderer's per-frame and per-thread state (renderer.cpp),
// and what frameMemory() counts of it (frame_memory.cpp). Only core/render includes it.
// Per frame: each object's view for the camera and each piece's screen box. Per thread: a
// TileWorker, the reusable buffers of one tile after another, and the seam where a thread's
// shading context and ray tracer hang.
#pragma once

#include "core/geom/tessellation.h"
#include "core/render/adaptive_shading.h"
#include "core/render/filter_borders.h"
#include "core/render/lazy_tessellation.h"
#include "core/render/pixel_filter.h"
#include "core/render/render_stats.h"
#include "core/render/shading_points.h"
#include "core/render/tile_objects.h"
#include "core/render/visibility.h"
#include "core/render/visible_set.h"
#include "core/util/release.h"

#include "cache/memory_budget.h"

#include <glm/vec4.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace pushpin::render::detail {

// Where one object sits for this camera (visible_set.h), found once per frame without its
// triangles, and the lights of each material slot in camera space. Each tile projects the
// triangles it needs from the object's tessellation.
struct ObjectView : ObjectPlacement {
    std::vector<std::vector<shade::Light>> slotLights;  // per material slot, camera space
    std::vector<uint8_t> slotTransparent;                // per material slot
    bool mayOcclude = false;  // some material slot is opaque
    uint32_t firstUnit = 0, unitCount = 0;  // its units: one per piece of its shape
};

// One piece of an object's shape (the whole shape when it is one piece), the thing a tile lists,
// orders by depth, tests for occlusion and rasterizes: where its piece's bounds fall on the
// screen, and the screen boxes of its tessellation's clusters.
struct UnitView : ScreenBox {
    uint32_t object = 0, piece = 0;
    bool kept = false;
    // Screen boxes of the tessellation's clusters, made by the first tile that needs them (rounded
    // outwards to floats) and charged as geometry for the frame.
    std::once_flag clustersMade;
    std::atomic<bool> clustersReady{false};
    std::vector<glm::vec4> clusterBoxes;  // (x0, y0, x1, y1)
    cache::MemoryCharge clusterCharge;
};

// ---------------------------------------------------------------- shading requests
struct SampleResult {
    float color[3];
    float transparency[3];
};

struct PendingBatch {
    uint32_t object = 0;
    uint32_t slot = 0;
    std::unique_ptr<shade::ShadingBatch> batch = std::make_unique<shade::ShadingBatch>();
    std::array<uint32_t, shade::kBatchSize> target{};  // index into the tile's sample results
};

// ---------------------------------------------------------------- one thread's tiles
// A tile's own copy of the triangles one of its units gave the rasterizer, made under a cap when
// the tessellations the tile pins leave no room for the next one it needs: the unit's pin is then
// let go and the tile shades from the copy. Triangle i of `tessellation` (with its vertices,
// face, material and neighbours as the unit's tessellation has them) is the unit's triangle
// ids[i]; `ids` ascend.
struct TileCopy {
    geom::Tessellation tessellation;
    std::vector<uint32_t> ids;
    cache::MemoryCharge charge;
};

// One thread's reusable state.
struct TileWorker {
    TileWorker(const SubsamplePattern& pattern, size_t units, size_t objects)
        : tessellation(units, nullptr), copiedIds(units, nullptr), topology(objects), pieceTopology(objects),
          rasterizer(pattern), resolver(pattern, topology) {}
    // The tile's units, front to back, with their tessellations pinned for the tile's life;
    // `tessellation` is indexed by unit, `topology` by object, and both are set for the tile's
    // units only. An object in pieces lists them in `pieceTopology` (one entry per piece, made on
    // first use), which its `topology` entry points to.
    std::vector<uint32_t> tileObjects;
    std::vector<LazyTessellations::Pin> pins;
    std::vector<uint32_t> pinnedUnits;  // the unit of each pin
    std::vector<const geom::Tessellation*> tessellation;
    // Under a cap: the triangles each unit gave the rasterizer in this tile (ascending offsets in
    // its tessellation, one run per unit), and the tile's copies of units whose pins were let go
    // (copiedIds, by unit: the copy's ids, null for a unit read from its pinned tessellation).
    struct SubmittedRun {
        uint32_t unit = 0, begin = 0, end = 0;
    };
    std::vector<uint32_t> submitted;
    std::vector<SubmittedRun> submittedRuns;
    std::vector<const std::vector<uint32_t>*> copiedIds;
    std::vector<std::unique_ptr<TileCopy>> copies;
    std::vector<ObjectTopology> topology;
    std::vector<std::vector<TopologyPiece>> pieceTopology;
    TileRasterizer rasterizer;
    PixelResolver resolver;
    shade::ShadingScratch scratch;
    std::unique_ptr<shade::ShadingResult> result = std::make_unique<shade::ShadingResult>();
    // Open batches, one per (object, material slot) met in the tile. Entries are reused across
    // tiles (a batch is several kilobytes); `pendingCount` are in use.
    std::vector<PendingBatch> pending;
    size_t pendingCount = 0;
    std::unordered_map<uint64_t, uint32_t> pendingIndex;  // (object << 32 | slot) → entry
    // tile storage
    std::vector<uint32_t> pixelGroupStart;   // base region pixel → first group (+1 end)
    std::vector<SurfaceGroup> groups;        // memberBegin rebased into rasterizer.sortedFragments()
    std::vector<float> nearestDepth;         // per base-region pixel
    std::vector<uint32_t> groupSampleStart;  // group → first base sample result (+1 end)
    std::vector<SampleResult> samples;       // base samples, group by group, in order
    std::vector<uint32_t> groupExtraStart;   // group → first adaptive sample result (+1 end)
    std::vector<SampleResult> extraSamples;
    std::vector<SurfaceShade> shades;        // per group
    std::vector<SurfaceContribution> contributions;  // per group
    std::vector<float> contributionNorm;     // per group: sum of filter weights over target pixels
    std::vector<FilterSurface> filterSurfaces;  // one pixel's surfaces as the tile keeps them
    std::vector<glm::vec3> baseColor;        // per base-region pixel, for the contrast test
    std::vector<uint8_t> adaptive;           // per base-region pixel
    // occlusion (rasterizeTile): objects waiting behind nearer ones, and per base-region pixel the
    // depth behind which the fragments rasterized so far hide everything
    std::vector<uint32_t> waiting;
    NearOccluders occluders;
    OcclusionMap occlusion;
    RenderStats stats;
    // What the buffers above hold beyond the fixed share frameMemory() charges per thread; they
    // grow with the fragments of the busiest tile so far.
    cache::MemoryCharge bufferCharge;

    // Gives back what the tile buffers grew to (an idle thread's, while deferred tiles render).
    void releaseBuffers(uint64_t fixedShare) {
        rasterizer.releaseMemory();
        resolver.releaseMemory();
        util::release(pixelGroupStart);
        util::release(groups);
        util::release(nearestDepth);
        util::release(groupSampleStart);
        util::release(samples);
        util::release(groupExtraStart);
        util::release(extraSamples);
        util::release(shades);
        util::release(contributions);
        util::release(contributionNorm);
        util::release(baseColor);
        util::release(adaptive);
        util::release(waiting);
        util::release(submitted);
        util::release(submittedRuns);
        occlusion.release();
        util::release(pending);
        pendingCount = 0;
        util::release(pendingIndex);
        const uint64_t held = bytes();
        bufferCharge.resize(held > fixedShare ? held - fixedShare : 0);
    }

    uint64_t bytes() const {
        auto cap = [](const auto& v) { return uint64_t(v.capacity()) * sizeof(v[0]); };
        uint64_t b = rasterizer.bytes() + resolver.bytes() + cap(pixelGroupStart) + cap(groups) +
                     cap(nearestDepth) + cap(groupSampleStart) + cap(samples) + cap(groupExtraStart) + cap(extraSamples) +
                     cap(shades) + cap(contributions) + cap(contributionNorm) + cap(baseColor) + cap(adaptive) +
                     cap(tileObjects) + cap(pins) + cap(pinnedUnits) + cap(tessellation) + cap(topology) +
                     cap(pieceTopology) + cap(submitted) + cap(submittedRuns) + cap(copiedIds) + cap(copies) +
                     cap(waiting) + occlusion.bytes();
        for (const std::vector<TopologyPiece>& p : pieceTopology) b += cap(p);
        b += uint64_t(pending.size()) * (sizeof(shade::ShadingBatch) + sizeof(PendingBatch));
        return b;
    }
};

}  // namespace pushpin::render::detail
