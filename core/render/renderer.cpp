#include "core/render/renderer.h"

#include "core/geom/tessellation.h"
#include "core/render/camera_space.h"
#include "core/render/contrast_borders.h"
#include "core/render/room_gate.h"
#include "core/render/detail/tile_worker.h"
#include "core/render/tile_index.h"
#include "core/render/tile_plan.h"
#include "core/util/process_memory.h"

#include "cache/error.h"
#include "cache/lru_cache.h"
#include "cache/memory_budget.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <functional>
#include <atomic>
#include <deque>
#include <mutex>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>

namespace pushpin::render {

static_assert(kNoTriangle == geom::kNoNeighbor && kHardEdgeBit == geom::kHardNeighborBit,
              "ObjectTopology reads Tessellation::neighbors as they are");

using detail::ObjectView;
using detail::PendingBatch;
using detail::SampleResult;
using detail::TileCopy;
using detail::TileWorker;
using detail::UnitView;

namespace {

using Clock = std::chrono::steady_clock;

// Without a cap, the most crossings (a triangle's fragment in a pixel) a tile may be estimated to
// hold before the tile is split. Larger tiles render more slowly (their fragments no longer stay
// in the caches while they are sorted and resolved): 859,000 crossings gave 777 tiles and 39.5 s
// on the --detail 3 bench scene on one thread, 1,243,000 gave 531 tiles and 42.0 s.
constexpr double kUncappedTileCrossings = 859'000;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A tile whose tessellations do not fit in the memory budget beside what other tiles hold.
struct TileDoesNotFit {
    std::string object;  // the object whose tessellation found no room
    uint64_t bytes = 0;  // its estimated size
    PixelRect tile;
};

class FrameRenderer {
public:
    FrameRenderer(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                  RenderStats& stats, const RenderOptions& options, cache::MemoryBudget& budget)
        : m_scene(scene), m_camera(camera), m_settings(settings), m_stats(stats), m_options(options),
          m_budget(budget), m_pattern(SubsamplePattern::forEdgeAntiAliasing(settings.edgeAntiAliasing)),
          m_filter(makePixelFilter(settings)),
          m_lazy(&budget) {}

    // The charge holding every thread's share of the tile buffers (`threads` shares), so that the
    // shares of the threads that idle while deferred tiles render one at a time go back to the
    // budget then.
    void setTileShares(cache::MemoryCharge* shares, int threads) {
        m_tileShares = shares;
        m_shareThreads = threads;
    }

    Framebuffer run();
    // Fills the memory figures of the stats from the budget and the process.
    void finishStats(const cache::MemoryBudget& budget) const;

private:
    void prepare();
    void prepareObject(uint32_t index);
    // The pixels an object's screen box must reach to be kept: the region widened by what the
    // tiles at its edges read around them.
    PixelRect objectReach() const {
        return {m_region.x0 - m_marginRight, m_region.y0 - m_marginBottom, m_region.x1 + m_marginLeft,
                m_region.y1 + m_marginTop};
    }
    void renderTile(size_t index, TileWorker& w);
    // Writes pixel (x, y)'s filtered colour sums (c premultiplied, a not clamped) over the background.
    void writeColor(int x, int y, const double* c, double a);
    // Tile `index` is rendered: what it kept for its neighbours' contrast tests may be read
    // (ContrastBorders), and with a multi-pixel filter the border pixels of the tiles around it
    // that are now ready are filtered (FilterBorders::tileDone) and what they no longer need given back.
    void bordersDone(size_t index, TileWorker& w);
    void returnDroppedMemory();
    void planFrameTiles();
    // Each kept object's screen box and triangles per scanline, for the tile plan.
    std::vector<ScreenCost> screenCosts() const;
    void rasterizeTile(const PixelRect& base, TileWorker& w);
    void addObjectTriangles(uint32_t unit, const PixelRect& base, TileWorker& w);
    const std::vector<glm::vec4>& clusterBoxes(TileWorker& w, uint32_t unit, const geom::Tessellation& g);
    bool copyPinnedUnits(TileWorker& w);
    // The topology of object `object` made in pieces, from the worker's table of its pieces.
    ObjectTopology piecesTopology(uint32_t object, const std::vector<TopologyPiece>& pieces) const {
        const std::span<const geom::SlotRun> runs = m_scene.objects[object].geometry->slotRuns();
        return ObjectTopology{nullptr, 0, pieces.data(), uint32_t(pieces.size()), runs.data(), uint32_t(runs.size())};
    }
    template <class Take>
    bool withRoom(TileWorker& w, uint64_t bytes, Take&& take, bool copyPinned = true);
    void holdCharge(TileWorker& w, cache::MemoryCharge& charge, uint64_t bytes);
    // `bytes` charged as geometry for something object `object` needs made, room made for it
    // (withRoom). Throws TileDoesNotFit, naming the object, when the budget cannot hold it.
    cache::MemoryCharge takeGeometryRoom(TileWorker& w, uint64_t bytes, uint32_t object);
    // Charges what the worker's buffers hold beyond its share, and `more` bytes about to be
    // allocated beside them.
    void chargeBuffers(TileWorker& w, uint64_t more = 0);
    void chargeBuffersAhead(TileWorker& w, uint64_t more);
    // What the worker's buffers hold, with `more` bytes beside them, beyond its share.
    uint64_t bufferBytesOverShare(const TileWorker& w, uint64_t more) const;
    // The tessellation (pinned by the tile) holding triangle id `triangle` of `object`, and the
    // triangle's index in it.
    std::pair<const geom::Tessellation*, uint32_t> triangleAt(const TileWorker& w, uint32_t object, uint32_t triangle) const;
    void requestSamples(TileWorker& w, uint32_t groupIndex, int px, int py, int first, int last, bool extra,
                        uint32_t firstTarget);
    void addSample(TileWorker& w, uint32_t object, uint32_t triangle, double rx, double ry, uint32_t target);
    void flush(TileWorker& w, PendingBatch& p);
    void flushAll(TileWorker& w);
    void fillSample(shade::ShadingBatch& b, int i, const TileWorker& w, uint32_t object, uint32_t triangle, double rx,
                    double ry) const;
    int baseSamples(const RenderObject& o) const;
    int maxSamples(const RenderObject& o) const;

