// core/util/index_table.h: an open-addressing hash index of 32-bit entry numbers whose keys live
// in the caller's own storage (a node's name, a cached plug's path). The table holds only the
// entry number and 32 bits of its hash, 8 bytes a slot, so a lookup touches one or two slots and
// then the one entry whose hash bits match, instead of a chain of separately allocated nodes.
// Keys are compared through a predicate the caller passes with each call; the caller supplies the
// hash (util::hashBytes, or its own mix for compound keys) and keeps keys unique where it needs to.
// Linear probing, at most half full, deletion by backward shift (no tombstones), so lookups stay
// short whatever the history of inserts and erases.
// Thread safety: none; a const table may be read from many threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

namespace pushpin::util {

// A 64-bit hash of a byte string (the standard library's, which is seeded the same in every run).
inline uint64_t hashBytes(std::string_view bytes) { return std::hash<std::string_view>()(bytes); }
// Mixes two hashes into one (for keys made of several parts).
inline uint64_t hashCombine(uint64_t a, uint64_t b) {
    return a ^ (b + 0x9E3779B97F4A7C15ull + (a << 12) + (a >> 4));
}
// The hash of a key made of a 32-bit id and a string: (node, plug path), (parent, name).
inline uint64_t hashIdAndBytes(uint32_t id, std::string_view bytes) {
    return hashCombine(hashBytes(bytes), uint64_t(id) * 0x9E3779B97F4A7C15ull);
}

class IndexTable {
public:
    static constexpr uint32_t kNone = ~uint32_t(0);

    size_t size() const { return m_count; }
    bool empty() const { return m_count == 0; }
    size_t memoryBytes() const { return m_slots.capacity() * sizeof(Slot); }
    void clear() {
        m_slots.clear();
        m_mask = 0;
        m_count = 0;
    }
    // Makes room for `count` entries without growing again.
    void reserve(size_t count) {
        size_t want = kMinSlots;
        while (want < count * 2) want *= 2;
        if (want > m_slots.size()) rehash(want);
    }

    // The entry whose key has `hash` and for which matches(entry) holds, or kNone.
    template <class Matches>
    uint32_t find(uint64_t hash, Matches&& matches) const {
        if (m_slots.empty()) return kNone;
        const uint32_t tag = tagOf(hash);
        for (size_t i = tag & mask();; i = (i + 1) & mask()) {
            const Slot& s = m_slots[i];
            if (s.entry == kNone) return kNone;
            if (s.tag == tag && matches(s.entry)) return s.entry;
        }
    }
    // Calls visit(entry) for every entry under `hash` for which matches(entry) holds, in table order.
    template <class Matches, class Visit>
    void forEach(uint64_t hash, Matches&& matches, Visit&& visit) const {
        if (m_slots.empty()) return;
        const uint32_t tag = tagOf(hash);
        for (size_t i = tag & mask(); m_slots[i].entry != kNone; i = (i + 1) & mask()) {
            const Slot& s = m_slots[i];
            if (s.tag == tag && matches(s.entry)) visit(s.entry);
        }
    }
    // Adds `entry` (any value but kNone) under `hash`. The caller makes sure no entry with an equal
    // key is present when it needs keys to be unique.
    void insert(uint64_t hash, uint32_t entry) {
        if ((m_count + 1) * 2 > m_slots.size()) rehash(m_slots.empty() ? kMinSlots : m_slots.size() * 2);
        place(Slot{tagOf(hash), entry});
        ++m_count;
    }
    // Replaces the entry that matches by `replacement` (which must have the same key). Returns
    // false if none matches.
    template <class Matches>
    bool replace(uint64_t hash, Matches&& matches, uint32_t replacement) {
        const size_t i = slotOf(hash, matches);
        if (i == kNoSlot) return false;
        m_slots[i].entry = replacement;
        return true;
    }
    // Removes the entry that matches; returns it, or kNone if none does.
    template <class Matches>
    uint32_t erase(uint64_t hash, Matches&& matches) {
        size_t hole = slotOf(hash, matches);
        if (hole == kNoSlot) return kNone;
        const uint32_t removed = m_slots[hole].entry;
        // Backward shift: move up each later slot of the run that may live in the hole.
        for (size_t i = (hole + 1) & mask(); m_slots[i].entry != kNone; i = (i + 1) & mask()) {
            const size_t home = m_slots[i].tag & mask();
            // The slot at i may move to the hole when its home is not within (hole, i].
            const bool homeBetween = hole <= i ? (home > hole && home <= i) : (home > hole || home <= i);
            if (homeBetween) continue;
            m_slots[hole] = m_slots[i];
            hole = i;
        }
        m_slots[hole] = Slot{0, kNone};
        --m_count;
        return removed;
    }

private:
    struct Slot {
        uint32_t tag;
        uint32_t entry;  // kNone: empty
    };
    static constexpr size_t kMinSlots = 16;
    static constexpr size_t kNoSlot = ~size_t(0);

    // The high half of a multiplicative mix: well spread even for weak hashes such as small integers.
    static uint32_t tagOf(uint64_t hash) { return uint32_t((hash * 0x9E3779B97F4A7C15ull) >> 32); }
    size_t mask() const { return m_mask; }

    template <class Matches>
    size_t slotOf(uint64_t hash, Matches& matches) const {
        if (m_slots.empty()) return kNoSlot;
        const uint32_t tag = tagOf(hash);
        for (size_t i = tag & mask();; i = (i + 1) & mask()) {
            const Slot& s = m_slots[i];
            if (s.entry == kNone) return kNoSlot;
            if (s.tag == tag && matches(s.entry)) return i;
        }
    }
    void place(Slot slot) {
        size_t i = slot.tag & mask();
        while (m_slots[i].entry != kNone) i = (i + 1) & mask();
        m_slots[i] = slot;
    }
    // Slots are placed by 32 bits of hash, so a table can grow to 2^32 slots, beyond any entry count.
    void rehash(size_t slots) {
        std::vector<Slot> old(slots, Slot{0, kNone});
        old.swap(m_slots);
        m_mask = slots - 1;
        for (const Slot& s : old)
            if (s.entry != kNone) place(s);
    }

    std::vector<Slot> m_slots;
    size_t m_mask = 0;  // m_slots.size() - 1 once there are slots
    size_t m_count = 0;
};

}  // namespace pushpin::util
