// core/render/render_stats.h: what one render counted and measured, and its --stats JSON (the names
// under "tiles", "tessellation" and "memory" are read by scripts: keep them).
#pragma once

#include "core/util/json_writer.h"

#include "cache/memory_budget.h"

#include <array>
#include <cstdint>

namespace pushpin::render {

struct RenderStats {
    // seconds of wall time per phase
    double prepareSeconds = 0.0;     // culling, projection, clipping, binning
    double tilesSeconds = 0.0;       // the parallel tile loop
    // seconds summed over threads inside the tile loop
    double rasterSeconds = 0.0, resolveSeconds = 0.0, shadeSeconds = 0.0, filterSeconds = 0.0;
    uint64_t tiles = 0;
    uint64_t pixels = 0;                   // pixels written (the render region)
    uint64_t objects = 0, objectsCulledFrustum = 0, objectsCulledFar = 0;
    uint64_t triangles = 0;                // triangles of the objects kept
    uint64_t trianglesBackfacing = 0;      // dropped: back faces of single-sided objects
    uint64_t trianglesNearClipped = 0;     // crossed the near plane and were clipped
    uint64_t trianglesOutside = 0;         // behind the near plane or off screen
    uint64_t trianglesRasterized = 0;      // per tile, summed (a triangle in two tiles counts twice)
    uint64_t fragments = 0, mergedFragments = 0, surfaces = 0;
    uint64_t shadingSamplesBase = 0, shadingSamplesAdaptive = 0;
    uint64_t adaptivePixels = 0;           // pixels that took extra samples
    uint64_t apronPixels = 0;              // pixels rendered outside their tile for the contrast test
    // tiles
    int tileMinSize = 0, tileMaxSize = 0;  // shortest and longest tile side, pixels
    double maxTileCost = 0.0;              // the plan's cost limit (triangles per tile scanline); 0: fixed tiles
    uint64_t tilesDeferred = 0;            // rendered again alone: their triangles did not fit beside other tiles'
    uint64_t roomWaits = 0;                // times a tile waited for other threads' tiles to end to find room (RoomGate)
    // tessellation (made per tile on first need, shared by instances, dropped under memory pressure)
    uint64_t tessellationShapes = 0;       // distinct shapes among the objects kept
    uint64_t tessellationInstances = 0;    // objects kept (instances of those shapes)
    uint64_t objectTileVisits = 0;         // objects rasterized per tile, summed over tiles
    uint64_t skippedOccluded = 0;          // object-tile visits skipped: hidden by opaque geometry
    uint64_t tessellationsMade = 0;        // tessellations made (first time and again)
    uint64_t trianglesMade = 0;            // their triangles
    uint64_t tessellationsEvicted = 0;     // dropped to make room
    uint64_t tessellationsRecomputed = 0;  // made again after being dropped
    // Tessellations a tile let go before it was shaded, keeping a copy of the triangles it
    // rasterized, to make room for the next one it needed (under a cap only).
    uint64_t tileCopies = 0;
    // Meshes of shapes in pieces made again for their pieces (they do not keep them), and how
    // many of those were dropped to make room before the frame ended.
    uint64_t meshesMade = 0;
    uint64_t meshesEvicted = 0;
    // memory
    uint64_t memoryCapBytes = 0;           // 0: unlimited
    uint64_t memoryPeakCharged = 0;        // most the render's budget held at once
    std::array<uint64_t, cache::kMemoryCategoryCount> memoryPeakByCategory{};
    uint64_t peakRssBytes = 0;             // the process's peak resident size when the render ended
};

// Writes the stats as one JSON object value (the --stats file holds one per rendered image).
void writeRenderStats(util::JsonWriter& json, const RenderStats& stats);

}  // namespace pushpin::render