    const FrameScene& m_scene;
    const RenderCamera& m_camera;
    const RenderSettings& m_settings;
    RenderStats& m_stats;
    const RenderOptions& m_options;
    cache::MemoryBudget& m_budget;
    SubsamplePattern m_pattern;
    PixelFilter m_filter;
    PixelRect m_region;                     // pixels rendered (the render region or the whole image)
    std::deque<ObjectView> m_views;         // per object (a deque: views do not move)
    std::deque<UnitView> m_units;           // per piece of each object's shape, object by object
    std::vector<PixelRect> m_tiles;
    LazyTessellations m_lazy;               // the tessellations, made when a tile first needs them
    RoomGate m_gate;                        // the threads' turns when a tile finds no room
    std::optional<TileIndex> m_tileIndex;    // which tile holds a pixel, for m_borders and m_contrast
    std::optional<FilterBorders> m_borders;  // with a multi-pixel filter: what tiles share for it
    std::vector<cache::MemoryCharge> m_borderCharges;  // per tile: what m_borders keeps of it
    std::optional<ContrastBorders> m_contrast;  // with adaptive shading: what tiles share for it
    std::vector<cache::MemoryCharge> m_contrastCharges;  // per tile: what m_contrast keeps of it
    uint64_t m_perThreadBytes = 0;          // the share of each worker's buffers charged up front
    cache::MemoryCharge* m_tileShares = nullptr;  // setTileShares
    int m_shareThreads = 1;
    std::atomic<uint64_t> m_droppedReturned{0};  // bytes the caches had dropped at the last return
    int m_marginLeft = 0, m_marginRight = 0, m_marginTop = 0, m_marginBottom = 0;
    bool m_adaptive = false;
    Framebuffer m_frame;
};

int FrameRenderer::baseSamples(const RenderObject& o) const {
    int n = o.shadingSamplesOverride ? o.shadingSamples : m_settings.shadingSamples;
    return std::clamp(n, 1, m_pattern.count);
}

int FrameRenderer::maxSamples(const RenderObject& o) const {
    int n = o.shadingSamplesOverride ? o.maxShadingSamples : m_settings.maxShadingSamples;
    return std::clamp(n, baseSamples(o), m_pattern.count);
}

void FrameRenderer::prepareObject(uint32_t index) {
    const RenderObject& obj = m_scene.objects[index];
    ObjectView& v = m_views[index];
    static_cast<ObjectPlacement&>(v) = placeObject(obj.geometry->bounds(), obj.worldFromObject, m_camera, objectReach());
    if (!v.kept) return;

    v.slotLights.resize(obj.materials.size());
    v.slotTransparent.resize(obj.materials.size());
    for (size_t s = 0; s < obj.materials.size(); ++s) {
        const MaterialSlot& slot = obj.materials[s];
        for (uint32_t li : slot.lights)
            if (li < m_scene.lights.size())
                v.slotLights[s].push_back(shade::transformed(m_scene.lights[li], m_camera.cameraFromWorld));
        if (m_scene.usesDefaultLight) v.slotLights[s].push_back(shade::defaultLight(glm::dvec3(0.0, 0.0, -1.0)));
        const auto& network = m_scene.shadingGroups[slot.shadingGroup].network;
        v.slotTransparent[s] = network && network->mayBeTransparent();
        v.mayOcclude = v.mayOcclude || !v.slotTransparent[s];
    }
}

void FrameRenderer::prepare() {
    auto t0 = Clock::now();
    const size_t n = m_scene.objects.size();
    for (size_t i = 0; i < n; ++i) m_views.emplace_back();
    tbb::parallel_for(size_t(0), n, [&](size_t i) { prepareObject(uint32_t(i)); });
    // The units: a kept object's pieces each placed by their own bounds (a shape in one piece
    // takes the object's placement).
    for (size_t i = 0; i < n; ++i) {
        ObjectView& v = m_views[i];
        v.firstUnit = uint32_t(m_units.size());
        v.unitCount = uint32_t(m_scene.objects[i].geometry->pieceCount());
        for (uint32_t k = 0; k < v.unitCount; ++k) {
            UnitView& u = m_units.emplace_back();
            u.object = uint32_t(i);
            u.piece = k;
        }
    }
    const PixelRect reach = objectReach();
    tbb::parallel_for(size_t(0), m_units.size(), [&](size_t i) {
        UnitView& u = m_units[i];
        const ObjectView& v = m_views[u.object];
        if (!v.kept) return;
        ObjectPlacement place = v;
        if (v.unitCount > 1) {
            const RenderObject& obj = m_scene.objects[u.object];
            place = placeObject(obj.geometry->pieceBounds(u.piece), obj.worldFromObject, m_camera, reach);
        }
        u.kept = place.kept;
        u.x0 = place.x0, u.y0 = place.y0, u.x1 = place.x1, u.y1 = place.y1;
        u.nearKey = place.nearKey, u.farKey = place.farKey;
    });
    m_stats.objects = n;
    std::unordered_set<const geom::GeometryHandle*> shapes;
    for (size_t i = 0; i < n; ++i) {
        const ObjectView& v = m_views[i];
        if (!v.kept) {
            ++(v.culledFar ? m_stats.objectsCulledFar : m_stats.objectsCulledFrustum);
            continue;
        }
        m_stats.triangles += m_scene.objects[i].geometry->triangleCount();
        ++m_stats.tessellationInstances;
        shapes.insert(m_scene.objects[i].geometry.get());
    }
    m_stats.tessellationShapes = shapes.size();
    planFrameTiles();
    m_stats.prepareSeconds += secondsSince(t0);
}

// Fixed tiles (forceTileSize, -tw/-th) or without a cap; under a cap, the memory-driven plan:
// each kept object's screen box with its triangles per scanline at its screen height, against
// the maxTileCost the budget left after the frame's own charges allows. An object's cost per
// scanline is its triangle crossings weighed by the fragments each leaves (1 + the width of a
// cell of the square grid its triangles make over its box).
void FrameRenderer::planFrameTiles() {
    // -tw/-th (forceTileSize): the fixed grid as asked. Under a cap, tiles are taken along the
    // Hilbert curve, so that the next tile (or a thread's next) meets what the last one made while
    // it is still cached.
    const bool capped = m_budget.capBytes() != 0;
    if (m_settings.forceTileSize) {
        std::vector<PixelRect> rowMajor =
            planTiles(m_region, std::max(1, m_settings.tileWidth), std::max(1, m_settings.tileHeight));
        m_tiles = capped ? alongHilbertCurve(rowMajor) : rowMajor;
        if (!m_options.tilePlan) return;
        TilePlan& plan = *m_options.tilePlan;
        plan = TilePlan{};
        plan.tiles = std::move(rowMajor);
        plan.maxTileCost = std::numeric_limits<double>::infinity();
        const std::vector<ScreenCost> costs = screenCosts();
        for (const PixelRect& t : plan.tiles) plan.cost.push_back(tileCost(t, costs));
        return;
    }
    const std::vector<ScreenCost> costs = screenCosts();
    TilePlan plan;
    if (!capped) {
        // The fixed grid, with a tile of more than kUncappedTileCrossings split down to 16×16: a
        // dense corner, or a small frame of a heavy scene, then spreads over tiles and threads
        // instead of one tile's buffers holding all its fragments.
        m_stats.maxTileCost = kUncappedTileCrossings / double(std::max(1, m_settings.tileHeight));
        const std::vector<PixelRect> grid =
            planTiles(m_region, std::max(1, m_settings.tileWidth), std::max(1, m_settings.tileHeight));
        plan = splitTiles(grid, costs, m_stats.maxTileCost, 16);
        m_tiles = plan.tiles;
    } else {
        const int threads = std::max(1, tbb::this_task_arena::max_concurrency());
        const uint64_t available = m_budget.availableBytes();
        m_stats.maxTileCost = maxTileCost(available / 2 / uint64_t(threads), m_settings, (m_region.height() + 1) / 2);
        plan = planAdaptiveTiles(m_region, costs, m_stats.maxTileCost, 16);
        m_tiles = alongHilbertCurve(plan.tiles);
    }
    if (m_options.tilePlan) *m_options.tilePlan = std::move(plan);
}

std::vector<ScreenCost> FrameRenderer::screenCosts() const {
    std::vector<ScreenCost> costs;
    const double far = 1e7;  // boxes that reach everywhere (crossing the near plane) are clamped
    for (uint32_t i = 0; i < m_views.size(); ++i) {
        const ObjectView& v = m_views[i];
        if (!v.kept) continue;
        ScreenCost c;
        c.x0 = std::clamp(v.x0, -far, far), c.x1 = std::clamp(v.x1, -far, far);
        c.y0 = std::clamp(v.y0, -far, far), c.y1 = std::clamp(v.y1, -far, far);
        // A triangle meets a row in about (its width + 1) fragments: weigh the crossings by the
        // width of a cell of the square grid its triangles make over the box.
        const geom::GeometryHandle& h = *m_scene.objects[i].geometry;
        const double columns = std::max(1.0, std::sqrt(double(h.triangleCount()) * 0.5));
        const double width = std::min(c.x1, double(m_region.x1)) - std::max(c.x0, double(m_region.x0));
        c.trianglesPerScanline = h.trianglesPerScanline(c.y1 - c.y0) * (1.0 + std::max(0.0, width) / columns);
        costs.push_back(c);
    }
    return costs;
}

namespace {
// The nearest float at or below (floatBelow) or above (floatAbove) d, so that a box kept in floats
// holds the box it was computed as.
float floatBelow(double d) {
    float f = float(d);
    if (double(f) > d) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return f;
}
float floatAbove(double d) {
    float f = float(d);
    if (double(f) < d) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return f;
}
}  // namespace

// Made once per unit and kept for the frame, charged as geometry. The room is taken before the
// boxes are claimed for making: a thread that waits for room (withRoom) must not hold the
// once_flag another thread waits on.
const std::vector<glm::vec4>& FrameRenderer::clusterBoxes(TileWorker& w, uint32_t unit, const geom::Tessellation& g) {
    UnitView& u = m_units[unit];
    if (u.clustersReady.load(std::memory_order_acquire)) return u.clusterBoxes;
    cache::MemoryCharge room = takeGeometryRoom(w, uint64_t(g.clusterBounds.size()) * sizeof(glm::vec4), u.object);
    const ObjectView& v = m_views[u.object];
    std::call_once(u.clustersMade, [&] {
        u.clusterBoxes.resize(g.clusterBounds.size());
        const double inf = std::numeric_limits<double>::infinity();
        for (size_t c = 0; c < g.clusterBounds.size(); ++c) {
            const geom::Bounds3 cb = g.clusterBounds[c].transformed(v.cameraFromObject);
            glm::dvec4 box(inf, inf, -inf, -inf);  // reaches no tile
            if (cb.empty() || -cb.lo.z < m_camera.nearClipPlane) {
                // empty, or wholly in front of the near plane: every triangle would be clipped away
            } else if (!std::isfinite(cb.lo.x + cb.lo.y + cb.hi.x + cb.hi.y + cb.lo.z + cb.hi.z) ||
                       -cb.hi.z < m_camera.nearClipPlane) {
                box = glm::dvec4(-inf, -inf, inf, inf);  // crosses the near plane: clipped per triangle
            } else {
                for (int k = 0; k < 8; ++k) {
                    glm::dvec3 p((k & 1) ? cb.hi.x : cb.lo.x, (k & 2) ? cb.hi.y : cb.lo.y, (k & 4) ? cb.hi.z : cb.lo.z);
                    const glm::dvec2 r = m_camera.rasterFromCamera(p);
                    box = glm::dvec4(std::min(box.x, r.x), std::min(box.y, r.y), std::max(box.z, r.x), std::max(box.w, r.y));
                }
            }
            u.clusterBoxes[c] = glm::vec4(floatBelow(box.x), floatBelow(box.y), floatAbove(box.z), floatAbove(box.w));
        }
        u.clusterCharge = std::move(room);
        u.clustersReady.store(true, std::memory_order_release);
    });
    return u.clusterBoxes;
}

std::pair<const geom::Tessellation*, uint32_t> FrameRenderer::triangleAt(const TileWorker& w, uint32_t object,
                                                                        uint32_t triangle) const {
    const ObjectView& v = m_views[object];
    size_t unit = v.firstUnit;
    uint32_t local = triangle;
    if (v.unitCount != 1) {
        const geom::GeometryHandle::PiecePlace place = m_scene.objects[object].geometry->placeOf(triangle);
        unit += place.piece;
        local = place.local;
    }
    if (const std::vector<uint32_t>* ids = w.copiedIds[unit])
        local = uint32_t(std::lower_bound(ids->begin(), ids->end(), local) - ids->begin());
    return {w.tessellation[unit], local};
}

// Calls `take` (which tries to charge `bytes` more to the budget) until it succeeds: as things
// stand, then after dropping unpinned tessellations and meshes (their memory handed back), then
// once more after copying the tile's pinned units (copyPinnedUnits) and dropping those too (when
// `copyPinned`: not while the tile's pinned triangles are being read), then each time a tile of
// another thread has ended (RoomGate), while one is running. Returns whether it succeeded.
template <class Take>
bool FrameRenderer::withRoom(TileWorker& w, uint64_t bytes, Take&& take, bool copyPinned) {
    std::optional<RoomGate::Turn> turn;
    for (bool copied = false;;) {
        if (take()) return true;
        if (m_lazy.reclaim(bytes)) {
            returnDroppedMemory();
            if (take()) return true;
        }
        if (copyPinned && !copied && copyPinnedUnits(w)) {
            copied = true;
            continue;
        }
        if (!turn) turn.emplace(m_gate);
        if (!turn->wait()) return false;
    }
}

cache::MemoryCharge FrameRenderer::takeGeometryRoom(TileWorker& w, uint64_t bytes, uint32_t object) {
    std::optional<cache::MemoryCharge> room;
    if (!withRoom(w, bytes, [&] {
            room = cache::MemoryCharge::tryCharge(m_budget, cache::MemoryCategory::Geometry, bytes);
            return room.has_value();
        }))
        throw TileDoesNotFit{m_scene.objects[object].name, bytes};
    return std::move(*room);
}

// Resizes `charge` to `bytes`, making room (withRoom) for what it grows by. Throws TileDoesNotFit
// (no object named) when the budget cannot hold it.
void FrameRenderer::holdCharge(TileWorker& w, cache::MemoryCharge& charge, uint64_t bytes) {
    if (bytes <= charge.bytes()) {
        charge.resize(bytes);
        return;
    }
    const uint64_t more = bytes - charge.bytes();
    if (!withRoom(w, more, [&] { return charge.tryResize(bytes); })) throw TileDoesNotFit{std::string(), more};
}

// Charges what the worker's tile buffers have grown to beyond the share frameMemory() charged up
// front, as the tile goes.
void FrameRenderer::chargeBuffers(TileWorker& w, uint64_t more) {
    holdCharge(w, w.bufferCharge, bufferBytesOverShare(w, more));
}

uint64_t FrameRenderer::bufferBytesOverShare(const TileWorker& w, uint64_t more) const {
    const uint64_t held = w.bytes() + more;
    return held > m_perThreadBytes ? held - m_perThreadBytes : 0;
}

// chargeBuffers while the rasterizer runs, before its buffers grow by `more`: room is made from what
// the caches hold unpinned only (the tile's pinned triangles are being read), and when that is
// not enough the growth goes ahead, charged by the next chargeBuffers.
void FrameRenderer::chargeBuffersAhead(TileWorker& w, uint64_t more) {
    const uint64_t bytes = bufferBytesOverShare(w, more);
    cache::MemoryCharge& charge = w.bufferCharge;
    if (bytes <= charge.bytes()) return;
    withRoom(w, bytes - charge.bytes(), [&] { return charge.tryResize(bytes); }, false);
}

// Gives back the pins of the tile's units that a copy of the triangles they gave the rasterizer
// would hold in less memory, shading from the copies instead (TileCopy), so that a tile which
// meets more pieces than the budget holds at once still renders: what the copies keep grows with
// the triangles that reach the tile, not with the pieces they come from. Returns whether a pin
// was given back. The image is the same: a copy holds the same numbers for every triangle that
// can have a fragment.
bool FrameRenderer::copyPinnedUnits(TileWorker& w) {
    if (!m_options.copyPinnedTriangles) return false;
    bool released = false;
    for (size_t k = 0; k < w.pins.size();) {
        const uint32_t unit = w.pinnedUnits[k];
        const geom::Tessellation& g = *w.tessellation[unit];
        std::span<const uint32_t> kept;
        for (const TileWorker::SubmittedRun& r : w.submittedRuns)
            if (r.unit == unit) kept = std::span<const uint32_t>(w.submitted.data() + r.begin, r.end - r.begin);
        const size_t n = kept.size();
        // The vertices the kept triangles use (charged while they are found), then the copy.
        std::optional<cache::MemoryCharge> scratch =
            cache::MemoryCharge::tryCharge(m_budget, cache::MemoryCategory::Tessellation, 3 * n * sizeof(uint32_t));
        if (!scratch) break;
        std::vector<uint32_t> vertices = geom::triangleVertices(g, kept);
        const uint64_t bytes =
            sizeof(TileCopy) + geom::copiedTrianglesBytes(g, n, vertices.size()) + n * sizeof(uint32_t);
        std::optional<cache::MemoryCharge> charge;
        if (bytes < g.bytes()) charge = cache::MemoryCharge::tryCharge(m_budget, cache::MemoryCategory::Tessellation, bytes);
        if (!charge) {
            ++k;
            continue;
        }
        auto copy = std::make_unique<TileCopy>();
        geom::Tessellation& c = copy->tessellation;
        c = geom::copyTriangles(g, kept, vertices);
        copy->ids.assign(kept.begin(), kept.end());
        util::release(vertices);
        scratch.reset();
        copy->charge = std::move(*charge);
        copy->charge.resize(sizeof(TileCopy) + c.bytes() + uint64_t(copy->ids.capacity()) * sizeof(uint32_t));

        const UnitView& u = m_units[unit];
        const ObjectView& v = m_views[u.object];
        std::vector<TopologyPiece>& pieces = w.pieceTopology[u.object];
        if (v.unitCount == 1) pieces.assign(1, TopologyPiece{});
        TopologyPiece& piece = pieces[u.piece];
        piece.triangleCount = uint32_t(n);
        piece.neighbors = c.neighbors.data();
        piece.ids = copy->ids.data();
        w.topology[u.object] = piecesTopology(u.object, pieces);
        w.tessellation[unit] = &c;
        w.copiedIds[unit] = &copy->ids;
        w.copies.push_back(std::move(copy));
        w.pins[k] = std::move(w.pins.back());
        w.pins.pop_back();
        w.pinnedUnits[k] = w.pinnedUnits.back();
        w.pinnedUnits.pop_back();
        ++w.stats.tileCopies;
        released = true;
    }
    return released;
}

// Projects the triangles of one object that may reach `base` (the tile and its apron) into the
// tile's rasterizer: clusters whose screen box misses `base` are passed over, then each triangle
// is culled (back faces of single-sided objects), clipped at the near plane and projected, the
// same arithmetic whichever tile does it.
void FrameRenderer::addObjectTriangles(uint32_t unit, const PixelRect& base, TileWorker& w) {
    const uint32_t index = m_units[unit].object;
    const RenderObject& obj = m_scene.objects[index];
    const ObjectView& v = m_views[index];
    const geom::Tessellation& g = *w.tessellation[unit];
    // The triangle ids of the piece's triangles, run by run (t ascending below).
    const std::span<const geom::SlotRun> runs = obj.geometry->pieceSlotRuns(m_units[unit].piece);
    size_t run = 0;
    auto idOf = [&](uint32_t t) {
        while (run + 1 < runs.size() && runs[run + 1].local <= t) ++run;
        return runs[run].firstSlot + (t - runs[run].local);
    };
    const std::vector<glm::vec4>& boxes = clusterBoxes(w, unit, g);
    RenderStats& st = w.stats;
    const double nearZ = -m_camera.nearClipPlane;
    const size_t triangles = g.triangleCount();
    // Under a cap the tile notes which triangles it rasterized, so that it can copy them and let
    // the tessellation go (copyPinnedUnits).
    const bool record = m_budget.capBytes() != 0 && m_options.copyPinnedTriangles;
    const uint32_t runBegin = uint32_t(w.submitted.size());
    for (size_t cluster = 0; cluster < boxes.size(); ++cluster) {
        const glm::vec4& box = boxes[cluster];
        if (box.z < base.x0 || box.x > base.x1 || box.w < base.y0 || box.y > base.y1) continue;
        const size_t end = std::min(triangles, (cluster + 1) * geom::Tessellation::kClusterTriangles);
        for (size_t t = cluster * geom::Tessellation::kClusterTriangles; t < end; ++t) {
            glm::dvec3 c[3];
            for (int k = 0; k < 3; ++k) c[k] = cameraPoint(v.cameraFromObject, g.position(3 * t + size_t(k)));
            glm::dvec3 n = glm::cross(c[1] - c[0], c[2] - c[0]);
            if (obj.opposite) n = -n;
            if (!obj.doubleSided) {
                glm::dvec3 view = m_camera.orthographic ? glm::dvec3(0.0, 0.0, -1.0) : c[0];
                if (glm::dot(n, view) >= 0.0) {
                    ++st.trianglesBackfacing;
                    continue;
                }
            }
            glm::dvec3 poly[4];
            int count = clipNear(c, nearZ, poly);
            if (count < 3) {
                ++st.trianglesOutside;
                continue;
            }
            if (count != 3 || poly[0] != c[0] || poly[1] != c[1] || poly[2] != c[2]) ++st.trianglesNearClipped;
            ScreenTriangle s;
            s.object = index;
            s.triangle = idOf(uint32_t(t));
            const uint16_t slot = t < g.material.size() ? g.material[t] : 0;
            s.transparent = slot < v.slotTransparent.size() && v.slotTransparent[slot];
            glm::dvec2 r[4];
            double z[4];
            for (int k = 0; k < count; ++k) {
                r[k] = m_camera.rasterFromCamera(poly[k]);
                z[k] = m_camera.depthKey(poly[k]);
            }
            for (int k = 1; k + 1 < count; ++k) {
                const int idx[3] = {0, k, k + 1};
                double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
                for (int j = 0; j < 3; ++j) {
                    s.x[j] = r[idx[j]].x;
                    s.y[j] = r[idx[j]].y;
                    s.z[j] = z[idx[j]];
                    x0 = std::min(x0, s.x[j]), x1 = std::max(x1, s.x[j]);
                    y0 = std::min(y0, s.y[j]), y1 = std::max(y1, s.y[j]);
                }
                if (x1 < base.x0 || x0 > base.x1 || y1 < base.y0 || y0 > base.y1) continue;
                w.rasterizer.add(s);
                if (record && (w.submitted.size() == runBegin || w.submitted.back() != uint32_t(t)))
                    w.submitted.push_back(uint32_t(t));
            }
        }
    }
    if (w.submitted.size() > runBegin) w.submittedRuns.push_back({unit, runBegin, uint32_t(w.submitted.size())});
}

// The tile's objects front to back, their tessellations pinned (made on first need, shared by
// instances), their triangles rasterized into `base`. Throws TileDoesNotFit when a tessellation
// cannot be made room for in the budget.
//
// Occlusion (DESIGN.md step 5a): an object whose box within `base` lies wholly behind the far
// ends of nearer objects that may be opaque, and whose box they could cover between them, waits
// until the others are rasterized. Then every pixel it reaches is asked for its occluding depth
// (PixelResolver::occludingDepth); an object behind it in every one of them adds nothing to the
// image and is neither tessellated nor rasterized (skippedOccluded). Any other waiting object is
// rasterized as usual: the skip changes no bit, only the work done.
void FrameRenderer::rasterizeTile(const PixelRect& base, TileWorker& w) {
    w.tileObjects.clear();
    for (uint32_t i = 0; i < m_units.size(); ++i)
        if (m_units[i].kept && reaches(m_units[i], base)) w.tileObjects.push_back(i);
    sortNearestFirst(w.tileObjects, [&](uint32_t i) { return m_units[i].nearKey; });
    w.rasterizer.reset(base);

    auto rasterize = [&](uint32_t unit) {
        const uint32_t i = m_units[unit].object, piece = m_units[unit].piece;
        const geom::GeometryHandle* handle = m_scene.objects[i].geometry.get();
        // Room for `bytes` while something is made (withRoom).
        auto takeRoom = [&](uint64_t bytes) { return takeGeometryRoom(w, bytes, i); };
        std::optional<LazyTessellations::Pin> pin;
        try {
            pin = m_lazy.acquire(*handle, piece, takeRoom);
        } catch (const TessellationDoesNotFit& e) {
            throw TileDoesNotFit{m_scene.objects[i].name, e.bytes};
        }
        const geom::Tessellation& made = **pin;
        w.tessellation[unit] = &made;
        if (m_views[i].unitCount == 1) {
            w.topology[i] = {made.neighbors.data(), uint32_t(made.triangleCount())};
        } else {
            std::vector<TopologyPiece>& pieces = w.pieceTopology[i];
            if (pieces.empty()) pieces.resize(m_views[i].unitCount);
            pieces[piece].triangleCount = uint32_t(made.triangleCount());
            pieces[piece].neighbors = made.neighbors.data();
            w.topology[i] = piecesTopology(i, pieces);
        }
        w.pins.push_back(std::move(*pin));
        w.pinnedUnits.push_back(unit);
        ++w.stats.objectTileVisits;
        addObjectTriangles(unit, base, w);
    };

    // Nearer objects that may hide the ones behind them, and those waiting behind them.
    w.occluders.clear();
    w.waiting.clear();
    PixelRect waitingReach{base.x1, base.y1, base.x0, base.y0};
    for (uint32_t i : w.tileObjects) {
        const UnitView& v = m_units[i];
        const PixelRect reach = reachOf(v, base);
        if (m_options.skipOccluded && w.occluders.mayHide(reach, v.nearKey)) {
            w.waiting.push_back(i);
            waitingReach = {std::min(waitingReach.x0, reach.x0), std::min(waitingReach.y0, reach.y0),
                            std::max(waitingReach.x1, reach.x1), std::max(waitingReach.y1, reach.y1)};
            continue;
        }
        rasterize(i);
        if (m_views[v.object].mayOcclude) w.occluders.add(reach, v.farKey);
    }

    bool finished = false;  // whether the fragments are sorted with every object rasterized so far
    if (!w.waiting.empty()) {
        w.rasterizer.finish();
        finished = true;
        w.occlusion.reset(base);
        for (int y = waitingReach.y0; y < waitingReach.y1; ++y)
            for (int x = waitingReach.x0; x < waitingReach.x1; ++x) {
                std::span<const Fragment> frags = w.rasterizer.fragments(x, y);
                if (!frags.empty()) w.occlusion.set(x, y, w.resolver.occludingDepth(frags));
            }
        w.occlusion.finish();
        for (uint32_t i : w.waiting) {
            if (w.occlusion.hides(reachOf(m_units[i], base), m_units[i].nearKey)) {
                ++w.stats.skippedOccluded;
                continue;
            }
            rasterize(i);
            finished = false;
        }
    }
    if (!finished) w.rasterizer.finish();
}

void FrameRenderer::fillSample(shade::ShadingBatch& b, int i, const TileWorker& w, uint32_t object, uint32_t triangle,
                               double rx, double ry) const {
    const RenderObject& obj = m_scene.objects[object];
    const ObjectView& co = m_views[object];
    const auto [tessellation, local] = triangleAt(w, object, triangle);
    const geom::Tessellation& g = *tessellation;
    ShadingTriangle t;
    t.hasUvs = !g.uvs.empty();
    t.opposite = obj.opposite;
    for (int k = 0; k < 3; ++k) {
        const uint32_t v = g.corners[3 * size_t(local) + size_t(k)];
        t.p[k] = cameraPoint(co.cameraFromObject, g.positions[v]);
        t.n[k] = cameraNormal(co.normalToCamera, g.normals[v]);
        if (t.hasUvs) t.uv[k] = glm::dvec2(g.uvs[v]);
    }
    glm::dvec3 origin, dir;
    m_camera.rayThrough(rx, ry, origin, dir);
    const ShadingPoint s = shadingPointOn(t, origin, dir);
    const glm::dvec3& p = s.position;
    b.px[i] = float(p.x), b.py[i] = float(p.y), b.pz[i] = float(p.z);
    b.nx[i] = float(s.shadingNormal.x), b.ny[i] = float(s.shadingNormal.y), b.nz[i] = float(s.shadingNormal.z);
    b.gx[i] = float(s.geometricNormal.x), b.gy[i] = float(s.geometricNormal.y), b.gz[i] = float(s.geometricNormal.z);
    b.rx[i] = float(dir.x), b.ry[i] = float(dir.y), b.rz[i] = float(dir.z);
    b.u[i] = float(s.uv.x), b.v[i] = float(s.uv.y);
    b.tux[i] = float(s.tangentU.x), b.tuy[i] = float(s.tangentU.y), b.tuz[i] = float(s.tangentU.z);
    b.tvx[i] = float(s.tangentV.x), b.tvy[i] = float(s.tangentV.y), b.tvz[i] = float(s.tangentV.z);
    glm::dvec3 pw(m_camera.worldFromCamera * glm::dvec4(p, 1.0));
    glm::dvec3 po(co.objectFromCamera * glm::dvec4(p, 1.0));
    b.wx[i] = float(pw.x), b.wy[i] = float(pw.y), b.wz[i] = float(pw.z);
    b.ox[i] = float(po.x), b.oy[i] = float(po.y), b.oz[i] = float(po.z);
    b.pixelX[i] = float(std::floor(rx) + 0.5), b.pixelY[i] = float(std::floor(ry) + 0.5);
    b.flipped[i] = s.flipped ? 1 : 0;
}

void FrameRenderer::flush(TileWorker& w, PendingBatch& p) {
    shade::ShadingBatch& b = *p.batch;
    if (b.count == 0) return;
    const RenderObject& obj = m_scene.objects[p.object];
    const MaterialSlot& slot = obj.materials[p.slot];
    const auto& network = m_scene.shadingGroups[slot.shadingGroup].network;
    shade::ShadingResult& r = *w.result;
    network->evaluate(b, m_views[p.object].slotLights[p.slot], w.scratch, r);
    for (int i = 0; i < b.count; ++i) {
        uint32_t t = p.target[size_t(i)];
        SampleResult& s = (t & 0x80000000u) ? w.extraSamples[t & 0x7fffffffu] : w.samples[t];
        s.color[0] = r.cr[i], s.color[1] = r.cg[i], s.color[2] = r.cb[i];
        s.transparency[0] = r.tr[i], s.transparency[1] = r.tg[i], s.transparency[2] = r.tb[i];
    }
    b.count = 0;
}

void FrameRenderer::flushAll(TileWorker& w) {
    for (size_t i = 0; i < w.pendingCount; ++i) flush(w, w.pending[i]);
}

void FrameRenderer::addSample(TileWorker& w, uint32_t object, uint32_t triangle, double rx, double ry, uint32_t target) {
    const auto [g, local] = triangleAt(w, object, triangle);
    uint32_t slot = local < g->material.size() ? g->material[local] : 0;
    auto [it, inserted] = w.pendingIndex.try_emplace((uint64_t(object) << 32) | slot, uint32_t(w.pendingCount));
    if (inserted) {
        if (w.pendingCount == w.pending.size()) w.pending.emplace_back();
        PendingBatch& fresh = w.pending[w.pendingCount++];
        fresh.object = object;
        fresh.slot = slot;
        fresh.batch->count = 0;
        fresh.batch->objectId = object;
    }
    PendingBatch* p = &w.pending[it->second];
    shade::ShadingBatch& b = *p->batch;
    fillSample(b, b.count, w, object, triangle, rx, ry);
    p->target[size_t(b.count)] = target;
    if (++b.count == shade::kBatchSize) flush(w, *p);
}

// Shading positions of a surface: its visible sub-samples in the pattern's stratified order,
// samples [first, last); a surface with no visible sub-sample (a sliver between sub-samples)
// is shaded once at its centroid.
void FrameRenderer::requestSamples(TileWorker& w, uint32_t groupIndex, int px, int py, int first, int last, bool extra,
                                   uint32_t firstTarget) {
    const SurfaceGroup& g = w.groups[groupIndex];
    int k = 0;
    uint32_t slot = firstTarget;
    if (g.visibleMask == 0) {
        if (first == 0 && last > 0) {
            const Fragment* largest = &surfaceMemberAt(w.rasterizer.sortedFragments(), g, -1);
            addSample(w, g.object, largest->triangle, px + double(largest->cu), py + double(largest->cv),
                      extra ? (slot | 0x80000000u) : slot);
        }
        return;
    }
    for (int o = 0; o < m_pattern.count && k < last; ++o) {
        int bit = m_pattern.order[size_t(o)];
        if (!((g.visibleMask >> bit) & 1u)) continue;
        if (k >= first) {
            const Fragment* member = &surfaceMemberAt(w.rasterizer.sortedFragments(), g, bit);
            double rx = px + ((bit % kSubsampleGrid) + 0.5) / kSubsampleGrid;
            double ry = py + ((bit / kSubsampleGrid) + 0.5) / kSubsampleGrid;
            addSample(w, g.object, member->triangle, rx, ry, extra ? (slot | 0x80000000u) : slot);
            ++slot;
        }
        ++k;
    }
}

// Under a cap, what the caches drop and what making tessellations used goes back to the system
// every 64 MB or so (after a tile, and before making something the caches dropped room for): the
// allocator keeps freed pages between live blocks otherwise, and the process's resident size
// would grow past what is charged.
void FrameRenderer::returnDroppedMemory() {
#ifdef __GLIBC__
    constexpr uint64_t kEvery = uint64_t(64) << 20;
    if (m_budget.capBytes() == 0) return;
    const uint64_t dropped = m_lazy.tessellationStats().evictedBytes + m_lazy.meshStats().evictedBytes + m_lazy.transientFreed();
    uint64_t last = m_droppedReturned.load(std::memory_order_relaxed);
    if (dropped - last < kEvery || !m_droppedReturned.compare_exchange_strong(last, dropped)) return;
    malloc_trim(0);
#endif
}

void FrameRenderer::renderTile(size_t index, TileWorker& w) {
    auto tRaster = Clock::now();
    const PixelRect& tile = m_tiles[index];
    // The pixels whose base colours the contrast test reads, and the base region rendered: the
    // tile, widened only where those pixels lie in tiles not done yet (the rest come from what
    // the tiles around kept, ContrastBorders).
    const PixelRect colorsRect{std::max(m_region.x0, tile.x0 - m_marginLeft), std::max(m_region.y0, tile.y0 - m_marginTop),
                               std::min(m_region.x1, tile.x1 + m_marginRight), std::min(m_region.y1, tile.y1 + m_marginBottom)};
    const PixelRect base = m_contrast ? m_contrast->baseFor(index) : colorsRect;
    const int bw = base.width(), bh = base.height();
    auto baseIndex = [&](int x, int y) { return size_t(y - base.y0) * bw + (x - base.x0); };

    // The tile's pins and per-object entries are given back however the tile ends.
    struct TileScope {
        TileWorker& w;
        const FrameRenderer& renderer;
        ~TileScope() { release(); }
        void release() {
            for (uint32_t i : w.tileObjects) {
                const UnitView& u = renderer.m_units[i];
                w.tessellation[i] = nullptr;
                w.copiedIds[i] = nullptr;
                w.topology[u.object] = ObjectTopology{};
                if (std::vector<TopologyPiece>& pieces = w.pieceTopology[u.object]; u.piece < pieces.size()) {
                    pieces[u.piece].triangleCount = 0;
                    pieces[u.piece].neighbors = nullptr;
                    pieces[u.piece].ids = nullptr;
                }
            }
            w.tileObjects.clear();
            w.pins.clear();
            w.pinnedUnits.clear();
            w.copies.clear();
            w.submitted.clear();
            w.submittedRuns.clear();
        }
    } scope{w, *this};
    TileRasterizer& rast = w.rasterizer;
    rasterizeTile(base, w);
    chargeBuffers(w);
    w.stats.rasterSeconds += secondsSince(tRaster);

    // Resolve every pixel of the base region and keep its surfaces. A surface's members are the
    // pixel's fragments, put in the order of the surfaces where the rasterizer holds them.
    auto tResolve = Clock::now();
    w.pixelGroupStart.assign(size_t(bw) * bh + 1, 0);
    w.groups.clear();
    w.nearestDepth.assign(size_t(bw) * bh, std::numeric_limits<float>::infinity());
    const Fragment* const sorted = rast.sortedFragments().data();
    for (int y = base.y0; y < base.y1; ++y)
        for (int x = base.x0; x < base.x1; ++x) {
            size_t pi = baseIndex(x, y);
            w.pixelGroupStart[pi] = uint32_t(w.groups.size());
            std::span<const Fragment> frags = rast.fragments(x, y);
            if (frags.empty()) continue;
            w.resolver.resolve(frags);
            const uint32_t memberBase = uint32_t(frags.data() - sorted);
            rast.reorderPixel(x, y, w.resolver.members());
            for (SurfaceGroup g : w.resolver.groups()) {
                g.memberBegin += memberBase;
                w.groups.push_back(g);
            }
            w.nearestDepth[pi] = w.resolver.nearestDepth();
        }
    w.pixelGroupStart[size_t(bw) * bh] = uint32_t(w.groups.size());
    chargeBuffers(w);
    w.stats.resolveSeconds += secondsSince(tResolve);

    // Base shading of every visible surface.
    auto tShade = Clock::now();
    const size_t groupCount = w.groups.size();
    w.groupSampleStart.assign(groupCount + 1, 0);
    uint32_t total = 0;
    for (size_t gi = 0; gi < groupCount; ++gi) {
        w.groupSampleStart[gi] = total;
        const SurfaceGroup& g = w.groups[gi];
        if (g.coverage <= 0.0f) continue;
        int n = baseSamples(m_scene.objects[g.object]);
        int avail = g.visibleMask ? std::popcount(g.visibleMask) : 1;
        total += uint32_t(std::min(n, avail));
    }
    w.groupSampleStart[groupCount] = total;
    w.samples.assign(total, SampleResult{});
    w.pendingCount = 0;
    w.pendingIndex.clear();
    for (int y = base.y0; y < base.y1; ++y)
        for (int x = base.x0; x < base.x1; ++x) {
            size_t pi = baseIndex(x, y);
            for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                uint32_t n = w.groupSampleStart[gi + 1] - w.groupSampleStart[gi];
                if (n) requestSamples(w, gi, x, y, 0, int(n), false, w.groupSampleStart[gi]);
            }
        }
    flushAll(w);
    for (int y = tile.y0; y < tile.y1; ++y) {
        size_t p0 = baseIndex(tile.x0, y), p1 = baseIndex(tile.x1 - 1, y) + 1;
        w.stats.shadingSamplesBase += w.groupSampleStart[w.pixelGroupStart[p1]] - w.groupSampleStart[w.pixelGroupStart[p0]];
    }

