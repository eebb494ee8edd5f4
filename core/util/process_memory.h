// core/util/process_memory.h: what the process's allocator holds for live blocks, for charging a
// memory budget with what no single structure accounts for (the node tables of a loaded scene,
// the small allocations of a frame scene).
// Thread safety: callable from any thread. Memory: none.
#pragma once

#include <cstdint>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace pushpin::util {

// Bytes in live heap blocks (glibc: mallinfo2's in-use and mmapped bytes); 0 where the C library
// does not say.
inline uint64_t heapBytesInUse() {
#ifdef __GLIBC__
    const struct mallinfo2 m = mallinfo2();
    return uint64_t(m.uordblks) + uint64_t(m.hblkhd);
#else
    return 0;
#endif
}

// Makes every later block of `bytes` or more a mapping of its own, handed back to the system when
// it is freed (glibc: a fixed M_MMAP_THRESHOLD instead of one that grows with the blocks freed).
// Under a memory cap the blocks that making and dropping tessellations free then leave the
// process at once instead of staying resident between live blocks. Process-wide; idempotent.
inline void returnLargeBlocksOnFree(uint64_t bytes = uint64_t(1) << 18) {
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, int(bytes));
#else
    (void)bytes;
#endif
}

}  // namespace pushpin::util
