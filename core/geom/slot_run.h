// core/geom/slot_run.h: where a triangle id of a shape made in pieces lives. A piece's triangles
// need not have consecutive ids (a piece may gather several runs of faces), so a shape lists its
// runs of ids: ids [firstSlot, the next run's firstSlot) are the triangles local, local + 1, … of
// piece `piece`'s tessellation.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pushpin::geom {

struct SlotRun {
    uint32_t firstSlot = 0;
    uint32_t piece = 0;
    uint32_t local = 0;
};

// The run holding `slot` among `count` runs sorted by firstSlot (the last one starting at or
// before it), or null when the first starts after it.
inline const SlotRun* findSlotRun(const SlotRun* runs, size_t count, uint32_t slot) {
    if (count == 0 || runs[0].firstSlot > slot) return nullptr;
    size_t lo = 0, hi = count;
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        (runs[mid].firstSlot <= slot ? lo : hi) = mid;
    }
    return runs + lo;
}

}  // namespace pushpin::geom