    // Surface shades from the base samples (mean in sample order).
    w.shades.assign(groupCount, SurfaceShade{});
    auto averageShade = [&](size_t gi) {
        SurfaceShade s;
        uint32_t b0 = w.groupSampleStart[gi], b1 = w.groupSampleStart[gi + 1];
        uint32_t e0 = w.groupExtraStart.empty() ? 0 : w.groupExtraStart[gi];
        uint32_t e1 = w.groupExtraStart.empty() ? 0 : w.groupExtraStart[gi + 1];
        uint32_t n = (b1 - b0) + (e1 - e0);
        if (n == 0) return s;
        double c[3] = {0, 0, 0}, t[3] = {0, 0, 0};
        for (uint32_t i = b0; i < b1; ++i)
            for (int k = 0; k < 3; ++k) c[k] += w.samples[i].color[k], t[k] += w.samples[i].transparency[k];
        for (uint32_t i = e0; i < e1; ++i)
            for (int k = 0; k < 3; ++k) c[k] += w.extraSamples[i].color[k], t[k] += w.extraSamples[i].transparency[k];
        for (int k = 0; k < 3; ++k) {
            s.color[k] = float(c[k] / n);
            s.transparency[k] = std::clamp(float(t[k] / n), 0.0f, 1.0f);
        }
        return s;
    };
    w.groupExtraStart.clear();
    for (size_t gi = 0; gi < groupCount; ++gi) w.shades[gi] = averageShade(gi);

