// texture/detail/page_map.h: the open-addressing hash map from page key to cache entry that each
// shard of TextureCache keeps. Linear probing with backward-shift deletion, so a miss (insert) and
// an eviction (erase) never allocate once the table has grown to its working size.
// Thread safety: none; the owning shard's mutex guards it.
// Memory: 2 × (8 + sizeof(Value)) bytes per entry at most-half load.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pushpin::texture::detail {

template <class Value>
class PageMap {
public:
    static constexpr uint64_t kEmpty = ~uint64_t(0);  // never a page key (texture ids < 2^20)

    PageMap() { rehash(16); }

    Value* find(uint64_t key) {
        for (size_t i = home(key);; i = (i + 1) & m_mask) {
            if (m_keys[i] == key) return &m_values[i];
            if (m_keys[i] == kEmpty) return nullptr;
        }
    }

    // Inserts a value-initialised entry for `key`, which must not be present.
    Value& insert(uint64_t key) {
        if ((m_size + 1) * 2 > m_keys.size()) rehash(m_keys.size() * 2);
        size_t i = home(key);
        while (m_keys[i] != kEmpty) i = (i + 1) & m_mask;
        m_keys[i] = key;
        m_values[i] = Value{};
        ++m_size;
        return m_values[i];
    }

    // Removes `key`; returns false if it was absent.
    bool erase(uint64_t key) {
        size_t i = home(key);
        while (m_keys[i] != key) {
            if (m_keys[i] == kEmpty) return false;
            i = (i + 1) & m_mask;
        }
        // Backward shift: pull later entries of the probe run into the hole unless their home
        // lies cyclically in (hole, position], where they would become unreachable.
        for (size_t j = (i + 1) & m_mask; m_keys[j] != kEmpty; j = (j + 1) & m_mask) {
            const size_t k = home(m_keys[j]);
            const bool stays = (i <= j) ? (i < k && k <= j) : (i < k || k <= j);
            if (stays) continue;
            m_keys[i] = m_keys[j];
            m_values[i] = m_values[j];
            i = j;
        }
        m_keys[i] = kEmpty;
        --m_size;
        return true;
    }

    size_t size() const { return m_size; }

private:
    size_t home(uint64_t key) const { return size_t((key * 0x9E3779B97F4A7C15ull) >> m_shift); }

    void rehash(size_t capacity) {
        std::vector<uint64_t> keys(capacity, kEmpty);
        std::vector<Value> values(capacity);
        keys.swap(m_keys);
        values.swap(m_values);
        m_mask = capacity - 1;
        m_shift = 64;
        for (size_t c = capacity; c > 1; c >>= 1) --m_shift;
        m_size = 0;
        for (size_t i = 0; i < keys.size(); ++i)
            if (keys[i] != kEmpty) insert(keys[i]) = values[i];
    }

    std::vector<uint64_t> m_keys;
    std::vector<Value> m_values;
    size_t m_mask = 0;
    int m_shift = 64;
    size_t m_size = 0;
};

}  // namespace pushpin::texture::detail
