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

}  // namespace pushpin::util