    w.contributions.assign(groupCount, SurfaceContribution{});
    auto compositePixel = [&](size_t pi) {
        uint32_t g0 = w.pixelGroupStart[pi], g1 = w.pixelGroupStart[pi + 1];
        if (g0 == g1) return;
        compositeSurfaces(m_pattern, std::span<const SurfaceGroup>(w.groups.data() + g0, g1 - g0), rast.sortedFragments(),
                          std::span<const SurfaceShade>(w.shades.data() + g0, g1 - g0),
                          std::span<SurfaceContribution>(w.contributions.data() + g0, g1 - g0));
    };
    for (size_t pi = 0; pi < size_t(bw) * bh; ++pi) compositePixel(pi);

    // Highest quality: extra samples where the colour contrast with the already-computed
    // neighbours (W, WW, NW, N, NE in scanline order) exceeds the per-channel thresholds.
    w.adaptive.assign(size_t(bw) * bh, 0);
    if (m_adaptive) {
        const glm::vec3 bg(m_camera.backgroundColor);
        const int cw = colorsRect.width();
        auto colorIndex = [&](int x, int y) { return size_t(y - colorsRect.y0) * size_t(cw) + size_t(x - colorsRect.x0); };
        w.baseColor.assign(size_t(cw) * size_t(colorsRect.height()), glm::vec3(0.0f));
        for (int y = colorsRect.y0; y < colorsRect.y1; ++y)
            for (int x = colorsRect.x0; x < colorsRect.x1; ++x) {
                if (!base.contains(x, y)) {
                    w.baseColor[colorIndex(x, y)] = m_contrast->colorAt(x, y);
                    continue;
                }
                const size_t pi = baseIndex(x, y);
                glm::vec3 c(0.0f);
                float a = 0.0f;
                for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                    c += glm::vec3(w.contributions[gi].color[0], w.contributions[gi].color[1], w.contributions[gi].color[2]);
                    a += w.contributions[gi].alpha;
                }
                if (!m_settings.composite) c += bg * std::max(0.0f, 1.0f - a);
                w.baseColor[colorIndex(x, y)] = c;
            }
        if (m_contrast) {
            // The base colours the neighbours' contrast tests read, kept for them (charged first).
            holdCharge(w, m_contrastCharges[index], m_contrast->bytesFor(index));
            m_contrast->keep(index, [&](int x, int y) { return w.baseColor[colorIndex(x, y)]; });
        }
        const double thr[3] = {m_settings.redThreshold, m_settings.greenThreshold, m_settings.blueThreshold};
        w.groupExtraStart.assign(groupCount + 1, 0);
        std::vector<int> extraCount(groupCount, 0);
        uint32_t extraTotal = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                size_t pi = baseIndex(x, y);
                const double f = contrastExcess(w.baseColor, colorsRect, m_region, x, y, thr);
                if (f <= 0.0) continue;
                bool any = false;
                for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                    const SurfaceGroup& g = w.groups[gi];
                    if (g.coverage <= 0.0f || g.visibleMask == 0) continue;
                    const RenderObject& obj = m_scene.objects[g.object];
                    const int want = adaptiveSampleCount(baseSamples(obj), maxSamples(obj), f, std::popcount(g.visibleMask));
                    int have = int(w.groupSampleStart[gi + 1] - w.groupSampleStart[gi]);
                    if (want > have) {
                        extraCount[gi] = want - have;
                        any = true;
                    }
                }
                if (any) w.adaptive[pi] = 1;
            }
        for (size_t gi = 0; gi < groupCount; ++gi) {
            w.groupExtraStart[gi] = extraTotal;
            extraTotal += uint32_t(extraCount[gi]);
        }
        w.groupExtraStart[groupCount] = extraTotal;
        w.extraSamples.assign(extraTotal, SampleResult{});
        if (extraTotal) {
            for (int y = base.y0; y < base.y1; ++y)
                for (int x = base.x0; x < base.x1; ++x) {
                    size_t pi = baseIndex(x, y);
                    if (!w.adaptive[pi]) continue;
                    for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                        if (!extraCount[gi]) continue;
                        int have = int(w.groupSampleStart[gi + 1] - w.groupSampleStart[gi]);
                        requestSamples(w, gi, x, y, have, have + extraCount[gi], true, w.groupExtraStart[gi]);
                    }
                }
            flushAll(w);
            for (int y = base.y0; y < base.y1; ++y)
                for (int x = base.x0; x < base.x1; ++x) {
                    size_t pi = baseIndex(x, y);
                    if (!w.adaptive[pi]) continue;
                    for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi)
                        if (extraCount[gi]) w.shades[gi] = averageShade(gi);
                    compositePixel(pi);
                }
        }
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                size_t pi = baseIndex(x, y);
                if (!w.adaptive[pi]) continue;
                ++w.stats.adaptivePixels;
                for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi)
                    w.stats.shadingSamplesAdaptive += w.groupExtraStart[gi + 1] - w.groupExtraStart[gi];
            }
    }
    chargeBuffers(w);
    w.stats.shadeSeconds += secondsSince(tShade);

    // Filter: gather into each tile pixel the surfaces of the pixels within reach. A pixel whose
    // window reaches past the tile is filtered at the end, from what the tiles keep (m_borders).
    auto tFilter = Clock::now();
    const int reach = m_filter.reach;
    if (reach > 0) {
        w.contributionNorm.assign(groupCount, 0.0f);
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                size_t pi = baseIndex(x, y);
                for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                    const SurfaceContribution& c = w.contributions[gi];
                    w.contributionNorm[gi] = float(filterNorm(m_filter, m_region, x, y, c.cu, c.cv));
                }
            }
    }
    auto surfacesOf = [&](int sx, int sy, auto&& visit) {
        const size_t pi = baseIndex(sx, sy);
        for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi)
            visit(w.contributions[gi], w.contributionNorm[gi]);
    };
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            double c[3] = {0, 0, 0}, a = 0.0;
            if (reach == 0) {
                size_t pi = baseIndex(x, y);
                for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi) {
                    const SurfaceContribution& s = w.contributions[gi];
                    c[0] += s.color[0], c[1] += s.color[1], c[2] += s.color[2], a += s.alpha;
                }
                writeColor(x, y, c, a);
            } else if (m_borders->completeIn(tile, x, y)) {
                gatherFiltered(m_filter, m_region, x, y, surfacesOf, c, a);
                writeColor(x, y, c, a);
            }
            if (!m_frame.depth.empty()) {
                float key = w.nearestDepth[baseIndex(x, y)];
                m_frame.depth[size_t(y) * m_frame.width + x] =
                    std::isfinite(key) ? float(m_camera.distanceFromDepthKey(key)) : std::numeric_limits<float>::infinity();
            }
            if (m_options.adaptiveMask) (*m_options.adaptiveMask)[size_t(y) * m_frame.width + x] = w.adaptive[baseIndex(x, y)];
        }
    if (reach > 0) {
        // The surfaces of the pixels a border pixel may read, charged, then kept for the end.
        uint64_t kept = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
                if (m_borders->needed(tile, x, y)) {
                    const size_t pi = baseIndex(x, y);
                    kept += w.pixelGroupStart[pi + 1] - w.pixelGroupStart[pi];
                }
        holdCharge(w, m_borderCharges[index], FilterBorders::bytesFor(tile, kept));
        m_borders->keep(index, [&](int x, int y) {
            const size_t pi = baseIndex(x, y);
            w.filterSurfaces.clear();
            for (uint32_t gi = w.pixelGroupStart[pi]; gi < w.pixelGroupStart[pi + 1]; ++gi)
                w.filterSurfaces.push_back({w.contributions[gi], w.contributionNorm[gi]});
            return std::span<const FilterSurface>(w.filterSurfaces);
        });
    }
    w.stats.filterSeconds += secondsSince(tFilter);
    w.stats.apronPixels += uint64_t(base.width()) * base.height() - uint64_t(tile.width()) * tile.height();
    ++w.stats.tiles;
    // What the filter added, with this tile's tessellations given back first.
    scope.release();
    chargeBuffers(w);
}

