// texture/detail/mapped_file.h: read-only mappings of BOT files for the texture cache, and a copy
// out of a mapping that survives the file shrinking underneath it.
// Thread safety: every function may be called from any thread. copyFromMapping uses a per-thread
// guard and a process-wide SIGBUS handler installed on the first mapFile call (it chains to the
// handler that was there before for every fault that is not inside a guarded copy).
// Memory: a mapping holds address space, not heap; its resident pages are the kernel's page cache
// (shared, clean, reclaimable: the same pages a pread would fill), so nothing is charged.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pushpin::texture::detail {

// Maps the first `byteCount` bytes of the regular file open on `fd` read-only (MAP_SHARED).
// Returns nullptr (errno set) when mmap fails, for example on a file system that cannot map;
// callers then fall back to pread. The descriptor may be closed once this returns.
const uint8_t* mapFile(int fd, size_t byteCount);
// Undoes mapFile. No thread may be reading from the mapping.
void unmapFile(const uint8_t* bytes, size_t byteCount);

// Copies n bytes from a mapping made by mapFile. Returns false, with dst partly written, when the
// read faults because the file became shorter than the mapping since it was mapped (SIGBUS);
// then nothing else is affected and the same thread may go on. Never throws.
bool copyFromMapping(void* dst, const uint8_t* src, size_t n) noexcept;

}  // namespace pushpin::texture::detail
