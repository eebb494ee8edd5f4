// cache/memory_budget.cpp: lock-free accounting of the render's memory by category.
#include "cache/memory_budget.h"

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <ostream>
#include <utility>

namespace pushpin::cache {

namespace {

void raiseTo(std::atomic<uint64_t>& peak, uint64_t value) {
    uint64_t seen = peak.load(std::memory_order_relaxed);
    while (seen < value && !peak.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
    }
}

}  // namespace

const char* memoryCategoryName(MemoryCategory category) {
    switch (category) {
        case MemoryCategory::Textures: return "textures";
        case MemoryCategory::Tessellation: return "tessellation";
        case MemoryCategory::RayTracing: return "rayTracing";
        case MemoryCategory::Fragments: return "fragments";
        case MemoryCategory::Shading: return "shading";
        case MemoryCategory::ShadowMaps: return "shadowMaps";
        case MemoryCategory::Framebuffer: return "framebuffer";
        case MemoryCategory::Other: return "other";
        case MemoryCategory::Geometry: return "geometry";
        case MemoryCategory::Scene: return "scene";
    }
    return "?";
}

std::ostream& operator<<(std::ostream& os, const MemoryBudgetSnapshot& s) {
    os << "{cap " << s.capBytes << ", used " << s.usedBytes << ", peak " << s.peakBytes
       << ", refused " << s.refusedCharges;
    for (size_t c = 0; c < kMemoryCategoryCount; ++c)
        os << ", " << memoryCategoryName(MemoryCategory(c)) << " " << s.categoryBytes[c] << " (peak "
           << s.categoryPeakBytes[c] << ")";
    return os << "}";
}

MemoryBudget::MemoryBudget(uint64_t capBytes) : m_capBytes(capBytes) {}

void MemoryBudget::addToCategory(MemoryCategory category, uint64_t bytes) {
    Category& c = m_categories[size_t(category)];
    raiseTo(c.peak, c.bytes.fetch_add(bytes, std::memory_order_relaxed) + bytes);
}

void MemoryBudget::charge(MemoryCategory category, uint64_t bytes) {
    raiseTo(m_peak, m_used.fetch_add(bytes, std::memory_order_relaxed) + bytes);
    addToCategory(category, bytes);
}

bool MemoryBudget::tryCharge(MemoryCategory category, uint64_t bytes) {
    if (m_capBytes == 0) {
        charge(category, bytes);
        return true;
    }
    // The total is the only figure the cap applies to, so one compare-and-swap on it decides:
    // two threads racing for the last bytes cannot both get them.
    uint64_t used = m_used.load(std::memory_order_relaxed);
    do {
        if (bytes > m_capBytes || used > m_capBytes - bytes) {
            m_refused.fetch_add(1, std::memory_order_relaxed);
            return false;
        }
    } while (!m_used.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
    raiseTo(m_peak, used + bytes);
    addToCategory(category, bytes);
    return true;
}

void MemoryBudget::release(MemoryCategory category, uint64_t bytes) {
    Category& c = m_categories[size_t(category)];
    const uint64_t before = c.bytes.fetch_sub(bytes, std::memory_order_relaxed);
    if (bytes > before) {
        // An always-on check in the manner of CHECK_LE: accounting that went negative would make
        // every later decision about the cap wrong, so stop here with both figures.
        std::fprintf(stderr,
                     "pushpin: MemoryBudget::release: releasing %llu bytes of '%s', which holds "
                     "only %llu\n",
                     static_cast<unsigned long long>(bytes), memoryCategoryName(category),
                     static_cast<unsigned long long>(before));
        std::abort();
    }
    m_used.fetch_sub(bytes, std::memory_order_relaxed);
}

uint64_t MemoryBudget::usedBytes(MemoryCategory category) const {
    return m_categories[size_t(category)].bytes.load(std::memory_order_relaxed);
}

uint64_t MemoryBudget::peakBytes(MemoryCategory category) const {
    return m_categories[size_t(category)].peak.load(std::memory_order_relaxed);
}

uint64_t MemoryBudget::availableBytes() const {
    if (m_capBytes == 0) return std::numeric_limits<uint64_t>::max();
    const uint64_t used = usedBytes();
    return used >= m_capBytes ? 0 : m_capBytes - used;
}

MemoryBudgetSnapshot MemoryBudget::snapshot() const {
    MemoryBudgetSnapshot s;
    s.capBytes = m_capBytes;
    s.usedBytes = usedBytes();
    s.peakBytes = peakBytes();
    s.refusedCharges = m_refused.load(std::memory_order_relaxed);
    for (size_t c = 0; c < kMemoryCategoryCount; ++c) {
        s.categoryBytes[c] = m_categories[c].bytes.load(std::memory_order_relaxed);
        s.categoryPeakBytes[c] = m_categories[c].peak.load(std::memory_order_relaxed);
    }
    return s;
}

// ---------------------------------------------------------------- MemoryCharge

MemoryCharge::MemoryCharge(MemoryBudget* budget, MemoryCategory category, uint64_t bytes)
    : m_budget(budget), m_category(category), m_bytes(budget ? bytes : 0) {
    if (m_budget) m_budget->charge(m_category, m_bytes);
}

std::optional<MemoryCharge> MemoryCharge::tryCharge(MemoryBudget& budget, MemoryCategory category,
                                                    uint64_t bytes) {
    if (!budget.tryCharge(category, bytes)) return std::nullopt;
    MemoryCharge c;
    c.m_budget = &budget;
    c.m_category = category;
    c.m_bytes = bytes;
    return c;
}

MemoryCharge::MemoryCharge(MemoryCharge&& other) noexcept
    : m_budget(std::exchange(other.m_budget, nullptr)),
      m_category(other.m_category),
      m_bytes(std::exchange(other.m_bytes, 0)) {}

MemoryCharge& MemoryCharge::operator=(MemoryCharge&& other) noexcept {
    if (this != &other) {
        reset();
        m_budget = std::exchange(other.m_budget, nullptr);
        m_category = other.m_category;
        m_bytes = std::exchange(other.m_bytes, 0);
    }
    return *this;
}

bool MemoryCharge::tryResize(uint64_t bytes) {
    if (!m_budget || bytes <= m_bytes) {
        resize(bytes);
        return true;
    }
    if (!m_budget->tryCharge(m_category, bytes - m_bytes)) return false;
    m_bytes = bytes;
    return true;
}

void MemoryCharge::resize(uint64_t bytes) {
    if (!m_budget) return;
    if (bytes > m_bytes)
        m_budget->charge(m_category, bytes - m_bytes);
    else if (bytes < m_bytes)
        m_budget->release(m_category, m_bytes - bytes);
    m_bytes = bytes;
}

void MemoryCharge::reset() {
    if (m_budget && m_bytes) m_budget->release(m_category, m_bytes);
    m_budget = nullptr;
    m_bytes = 0;
}

}  // namespace pushpin::cache