void FrameRenderer::bordersDone(size_t index, TileWorker& w) {
    if (m_contrast) m_contrast->markDone(index);
    if (!m_borders) return;
    const auto tFilter = Clock::now();
    m_borders->tileDone(
        index, [&](int x, int y, const double* c, double a) { writeColor(x, y, c, a); },
        [&](size_t tile) { m_borderCharges[tile].resize(0); });
    w.stats.filterSeconds += secondsSince(tFilter);
}

void FrameRenderer::writeColor(int x, int y, const double* c, double a) {
    a = std::clamp(a, 0.0, 1.0);
    const glm::vec3 bg(m_camera.backgroundColor);
    float* px = m_frame.pixel(x, y);
    for (int k = 0; k < 3; ++k) px[k] = float(m_settings.composite ? c[k] : c[k] + (1.0 - a) * bg[k]);
    px[3] = float(a);
}

Framebuffer FrameRenderer::run() {
    const FrameLayout layout = frameLayout(m_scene, m_camera, m_settings);
    m_region = layout.region;
    m_adaptive = layout.adaptive;
    m_marginLeft = layout.marginLeft;
    m_marginRight = layout.marginRight;
    m_marginTop = layout.marginTop;
    m_marginBottom = layout.marginBottom;
    m_frame.resize(m_camera.width, m_camera.height, m_settings.depth.value_or(false));
    if (m_options.adaptiveMask) m_options.adaptiveMask->assign(size_t(m_camera.width) * m_camera.height, 0);
    prepare();
    m_stats.pixels = uint64_t(m_region.width()) * m_region.height();
    // What tiles keep for their neighbours, charged tile by tile as "fragments".
    auto chargePerTile = [&] {
        std::vector<cache::MemoryCharge> charges;
        charges.reserve(m_tiles.size());
        for (size_t i = 0; i < m_tiles.size(); ++i) charges.emplace_back(&m_budget, cache::MemoryCategory::Fragments, 0);
        return charges;
    };
    if (m_adaptive || m_filter.reach > 0) m_tileIndex.emplace(m_region, m_tiles);
    if (m_adaptive) {
        m_contrast.emplace(*m_tileIndex);
        m_contrastCharges = chargePerTile();
    }
    if (m_filter.reach > 0) {
        m_borders.emplace(m_filter, *m_tileIndex);
        m_borderCharges = chargePerTile();
    }

    auto tTiles = Clock::now();
    const size_t objects = m_scene.objects.size();
    m_perThreadBytes = frameMemory(m_scene, m_camera, m_settings, m_options, 1).perThreadBytes;
    tbb::enumerable_thread_specific<std::unique_ptr<TileWorker>> workers([&] {
        auto w = std::make_unique<TileWorker>(m_pattern, m_units.size(), objects);
        w->bufferCharge = cache::MemoryCharge(&m_budget, cache::MemoryCategory::Fragments, 0);
        // Under a cap the fragment buffers are charged before they grow, old and new together,
        // so that the process never holds more than the budget allows while they are copied.
        if (m_budget.capBytes() > 0)
            w->rasterizer.setGrowHook([this, worker = w.get()](uint64_t more) { chargeBuffersAhead(*worker, more); });
        return w;
    });
    // A tile that finds no room waits for the other threads' tiles to end (withRoom, RoomGate).
    // Tiles that do not fit even so, beside what tiles waiting like them hold, are rendered again
    // afterwards, one at a time, with the whole budget to themselves.
    std::mutex deferredMutex;
    std::vector<size_t> deferred;
    // The threads take the tiles in the plan's order from one counter, in runs of at most `chunk`
    // tiles. When the budget holds less than a quarter of the tessellations the kept objects need,
    // the runs are single tiles: the threads render tiles next to one another (along the Hilbert
    // curve) and share what those tiles pin and find cached. Otherwise little is dropped, and
    // runs of up to 32 tiles keep the threads from waiting on the pieces the other is making. A
    // run takes a quarter of a thread's share of the tiles left, so that the runs shrink towards
    // the end of the frame and the threads finish together.
    std::atomic<size_t> nextTile{0};
    const int takers = std::max(1, tbb::this_task_arena::max_concurrency());
    size_t chunk = std::clamp<size_t>(m_tiles.size() / (4 * size_t(takers)), 1, 32);
    if (m_budget.capBytes() > 0) {
        std::unordered_set<PieceKey, PieceKeyHash> pieces;
        uint64_t tessellations = 0;
        for (const UnitView& u : m_units) {
            const geom::GeometryHandle* h = m_scene.objects[u.object].geometry.get();
            if (u.kept && pieces.insert(PieceKey{h, u.piece}).second) tessellations += h->pieceBytesEstimate(u.piece);
        }
        if (m_budget.availableBytes() < tessellations / 4) chunk = 1;
    }
    tbb::parallel_for(0, takers, [&](int) {
        TileWorker& w = *workers.local();
        size_t next = 0, runEnd = 0;
        auto take = [&]() -> size_t {
            if (next == runEnd) {
                const size_t taken = std::min(m_tiles.size(), nextTile.load(std::memory_order_relaxed));
                const size_t run = std::clamp<size_t>((m_tiles.size() - taken) / (4 * size_t(takers)), 1, chunk);
                next = nextTile.fetch_add(run, std::memory_order_relaxed);
                runEnd = std::min(m_tiles.size(), next + run);
            }
            return next < runEnd ? next++ : m_tiles.size();
        };
        for (size_t i = take(); i < m_tiles.size(); i = take()) {
            // A tile searching for room gets what this thread's buffers grew to beyond its share.
            const RoomGate::Tile turn(m_gate, [&] { w.releaseBuffers(m_perThreadBytes); });
            const RenderStats before = w.stats;
            const RasterStats rasterBefore = w.rasterizer.stats();
            const ResolveStats resolveBefore = w.resolver.stats();
            try {
                renderTile(i, w);
                returnDroppedMemory();
                bordersDone(i, w);
            } catch (const TileDoesNotFit&) {
                // What the tile counted is counted again when it is rendered alone.
                w.stats = before;
                w.rasterizer.restoreStats(rasterBefore);
                w.resolver.restoreStats(resolveBefore);
                std::lock_guard<std::mutex> lock(deferredMutex);
                deferred.push_back(i);
            }
        }
    });
    std::sort(deferred.begin(), deferred.end());
    m_stats.tilesDeferred = deferred.size();
    m_stats.roomWaits = m_gate.waits();
    if (!deferred.empty()) {
        // One tile at a time now: what the tile buffers grew to goes back (the deferred tiles grow
        // them again as they need).
        for (auto& wp : workers) wp->releaseBuffers(m_perThreadBytes);
        // One worker renders from here: the idle threads' shares go back.
        if (m_tileShares && m_shareThreads > 1) {
            const uint64_t idle = std::min(m_tileShares->bytes(), uint64_t(m_shareThreads - 1) * m_perThreadBytes);
            m_tileShares->resize(m_tileShares->bytes() - idle);
        }
    }
    for (size_t i : deferred) {
        TileWorker& w = *workers.local();
        try {
            renderTile(i, w);
            returnDroppedMemory();
            bordersDone(i, w);
        } catch (TileDoesNotFit& e) {
            e.tile = m_tiles[i];
            throw;
        }
    }
    if (m_borders && !m_borders->allFiltered()) throw std::logic_error("renderFrame: a tile's border pixels were not filtered");
    m_stats.tilesSeconds += secondsSince(tTiles);
    for (auto& wp : workers) {
        const TileWorker& w = *wp;
        m_stats.rasterSeconds += w.stats.rasterSeconds;
        m_stats.resolveSeconds += w.stats.resolveSeconds;
        m_stats.shadeSeconds += w.stats.shadeSeconds;
        m_stats.filterSeconds += w.stats.filterSeconds;
        m_stats.tiles += w.stats.tiles;
        m_stats.shadingSamplesBase += w.stats.shadingSamplesBase;
        m_stats.shadingSamplesAdaptive += w.stats.shadingSamplesAdaptive;
        m_stats.adaptivePixels += w.stats.adaptivePixels;
        m_stats.apronPixels += w.stats.apronPixels;
        m_stats.trianglesBackfacing += w.stats.trianglesBackfacing;
        m_stats.trianglesNearClipped += w.stats.trianglesNearClipped;
        m_stats.trianglesOutside += w.stats.trianglesOutside;
        m_stats.objectTileVisits += w.stats.objectTileVisits;
        m_stats.skippedOccluded += w.stats.skippedOccluded;
        m_stats.tileCopies += w.stats.tileCopies;
        const RasterStats& rs = w.rasterizer.stats();
        m_stats.trianglesRasterized += rs.trianglesRasterized;
        m_stats.fragments += rs.fragments;
        const ResolveStats& vs = w.resolver.stats();
        m_stats.mergedFragments += vs.mergedFragments;
        m_stats.surfaces += vs.surfaces;
    }
    const cache::LruCacheStats ts = m_lazy.tessellationStats();
    m_stats.tessellationsMade = ts.made;
    m_stats.tessellationsEvicted = ts.evicted;
    m_stats.tessellationsRecomputed = ts.recomputed;
    const cache::LruCacheStats ms = m_lazy.meshStats();
    m_stats.meshesMade = ms.made;
    m_stats.meshesEvicted = ms.evicted;
    m_stats.trianglesMade = m_lazy.trianglesMade();
    m_stats.tileMinSize = m_stats.tileMaxSize = 0;
    for (const PixelRect& t : m_tiles) {
        const int lo = std::min(t.width(), t.height()), hi = std::max(t.width(), t.height());
        m_stats.tileMinSize = m_stats.tileMinSize == 0 ? lo : std::min(m_stats.tileMinSize, lo);
        m_stats.tileMaxSize = std::max(m_stats.tileMaxSize, hi);
    }
    return std::move(m_frame);
}

