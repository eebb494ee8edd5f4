// core/scene/detail/name_index.h: the Graph's index from a node name to the first node of that
// name. Maya numbers its names (pCube1, pCubeShape1, polySurface12, mesh7231558), so a name that
// ends in a plain decimal number is kept under its base ("pCube") in an array indexed by the number
// while the base's numbers are dense; any other name, and a numbered one too far past its base's
// count, goes into one hash table. Renaming a million clashing "x" to x1, x2, … then writes one
// array in order instead of probing a table of millions at random, and a lookup of a numbered name
// hashes only its base, which the previous lookup most likely left in the cache.
// Memory: 4 bytes a number in a base's range (at most about twice the names under it, plus 16),
// about 64 bytes a base besides its text, 8 bytes a slot of the hash tables (at most half full).
// Thread safety: none; a const index may be read from many threads.
#pragma once

#include "core/util/index_table.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::scene::detail {

class NameIndex {
public:
    static constexpr uint32_t kNone = util::IndexTable::kNone;

    // A name split into its base and trailing number, when it has one in canonical form: 1 to 9
    // digits, no leading zero unless the number is 0 ("x0", "x12"; not "x", "x012", "x1234567890").
    struct Split {
        std::string_view base;
        uint32_t number = 0;
        bool numbered = false;
    };
    static Split split(std::string_view name);

    // The entry stored under `name`, or kNone. nameOf(entry) gives an entry's name (for the names
    // that live in the hash table, whose text the index does not keep).
    template <class NameOf>
    uint32_t find(std::string_view name, NameOf&& nameOf) const {
        const Split s = split(name);
        if (s.numbered) {
            if (const uint32_t* slot = slotOf(s); slot && *slot != kNone) return *slot;
            if (m_othersNumbered == 0) return kNone;  // every numbered name is in an array
        }
        return m_others.find(util::hashBytes(name), [&](uint32_t e) { return nameOf(e) == name; });
    }
    // Stores `entry` (any value but kNone) under `name`, which must not be present.
    void insert(std::string_view name, uint32_t entry);
    // Replaces `entry` under `name` by `replacement`; returns false if `entry` is not stored there.
    bool replace(std::string_view name, uint32_t entry, uint32_t replacement);
    // Removes `entry` from under `name`; returns false if it is not stored there.
    bool erase(std::string_view name, uint32_t entry);

    size_t size() const { return m_count; }
    size_t memoryBytes() const;

private:
    struct Base {
        uint32_t textOffset = 0;  // in m_text
        uint32_t textSize = 0;
        uint32_t count = 0;       // names held in `slots`
        std::vector<uint32_t> slots;  // by number; kNone: no such name here
    };
    uint32_t findBase(std::string_view base) const;
    // The array slot of a numbered name, or nullptr when its base's array does not reach it;
    // `base` receives the base's index.
    uint32_t* slotOf(const Split& s, uint32_t* base = nullptr);
    const uint32_t* slotOf(const Split& s) const { return const_cast<NameIndex*>(this)->slotOf(s); }
    uint32_t addBase(std::string_view base);
    std::string_view baseText(const Base& b) const { return std::string_view(m_text).substr(b.textOffset, b.textSize); }

    std::vector<Base> m_bases;
    util::IndexTable m_baseIndex;  // base text → index into m_bases
    std::string m_text;            // the bases' texts, one after another
    util::IndexTable m_others;     // every other name → entry
    size_t m_othersNumbered = 0;   // numbered names in m_others (too far past their base's count)
    size_t m_count = 0;
};

}  // namespace pushpin::scene::detail
