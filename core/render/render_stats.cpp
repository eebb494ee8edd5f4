#include "core/render/render_stats.h"

namespace pushpin::render {

void writeRenderStats(util::JsonWriter& j, const RenderStats& s) {
    j.beginObject();
    j.key("seconds").beginObject();
    j.field("prepare", s.prepareSeconds).field("tiles", s.tilesSeconds);
    j.field("rasterThreadSum", s.rasterSeconds).field("resolveThreadSum", s.resolveSeconds);
    j.field("shadeThreadSum", s.shadeSeconds).field("filterThreadSum", s.filterSeconds);
    j.endObject();
    j.key("tiles").beginObject();
    j.field("count", s.tiles).field("minSize", uint64_t(s.tileMinSize)).field("maxSize", uint64_t(s.tileMaxSize));
    j.field("maxTileCost", s.maxTileCost).field("deferred", s.tilesDeferred).field("waitedForRoom", s.roomWaits);
    j.endObject();
    j.key("tessellation").beginObject();
    j.field("objects", s.tessellationShapes).field("instances", s.tessellationInstances);
    j.field("skippedOccluded", s.skippedOccluded).field("skippedOffscreen", s.objectsCulledFrustum + s.objectsCulledFar);
    j.field("trianglesMade", s.trianglesMade).field("made", s.tessellationsMade);
    j.field("evicted", s.tessellationsEvicted).field("recomputed", s.tessellationsRecomputed);
    j.field("tileCopies", s.tileCopies);
    j.field("meshesMade", s.meshesMade).field("meshesEvicted", s.meshesEvicted);
    j.field("tileVisits", s.objectTileVisits);
    j.endObject();
    j.key("memory").beginObject();
    j.field("cap", s.memoryCapBytes).field("peakCharged", s.memoryPeakCharged).field("peakRss", s.peakRssBytes);
    j.key("byCategory").beginObject();
    for (size_t c = 0; c < cache::kMemoryCategoryCount; ++c)
        j.field(cache::memoryCategoryName(cache::MemoryCategory(c)), s.memoryPeakByCategory[c]);
    j.endObject();
    j.endObject();
    j.field("pixels", s.pixels).field("apronPixels", s.apronPixels);
    j.field("objects", s.objects).field("objectsCulledFrustum", s.objectsCulledFrustum);
    j.field("objectsCulledFar", s.objectsCulledFar);
    j.field("triangles", s.triangles).field("trianglesBackfacing", s.trianglesBackfacing);
    j.field("trianglesNearClipped", s.trianglesNearClipped).field("trianglesOutside", s.trianglesOutside);
    j.field("trianglesRasterized", s.trianglesRasterized);
    j.field("fragments", s.fragments).field("mergedFragments", s.mergedFragments).field("surfaces", s.surfaces);
    j.field("shadingSamplesBase", s.shadingSamplesBase).field("shadingSamplesAdaptive", s.shadingSamplesAdaptive);
    j.field("adaptivePixels", s.adaptivePixels);
    j.endObject();
}

}  // namespace pushpin::render