void FrameRenderer::finishStats(const cache::MemoryBudget& budget) const {
    const cache::MemoryBudgetSnapshot snap = budget.snapshot();
    m_stats.memoryCapBytes = snap.capBytes;
    m_stats.memoryPeakCharged = snap.peakBytes;
    m_stats.memoryPeakByCategory = snap.categoryPeakBytes;
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) == 0) m_stats.peakRssBytes = uint64_t(usage.ru_maxrss) * 1024;
}

}  // namespace

Framebuffer renderFrame(const FrameScene& scene, const RenderCamera& camera, const RenderSettings& settings,
                        RenderStats& stats, const RenderOptions& options) {
    int threads = settings.numCpusToUse > 0 ? settings.numCpusToUse : tbb::this_task_arena::max_concurrency();
    threads = std::max(1, threads);
    const MemoryCap cap = memoryCap(settings);
    std::optional<cache::MemoryBudget> ownBudget;
    cache::MemoryBudget& budget = options.memoryBudget ? *options.memoryBudget : ownBudget.emplace(cap.bytes);
    if (budget.capBytes() != 0) util::returnLargeBlocksOnFree();
    // Charged before the arena and before any buffer is allocated; released when this returns.
    std::vector<cache::MemoryCharge> charges =
        chargeFrame(budget, frameMemory(scene, camera, settings, options, threads), camera,
                    budget.capBytes() == cap.bytes ? cap.source : std::string());
    tbb::task_arena arena(threads);
    Framebuffer out;
    try {
        arena.execute([&] {
            FrameRenderer renderer(scene, camera, settings, stats, options, budget);
            for (cache::MemoryCharge& c : charges)
                if (c.category() == cache::MemoryCategory::Fragments) renderer.setTileShares(&c, threads);
            out = renderer.run();
            renderer.finishStats(budget);
        });
    } catch (const TileDoesNotFit& e) {
        const uint64_t capBytes = budget.capBytes();
        const std::string capText = formatCap(capBytes);
        const std::string source = budget.capBytes() == cap.bytes ? cap.source : std::string();
        throw MemoryCapError("the " + std::to_string(e.tile.width()) + "x" + std::to_string(e.tile.height()) +
                                 " tile at (" + std::to_string(e.tile.x0) + ", " + std::to_string(e.tile.y0) +
                                 ") needs about " + formatBytes(e.bytes) + " more for " +
                                 (e.object.empty() ? std::string("its fragments and shading") : "the triangles of " + e.object) +
                                 ", beyond the memory cap of " + capText + (source.empty() ? "" : " (" + source + ")") +
                                 " with the frame's buffers held",
                             budget.usedBytes() + e.bytes, capBytes);
    }
    return out;
}

}  // namespace pushpin::render
