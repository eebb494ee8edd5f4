// core/render/lazy_tessellation.h: a frame's tessellations, made the first time a tile needs them
// (DESIGN.md step 5a) and kept while the memory budget allows.
//
// Each piece of a geometry handle (the whole shape when it is one piece) has one tessellation,
// shared by every instance of the shape and every tile that needs it. They live in an LRU cache
// charged to the budget as `tessellation`: a tile pins what it uses for its life; under pressure
// the least recently used that no tile pins are dropped (reclaim) and made again when a tile needs
// them later (counted as recomputes). A shape in pieces whose source does not keep its mesh, and
// cannot make a piece's part of it alone, has its mesh made once for the pieces made while the
// mesh stays resident: a second LRU, charged as `geometry`. Before a tessellation is made, room for
// its making (the mesh evaluated again when it is not kept or shared, the working memory, and the
// tessellation itself) is taken through the caller's TakeRoom, and given back once it is made;
// no piece or mesh is claimed for making while TakeRoom runs, so TakeRoom may wait for other
// threads to give memory back.
//
// Thread safety: acquire and reclaim may be called by any number of threads at once; a piece that
// several threads need together is made once while the others wait for it.
// Memory: what the two caches hold, charged to the budget; the tables themselves are not charged.
#pragma once

#include "core/geom/geometry_handle.h"
#include "core/geom/mesh.h"
#include "core/geom/tessellation.h"

#include "cache/lru_cache.h"
#include "cache/memory_budget.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

namespace pushpin::render {

// A piece of a geometry handle's tessellation (piece 0 of a shape in one piece: the whole).
struct PieceKey {
    const geom::GeometryHandle* handle = nullptr;
    uint32_t piece = 0;
    bool operator==(const PieceKey&) const = default;
};
struct PieceKeyHash {
    size_t operator()(const PieceKey& k) const {
        return std::hash<const void*>()(k.handle) ^ (size_t(k.piece) * 0x9e3779b97f4a7c15ull);
    }
};

// What making piece `piece` of `h` needs beyond the tessellation itself when no shared mesh is
// used: the mesh evaluated again (when the shape does not keep it and cannot make a piece's part
// alone) and the working memory.
uint64_t transientBytes(const geom::GeometryHandle& h, size_t piece);

// Thrown by LazyTessellations::acquire when the caches cannot hold the piece or the mesh it is made
// from beside what is pinned.
struct TessellationDoesNotFit {
    uint64_t bytes = 0;  // what did not fit (estimated)
};

class LazyTessellations {
public:
    using TessellationCache = cache::LruCache<PieceKey, geom::Tessellation, PieceKeyHash>;
    using MeshCache = cache::LruCache<const void*, std::shared_ptr<const geom::Mesh>>;
    using Pin = TessellationCache::Pin;
    // Charges `bytes` to the budget (as geometry) for something about to be made and returns the
    // charge, or throws when no room can be made.
    using TakeRoom = std::function<cache::MemoryCharge(uint64_t bytes)>;

    // Charges `budget`; null charges nothing and drops nothing.
    explicit LazyTessellations(cache::MemoryBudget* budget)
        : m_tessellations(budget, cache::MemoryCategory::Tessellation), m_meshes(budget, cache::MemoryCategory::Geometry) {}

    // Piece `piece` of `handle` tessellated, pinned: the resident tessellation, or one made now
    // (and its shape's shared mesh first, when it uses one). Throws TessellationDoesNotFit when the
    // caches cannot make room for it beside what is pinned, and whatever takeRoom throws.
    Pin acquire(const geom::GeometryHandle& handle, uint32_t piece, const TakeRoom& takeRoom);
    // Drops unpinned tessellations, then unpinned meshes, until `bytes` more would fit; whether
    // anything was dropped.
    bool reclaim(uint64_t bytes) { return m_tessellations.reclaim(bytes) || m_meshes.reclaim(bytes); }

    cache::LruCacheStats tessellationStats() const { return m_tessellations.stats(); }
    cache::LruCacheStats meshStats() const { return m_meshes.stats(); }
    // Triangles of every tessellation made, again or not.
    uint64_t trianglesMade() const { return m_trianglesMade.load(std::memory_order_relaxed); }
    // Bytes charged while tessellations were made and given back: with what the caches dropped,
    // the memory the process may hand back to the system.
    uint64_t transientFreed() const { return m_transientFreed.load(std::memory_order_relaxed); }

private:
    TessellationCache m_tessellations;  // one per piece of a geometry handle, shared by instances
    MeshCache m_meshes;                 // meshes shared by the pieces of a shape
    std::atomic<uint64_t> m_trianglesMade{0};
    std::atomic<uint64_t> m_transientFreed{0};
};

}  // namespace pushpin::render
