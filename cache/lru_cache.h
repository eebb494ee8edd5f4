// cache/lru_cache.h: values that are expensive to make and cheap to make again (tessellations,
// ray-tracing data), kept while the memory budget allows and dropped least recently used first.
// A value is made by the first caller that needs it, once, while other callers of the same key
// wait; every byte it holds is charged to one MemoryBudget category. Values in use are pinned
// (Pin) and never dropped; unpinned values are dropped when a new one needs their room, and made
// again, counted as a recompute, when asked for again. A tier between the two (values written to
// a swap file instead of dropped) goes behind evictOne(): that is where a value leaves memory.
// Thread safety: every method may be called from any thread at once; one mutex guards the table,
// and values are made outside it.
// Memory: charges the budget with each resident value's bytes (as its maker reports them) and
// releases them when the value is dropped or the cache destroyed; the table itself is not
// charged (about 100 bytes per key).
#pragma once

#include "cache/memory_budget.h"

#include <condition_variable>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>

namespace pushpin::cache {

struct LruCacheStats {
    uint64_t made = 0;        // values made (first time and again)
    uint64_t recomputed = 0;  // values made again after being dropped
    uint64_t evicted = 0;     // values dropped to make room
    uint64_t evictedBytes = 0;  // the bytes they held
    uint64_t hits = 0;        // acquisitions that found the value resident
    uint64_t refused = 0;     // tryAcquire calls whose value could not be made room for
};

template <class Key, class Value, class Hash = std::hash<Key>>
class LruCache {
    struct Entry;

public:
    // Charges `category` of `budget` (null: nothing is charged and nothing is ever dropped).
    LruCache(MemoryBudget* budget, MemoryCategory category) : m_budget(budget), m_category(category) {}
    LruCache(const LruCache&) = delete;
    LruCache& operator=(const LruCache&) = delete;
    ~LruCache() {
        for (auto& [key, e] : m_entries)
            if (e.value && m_budget) m_budget->release(m_category, e.bytes);
    }

    // A pinned value: it stays resident until the Pin is destroyed or reset. Move-only.
    class Pin {
    public:
        Pin() = default;
        Pin(Pin&& o) noexcept : m_cache(std::exchange(o.m_cache, nullptr)), m_entry(o.m_entry), m_value(std::move(o.m_value)) {}
        Pin& operator=(Pin&& o) noexcept {
            if (this != &o) {
                reset();
                m_cache = std::exchange(o.m_cache, nullptr);
                m_entry = o.m_entry;
                m_value = std::move(o.m_value);
            }
            return *this;
        }
        ~Pin() { reset(); }
        void reset() {
            if (m_cache) m_cache->unpin(*m_entry);
            m_cache = nullptr;
            m_value.reset();
        }
        const Value& operator*() const { return *m_value; }
        const Value* operator->() const { return m_value.get(); }
        const Value* get() const { return m_value.get(); }
        explicit operator bool() const { return m_value != nullptr; }

    private:
        friend class LruCache;
        Pin(LruCache* cache, Entry* entry, std::shared_ptr<const Value> value)
            : m_cache(cache), m_entry(entry), m_value(std::move(value)) {}
        LruCache* m_cache = nullptr;
        Entry* m_entry = nullptr;
        std::shared_ptr<const Value> m_value;
    };

    // The value of `key`, pinned, when it is resident (counted as a hit), after waiting for the
    // caller making it, if any; nullopt when it is not resident, without making it. A caller that
    // must make room before a value is made (and may wait for that) asks here first, so that it
    // holds no key's making while it waits, and takes no room for a value another is making.
    std::optional<Pin> tryPin(const Key& key) {
        std::unique_lock<std::mutex> lock(m_mutex);
        const auto it = m_entries.find(key);
        if (it == m_entries.end()) return std::nullopt;
        Entry& e = it->second;
        while (e.making) m_made.wait(lock);
        if (!e.value) return std::nullopt;
        return pinResident(e);
    }

