// core/util/counting_sort.h: filing items under small integer keys in one stable pass (a
// counting sort), as the mesh and tile code does with points and pixels, or in place.
// Header-only; reentrant; allocates only `start`, `out` and `fill`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pushpin::util {

// Files items under keys below keyCount, keeping their order within a key. `forEach(visit)` calls
// visit(key, item) for every item to file, the same items in the same order each time (it is run
// twice: once to count, once to place). Afterwards `out` holds the items key by key and `start`
// (keyCount + 1 entries) bounds them: key k's items are out[start[k]] .. out[start[k + 1] - 1].
template <class Item, class ForEach>
void fileByKey(size_t keyCount, ForEach&& forEach, std::vector<uint32_t>& start, std::vector<Item>& out) {
    start.assign(keyCount + 1, 0);
    forEach([&](size_t key, const Item&) { ++start[key + 1]; });
    for (size_t k = 0; k < keyCount; ++k) start[k + 1] += start[k];
    out.resize(start[keyCount]);
    // start[k] advances to the end of key k's items while placing, then moves back one key.
    forEach([&](size_t key, const Item& item) { out[start[key]++] = item; });
    for (size_t k = keyCount; k > 0; --k) start[k] = start[k - 1];
    start[0] = 0;
}

// Files `items` under keys below keyCount in place, by swaps (an American flag sort: each swap puts
// one item where it belongs), so that no second copy of the items is held. The order within a key
// is not kept, but it depends only on the input order. `keyOf(item)` gives an item's key;
// afterwards `start` bounds the keys as fileByKey's does. `fill` is scratch (keyCount entries).
// `items`: any contiguous container with size(), operator[] and begin()/end().
template <class Items, class KeyOf>
void fileByKeyInPlace(size_t keyCount, Items& items, KeyOf&& keyOf, std::vector<uint32_t>& start,
                      std::vector<uint32_t>& fill) {
    start.assign(keyCount + 1, 0);
    for (const auto& item : items) ++start[size_t(keyOf(item)) + 1];
    for (size_t k = 0; k < keyCount; ++k) start[k + 1] += start[k];
    fill.assign(start.begin(), start.end() - 1);
    for (size_t k = 0; k < keyCount; ++k) {
        const uint32_t end = start[k + 1];
        while (fill[k] < end) {
            auto& here = items[fill[k]];
            const size_t key = size_t(keyOf(here));
            if (key == k) {
                ++fill[k];
            } else {
                using std::swap;
                swap(here, items[fill[key]++]);
            }
        }
    }
}

}  // namespace pushpin::util
