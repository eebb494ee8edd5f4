// cache/memory_budget.h: the one memory budget of a render (`-mm` / maxMemoryUse): the cap in
// bytes and what every large consumer holds, by category, with the peak of each.
// Thread safety: every method may be called from any thread at once. Charges and releases are
// lock-free (atomics); a snapshot taken while others charge may show a total that differs from
// the sum of its categories by the charges in flight.
// Memory: owns nothing it accounts; the budget itself is a few hundred bytes and charges nothing.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <optional>

namespace pushpin::cache {

// Who holds the memory. Counted separately so statistics say where the memory went.
enum class MemoryCategory : uint8_t {
    Textures = 0,  // texture cache slots and tables, in-memory fallback images
    Tessellation,  // tessellated triangles
    RayTracing,    // ray-tracing structures (Embree's memory monitor)
    Fragments,     // EAS fragments and coverage masks
    Shading,       // shading batches and per-tile arenas
    ShadowMaps,    // depth maps
    Framebuffer,   // the finished frame (colour, alpha, depth) and the image writer's copy of it
    Other,
    Geometry,      // what tessellations are made from: meshes and surfaces kept or being evaluated
    Scene,         // the loaded scene: its stored values (mesh, surface and curve payloads, arrays) and tables
};
constexpr size_t kMemoryCategoryCount = 10;

// "textures", "tessellation", "rayTracing", "fragments", "shading", "shadowMaps", "framebuffer",
// "other", "geometry", "scene".
const char* memoryCategoryName(MemoryCategory category);

// What a budget held at one moment (plain data).
struct MemoryBudgetSnapshot {
    uint64_t capBytes = 0;        // 0: unlimited
    uint64_t usedBytes = 0;       // now, all categories
    uint64_t peakBytes = 0;       // most ever held at once, all categories
    uint64_t refusedCharges = 0;  // tryCharge calls that were refused
    std::array<uint64_t, kMemoryCategoryCount> categoryBytes{};      // now, per category
    std::array<uint64_t, kMemoryCategoryCount> categoryPeakBytes{};  // most ever, per category

    uint64_t bytes(MemoryCategory c) const { return categoryBytes[size_t(c)]; }
    uint64_t peak(MemoryCategory c) const { return categoryPeakBytes[size_t(c)]; }
};
std::ostream& operator<<(std::ostream& os, const MemoryBudgetSnapshot& s);

class MemoryBudget {
public:
    // capBytes 0 means unlimited: tryCharge then never refuses.
    explicit MemoryBudget(uint64_t capBytes = 0);
    MemoryBudget(const MemoryBudget&) = delete;
    MemoryBudget& operator=(const MemoryBudget&) = delete;

    uint64_t capBytes() const { return m_capBytes; }

    // Records `bytes` held by `category` whatever the cap: for memory the render needs to be
    // correct (it may push usedBytes() past the cap; overCap() then says so, and consumers that
    // can give memory back, such as the swappable LRU, react). Never fails.
    void charge(MemoryCategory category, uint64_t bytes);
    // Records `bytes` only if the total stays within the cap; returns false, recording nothing and
    // counting a refusal, when it would not. Always succeeds when the cap is 0.
    bool tryCharge(MemoryCategory category, uint64_t bytes);
    // Gives back bytes charged earlier to the same category. Releasing more than the category
    // holds is a programmer error: the process prints both figures and aborts.
    void release(MemoryCategory category, uint64_t bytes);

    uint64_t usedBytes() const { return m_used.load(std::memory_order_relaxed); }
    uint64_t usedBytes(MemoryCategory category) const;
    uint64_t peakBytes() const { return m_peak.load(std::memory_order_relaxed); }
    uint64_t peakBytes(MemoryCategory category) const;
    // Bytes tryCharge would still accept now (UINT64_MAX when unlimited; 0 when over the cap).
    uint64_t availableBytes() const;
    bool overCap() const { return m_capBytes != 0 && usedBytes() > m_capBytes; }

    MemoryBudgetSnapshot snapshot() const;

private:
    void addToCategory(MemoryCategory category, uint64_t bytes);

    const uint64_t m_capBytes;
    std::atomic<uint64_t> m_used{0};
    std::atomic<uint64_t> m_peak{0};
    std::atomic<uint64_t> m_refused{0};
    // One cache line per category so consumers charging different categories do not contend.
    struct alignas(64) Category {
        std::atomic<uint64_t> bytes{0};
        std::atomic<uint64_t> peak{0};
    };
    std::array<Category, kMemoryCategoryCount> m_categories;
};

// A charge that releases itself: holds `bytes` of `category` in a budget from construction until
// reset() or destruction. Move-only. An empty charge (default-constructed, moved from, or made
// with a null budget) holds nothing. Not thread-safe itself; the budget it charges is.
class MemoryCharge {
public:
    MemoryCharge() = default;
    // Charges unconditionally (MemoryBudget::charge). A null budget makes an empty charge.
    MemoryCharge(MemoryBudget* budget, MemoryCategory category, uint64_t bytes);
    // Charges only within the cap; nullopt when the budget refuses.
    static std::optional<MemoryCharge> tryCharge(MemoryBudget& budget, MemoryCategory category,
                                                 uint64_t bytes);
    ~MemoryCharge() { reset(); }
    MemoryCharge(MemoryCharge&& other) noexcept;
    MemoryCharge& operator=(MemoryCharge&& other) noexcept;
    MemoryCharge(const MemoryCharge&) = delete;
    MemoryCharge& operator=(const MemoryCharge&) = delete;

    // Changes the charge to `bytes`, charging growth unconditionally and releasing shrinkage.
    void resize(uint64_t bytes);
    // The same, charging growth only within the cap: false (nothing changed) when the budget
    // refuses it.
    bool tryResize(uint64_t bytes);
    // Releases everything held; the charge becomes empty.
    void reset();

    uint64_t bytes() const { return m_bytes; }
    MemoryBudget* budget() const { return m_budget; }
    MemoryCategory category() const { return m_category; }

private:
    MemoryBudget* m_budget = nullptr;
    MemoryCategory m_category = MemoryCategory::Other;
    uint64_t m_bytes = 0;
};

}  // namespace pushpin::cache
