// texture/texture_cache.h: the one page cache every file texture of a render shares.
// Owns: N page slots (default 256) of 8×8 texels stored as float, a map from (texture, level,
// page) to slot, a bounded pool of open BOT files (each mapped read-only, or held as a descriptor
// where mapping fails), the registered textures and the statistics. Pages are read on demand
// (checksum + zstd through BotFile, from the mapping or with pread) and the least recently used
// page is replaced when the cache is full: exactly for up to 64 slots used from one thread;
// beyond that, the least recently used of the 64 slots after a rotating hand (see nextStamp()
// for how recency is recorded across threads).
// Thread safety: every public method may be called from any thread. Lookups go through a
// TextureCache::PerThread handle, one per thread: a page that the handle's microcache still
// resolves is read with no lock and no atomic read-modify-write; other hits take one shard lock;
// misses also take the eviction lock (one evicting thread at a time) and the file-pool lock,
// and the thread that loads a page is the only one that does (others wait for it).
// Memory: charged to TextureCacheOptions::memoryBudget (category textures) as it is allocated and
// released when freed; memoryBytes() is always the amount charged: the slots and their metadata
// (allocated at construction, reused on eviction, freed by the destructor), each registered
// texture's header, page table and dictionary (or in-memory pyramid), and each PerThread handle.
// Mapped files are not charged: their resident pages are the kernel's page cache, shared and
// reclaimable, the same pages pread would have filled.
// Files that change while open: a file shorter than when it was registered is refused when the
// pool opens it (the texture becomes broken, with one warning). A file truncated in place while
// it is mapped makes the next read of a page past its new end fail with an IoError naming the
// file and page (a guarded copy turns the SIGBUS into an error; see detail/mapped_file.h): the
// texture becomes broken, never the process. A file replaced by rename keeps being read from the
// old inode until the pool closes it.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "texture/bot_file.h"

namespace pushpin::cache {
class MemoryBudget;
}

namespace pushpin::texture {

namespace detail {
class PageSource;
}
class LookupTraceWriter;

// A registered texture, resolved once when the scene loads; lookups never search by name.
struct TextureHandle {
    static constexpr uint32_t kInvalid = 0xffffffffu;
    uint32_t id = kInvalid;
    bool valid() const { return id != kInvalid; }
    friend bool operator==(TextureHandle, TextureHandle) = default;
};

// Counters of one thread or of the whole cache (plain data; merge() adds them up).
// Invariants once all lookups have returned: lookups == hits + misses and
// misses == pagesRead + failedPages.
struct TextureCacheStats {
    // Page requests made by filtered lookups. A request whose page was evicted by another
    // thread between being loaded and being read loads it again and counts twice, so that
    // lookups == hits + misses and misses == pagesRead + failedPages always hold.
    uint64_t lookups = 0;
    uint64_t hits = 0;             // requests served by a resident page (or one another thread was loading)
    uint64_t misses = 0;           // requests that loaded the page (or failed to)
    uint64_t evictions = 0;        // resident pages replaced to make room
    uint64_t pagesRead = 0;        // pages loaded successfully
    uint64_t failedPages = 0;      // page loads that failed (corrupt or unreadable page)
    uint64_t bytesRead = 0;        // compressed bytes read from the files (mapped or pread)
    uint64_t filteredLookups = 0;  // texture samples (each made of one or more page requests)
    uint64_t fileOpens = 0;        // files opened (and mapped) by the file pool
    uint64_t fileCloses = 0;       // files closed (and unmapped) to stay under maxOpenFiles
    uint64_t peakOpenFiles = 0;    // most files open at once (merge keeps the maximum)
    uint64_t brokenTextures = 0;   // textures marked broken (failed open or failed page)
    double readSeconds = 0;        // wall time inside page reads: copy or pread, checksum, decompression

    void merge(const TextureCacheStats& other);
    double hitRatio() const { return lookups ? double(hits) / double(lookups) : 0.0; }
};
std::ostream& operator<<(std::ostream& os, const TextureCacheStats& s);

struct TextureCacheOptions {
    uint32_t pageSlots = 256;     // pages held at once; at least 1
    uint32_t maxChannels = 4;     // widest texture the slots hold (1..16); sets bytesPerSlot()
    uint32_t maxOpenFiles = 100;  // files held open (mapped or as a descriptor) at once; at least 1
    // Read pages from read-only mappings of the files (one memcpy per page) rather than with one
    // pread system call per page. Files that cannot be mapped are read with pread either way.
    bool mapFiles = true;
    // Where the cache's memory is charged (category textures); null: nowhere. Must outlive the
    // cache. Charged unconditionally: this memory is needed for a correct image, so the budget
    // records it even past its cap and other consumers make room.
    cache::MemoryBudget* memoryBudget = nullptr;
    // Receives each warning (broken texture, missing file). Default: one line on stderr.
    std::function<void(const std::string&)> warningHandler;
};

// Level geometry in the form a lookup uses it.
struct TextureLevelInfo {
    uint32_t width = 0, height = 0;
    float widthF = 0, heightF = 0;
};

// What the sampler needs of a texture; fixed after registration.
struct TextureInfo {
    uint32_t width = 0, height = 0, channels = 0;
    WrapMode wrapS = WrapMode::Periodic, wrapT = WrapMode::Periodic;
    std::vector<TextureLevelInfo> levels;  // level 0 = full resolution
    std::filesystem::path path;
};

class TextureCache {
public:
    class PerThread;