    // The value of `key`, pinned, made by `make()` (returning Value) when it is not resident, with
    // `bytes(value)` charged. Room is made by dropping unpinned values, least recently used first;
    // nullopt (nothing made resident, nothing charged) when the value does not fit even then.
    // With an unlimited budget it never fails.
    template <class Make, class Bytes>
    std::optional<Pin> tryAcquire(const Key& key, Make&& make, Bytes&& bytes) {
        std::unique_lock<std::mutex> lock(m_mutex);
        Entry& e = m_entries[key];
        for (;;) {
            if (e.value) return pinResident(e);
            if (!e.making) break;
            m_made.wait(lock);
        }
        e.making = true;
        lock.unlock();
        std::shared_ptr<const Value> value;
        uint64_t size = 0;
        try {
            value = std::make_shared<const Value>(make());
            size = bytes(*value);
        } catch (...) {
            lock.lock();
            e.making = false;
            m_made.notify_all();
            throw;
        }
        lock.lock();
        e.making = false;
        m_made.notify_all();
        if (!makeRoom(size)) {
            ++m_stats.refused;
            return std::nullopt;
        }
        ++m_stats.made;
        if (e.timesMade++ > 0) ++m_stats.recomputed;
        e.value = std::move(value);
        e.bytes = size;
        e.pins = 1;
        m_resident += size;
        return Pin(this, &e, e.value);
    }

    // Drops unpinned values, least recently used first, until the budget has `bytes` available or
    // nothing unpinned is left, for memory another consumer needs. Returns whether it has them.
    bool reclaim(uint64_t bytes) {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (!m_budget) return true;
        while (m_budget->availableBytes() < bytes && !m_lru.empty()) evictOne();
        return m_budget->availableBytes() >= bytes;
    }

    // Drops every unpinned value (for tests and for a caller that wants its memory back now).
    void dropUnpinned() {
        std::lock_guard<std::mutex> lock(m_mutex);
        while (!m_lru.empty()) evictOne();
    }

    LruCacheStats stats() const {
        std::lock_guard<std::mutex> lock(m_mutex);
        return m_stats;
    }
    // Bytes of the values resident now.
    uint64_t residentBytes() const {
        std::lock_guard<std::mutex> lock(m_mutex);
        return m_resident;
    }
    // Keys ever acquired.
    size_t keyCount() const {
        std::lock_guard<std::mutex> lock(m_mutex);
        return m_entries.size();
    }

private:
    struct Entry {
        std::shared_ptr<const Value> value;  // null when not resident
        uint64_t bytes = 0;
        uint32_t pins = 0;
        uint32_t timesMade = 0;
        bool making = false;
        bool inLru = false;
        typename std::list<Entry*>::iterator lruPosition;
    };

    // Pins resident entry `e` (a hit). Called with the mutex held.
    Pin pinResident(Entry& e) {
        ++e.pins;
        if (e.inLru) {
            m_lru.erase(e.lruPosition);
            e.inLru = false;
        }
        ++m_stats.hits;
        return Pin(this, &e, e.value);
    }

    // Charges `size`, dropping unpinned values (oldest first) while the budget refuses. Called
    // with the mutex held.
    bool makeRoom(uint64_t size) {
        if (!m_budget) return true;
        while (!m_budget->tryCharge(m_category, size)) {
            if (m_lru.empty()) return false;
            evictOne();
        }
        return true;
    }

    // Drops the least recently used unpinned value. Called with the mutex held.
    void evictOne() {
        Entry* e = m_lru.front();
        m_lru.pop_front();
        e->inLru = false;
        e->value.reset();
        if (m_budget) m_budget->release(m_category, e->bytes);
        m_resident -= e->bytes;
        m_stats.evictedBytes += e->bytes;
        e->bytes = 0;
        ++m_stats.evicted;
    }

    void unpin(Entry& e) {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (--e.pins == 0) {
            e.lruPosition = m_lru.insert(m_lru.end(), &e);
            e.inLru = true;
        }
    }

    MemoryBudget* m_budget;
    MemoryCategory m_category;
    mutable std::mutex m_mutex;
    std::condition_variable m_made;
    std::unordered_map<Key, Entry, Hash> m_entries;  // node-based: entries never move
    std::list<Entry*> m_lru;                         // unpinned resident values, oldest first
    uint64_t m_resident = 0;
    LruCacheStats m_stats;
};

}  // namespace pushpin::cache
