// core/scene/packed_ints.h: a read-only array of 32-bit integers kept small, for the graph's large
// stored runs of integers (mesh edges, the edges and uv ids of face records).
//
// The numbers are cut into blocks of kBlockNumbers. Each number of a block is predicted by the
// number `stride` places before it in the block (0 for the first `stride`), where the block takes
// the stride, 1 or the caller's hint, that codes its first 256 numbers smaller. Numbers and predictions are zigzagged
// (n >= 0 to 2n, n < 0 to -2n - 1: a face record's edge ~e lands next to edge e), their difference
// is zigzagged again and written in 7-bit groups, and the block's bytes are compressed by zstd when
// that saves an eighth. So the edges of a mesh (three numbers an edge) and of a run of quads (four
// a face) cost a byte or two a number before zstd, which takes runs of regular ids down further.
//
// Reading any range decodes the blocks it touches. Each reading thread keeps the last few blocks it
// decoded (kCachedBlocks of them), so reading a run number by number decodes each block once.
//
// Thread safety: immutable after construction; any number of threads may read at once. Each thread
// that reads or makes one keeps a zstd context and its decoded blocks (about 20 KB) for its life.
// Memory: heapBytes() is what the array holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pushpin::scene {

class PackedInts {
public:
    static constexpr size_t kBlockNumbers = 1024;
    static constexpr size_t kCachedBlocks = 4;
    // The largest stride hint used; a larger one codes with stride 1.
    static constexpr size_t kMaxStride = 255;

    PackedInts() = default;
    // Packs `values`; `strideHint` is the distance at which numbers are most alike (the width of
    // an element, the edge count of a face), 1 when there is none.
    PackedInts(std::span<const int32_t> values, size_t strideHint);

    size_t size() const { return m_size; }
    bool empty() const { return m_size == 0; }
    // Numbers [first, first + n) into out. Throws std::out_of_range past the end.
    void read(size_t first, size_t n, int32_t* out) const;
    int32_t operator[](size_t i) const {
        int32_t v = 0;
        read(i, 1, &v);
        return v;
    }
    std::vector<int32_t> unpacked() const {
        std::vector<int32_t> out(m_size);
        read(0, m_size, out.data());
        return out;
    }
    size_t heapBytes() const { return m_blockEnds.capacity() * sizeof(uint64_t) + m_bytes.capacity(); }

private:
    // Decoded block `block` from the thread's cache, decoding it there when it is not held.
    const int32_t* block(size_t block) const;

    uint64_t m_id = 0;  // names this array's blocks in the threads' caches (shared by copies)
    size_t m_size = 0;
    std::vector<uint64_t> m_blockEnds;  // block b's bytes end at m_bytes[m_blockEnds[b]]
    std::vector<uint8_t> m_bytes;
};

}  // namespace pushpin::scene