    // Allocates the slots. Throws std::invalid_argument when an option is out of range.
    explicit TextureCache(const TextureCacheOptions& options = {});
    // Every PerThread of this cache must be destroyed first. Closes all descriptors.
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    // The process-wide cache, created on first call with `firstUseOptions` (ignored afterwards).
    static TextureCache& process(const TextureCacheOptions& firstUseOptions = {});

    // Registers a BOT file; the same path (after lexical normalisation) returns the same handle.
    // Reads the header and page table now; keeps no descriptor open. Never throws for a bad
    // file: a missing, unreadable or invalid file gives a valid handle whose texture is broken,
    // with one warning naming the path; lookups on it return the default colour.
    TextureHandle registerFile(const std::filesystem::path& path);
    // Registers a texture whose pages come from `source` (an in-memory image, for example).
    TextureHandle registerSource(std::shared_ptr<const detail::PageSource> source);

    // nullptr for an invalid handle or a texture that failed to open; otherwise stable for the
    // lifetime of the cache.
    const TextureInfo* info(TextureHandle handle) const;
    // True once the texture failed to open or a page of it failed to load.
    bool broken(TextureHandle handle) const;
    size_t textureCount() const;

    // Sum over all threads, readable at any time (figures of running lookups may lag a little).
    TextureCacheStats stats() const;
    uint32_t pageSlots() const;
    size_t bytesPerSlot() const;
    // pageSlots() × bytesPerSlot(): the texel storage alone.
    size_t slotMemoryBytes() const;
    // Everything the cache charges to its memory budget right now (see the header comment).
    size_t memoryBytes() const;
    // Files held open by the pool (mapped or as a descriptor).
    size_t openFileCount() const;

    // When set, every filtered lookup batch is appended to `writer` (which must outlive its use).
    void setTraceWriter(LookupTraceWriter* writer);
    LookupTraceWriter* traceWriter() const { return m_trace.load(std::memory_order_acquire); }

    // Sends a message to the warning handler. Thread-safe.
    void warn(const std::string& message) const;

    struct Impl;

private:
    std::unique_ptr<Impl> m_impl;
    std::atomic<LookupTraceWriter*> m_trace{nullptr};
};

// One thread's way into the cache: a direct-mapped microcache of recently used pages in front
// of the shared map, and this thread's counters. Use from one thread only; destroy before the
// cache. Cheap to create (about 50 KB, charged to the cache's memory budget while it lives).
class TextureCache::PerThread {
public:
    explicit PerThread(TextureCache& cache);
    ~PerThread();
    PerThread(const PerThread&) = delete;
    PerThread& operator=(const PerThread&) = delete;

    TextureCache& cache() const { return *m_cache; }

    // Copies `count` texels of page (pageX, pageY) of `level`: texel offsets[i] (y × 8 + x within
    // the page) goes to out[i × channels … + channels), where channels is the texture's count.
    // The page must exist (level and page indices in range). Counts one page lookup, as a hit or
    // a miss (see TextureCacheStats::lookups). Returns false, writing nothing, when the texture is
    // broken or this page cannot be loaded (the texture is then marked broken and reported once).
    // Never throws.
    bool readTexels(TextureHandle texture, uint32_t level, uint32_t pageX, uint32_t pageY,
                    const uint8_t* offsets, uint32_t count, float* out) {
        return readTexelsN<0>(texture, level, pageX, pageY, offsets, count, out);
    }
    // The same with the texture's channel count known at compile time (C > 0; C == 0 reads it
    // from the page), so filters dispatched once per batch get unrolled copies.
    template <uint32_t C>
    bool readTexelsN(TextureHandle texture, uint32_t level, uint32_t pageX, uint32_t pageY,
                     const uint8_t* offsets, uint32_t count, float* out);

    void countFilteredLookups(uint64_t n) { bump(m_filteredLookups, n); }
    // This thread's share of the counters.
    TextureCacheStats stats() const;

    static uint64_t pageKey(uint32_t textureId, uint32_t level, uint32_t pageX, uint32_t pageY) {
        return (uint64_t(textureId) << 43) | (uint64_t(level) << 38) | (uint64_t(pageY) << 19) |
               uint64_t(pageX);
    }

private:
    struct MicroEntry {
        uint64_t key = ~uint64_t(0);
        const float* data = nullptr;
        const std::atomic<uint64_t>* generation = nullptr;
        uint64_t generationValue = 0;
        std::atomic<uint64_t>* stamp = nullptr;
        uint32_t channels = 0;
    };
    static constexpr uint32_t kMicroBits = 10;  // 1024 entries, 48 KiB: covers two mip levels of a tile
    static constexpr uint32_t kStampCountBits = 24;

    // Only the owning thread writes its counters, so a relaxed load + store (no locked
    // instruction) is enough; other threads read them for stats().
    static void bump(std::atomic<uint64_t>& c, uint64_t n = 1) {
        c.store(c.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
    }
    uint64_t nextStamp();
    size_t heapBytes() const;  // what this handle charges to the cache's memory budget
    // How a page request was served; decides which counter it lands in.
    enum class Outcome : uint8_t { Microcache, SharedHit, Loaded, Rejected };
    bool refill(uint64_t key, TextureHandle texture, uint32_t level, uint32_t pageX,
                uint32_t pageY, MicroEntry& entry, Outcome& outcome);
    // Loads are counted when they happen (one lookup and one miss each); a request served
    // without loading counts one lookup and one hit; a request rejected because the texture is
    // broken counts nothing.
    void countOutcome(Outcome outcome) {
        if (outcome == Outcome::Rejected || outcome == Outcome::Loaded) return;
        bump(m_lookups);
        bump(m_hits);
    }

    TextureCache* m_cache;
    Impl* m_impl;
    const std::atomic<uint64_t>* m_epoch;
    uint64_t m_stampEpoch = ~uint64_t(0);
    uint64_t m_stampCount = 0;
    std::unique_ptr<MicroEntry[]> m_micro;
    std::vector<float> m_scratch;
    std::atomic<uint64_t> m_lookups{0}, m_hits{0}, m_misses{0}, m_filteredLookups{0};
    std::atomic<uint64_t> m_evictions{0}, m_pagesRead{0}, m_failedPages{0}, m_bytesRead{0},
        m_readNanos{0};
};

// Recency stamp: the global miss epoch in the high bits, this thread's access count within that
// epoch in the low bits. From one thread, stamps strictly increase, so eviction is exact LRU;
// across threads, order is exact between epochs (every miss starts one) and arbitrary within
// one, a close approximation that costs one relaxed load of a read-mostly line per access.
inline uint64_t TextureCache::PerThread::nextStamp() {
    const uint64_t epoch = m_epoch->load(std::memory_order_relaxed);
    if (epoch != m_stampEpoch) {
        m_stampEpoch = epoch;
        m_stampCount = 0;
    }
    if (m_stampCount < (uint64_t(1) << kStampCountBits) - 1) ++m_stampCount;
    return (epoch << kStampCountBits) | m_stampCount;
}

// Why this is safe without pinning: a slot's generation is odd while the slot is empty or being
// refilled and even while it holds a page, and it changes on every eviction (a seqlock). A reader
// loads the generation (acquire), copies the texels with relaxed atomic loads, fences, and
// re-checks the generation; if an evictor reused the slot meanwhile, the copy is thrown away and
// the page is looked up again. So the evictor never waits for readers and a reader never returns
// texels of another page.
template <uint32_t C>
inline bool TextureCache::PerThread::readTexelsN(TextureHandle texture, uint32_t level,
                                                 uint32_t pageX, uint32_t pageY,
                                                 const uint8_t* offsets, uint32_t count,
                                                 float* out) {
    const uint64_t key = pageKey(texture.id, level, pageX, pageY);
    MicroEntry& e = m_micro[(key * 0x9E3779B97F4A7C15ull) >> (64 - kMicroBits)];
    Outcome outcome = Outcome::Microcache;
    for (;;) {
        if (e.key == key) {
            const uint64_t g = e.generation->load(std::memory_order_acquire);
            if (g == e.generationValue) {
                const uint32_t c = C ? C : e.channels;
                float* page = const_cast<float*>(e.data);
                // Unrolled for the filters' constant counts (1, 2 or 4 texels of C channels):
                // -O2 leaves these short loops rolled otherwise.
#pragma GCC unroll 4
                for (uint32_t i = 0; i < count; ++i) {
                    float* src = page + size_t(offsets[i]) * c;
#pragma GCC unroll 4
                    for (uint32_t ch = 0; ch < c; ++ch)
                        out[i * c + ch] = std::atomic_ref<float>(src[ch]).load(std::memory_order_relaxed);
                }
                std::atomic_thread_fence(std::memory_order_acquire);
                if (e.generation->load(std::memory_order_relaxed) == g) {
                    e.stamp->store(nextStamp(), std::memory_order_relaxed);
                    countOutcome(outcome);
                    return true;
                }
            }
        }
        if (!refill(key, texture, level, pageX, pageY, e, outcome)) {
            countOutcome(outcome);
            return false;
        }
    }
}

}  // namespace pushpin::texture
