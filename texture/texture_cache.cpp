// texture/texture_cache.cpp: slots, the sharded page map, LRU eviction, the file pool and the
// memory accounting.
#include "texture/texture_cache.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <new>
#include <stdexcept>
#include <thread>
#include <unordered_map>

#include "cache/error.h"
#include "cache/memory_budget.h"
#include "texture/detail/mapped_file.h"
#include "texture/detail/page_map.h"
#include "texture/detail/page_source.h"

namespace pushpin::texture {

void TextureCacheStats::merge(const TextureCacheStats& o) {
    lookups += o.lookups;
    hits += o.hits;
    misses += o.misses;
    evictions += o.evictions;
    pagesRead += o.pagesRead;
    failedPages += o.failedPages;
    bytesRead += o.bytesRead;
    filteredLookups += o.filteredLookups;
    fileOpens += o.fileOpens;
    fileCloses += o.fileCloses;
    peakOpenFiles = std::max(peakOpenFiles, o.peakOpenFiles);
    brokenTextures += o.brokenTextures;
    readSeconds += o.readSeconds;
}

std::ostream& operator<<(std::ostream& os, const TextureCacheStats& s) {
    return os << "{lookups " << s.lookups << ", hits " << s.hits << ", misses " << s.misses
              << ", evictions " << s.evictions << ", pagesRead " << s.pagesRead
              << ", failedPages " << s.failedPages << ", bytesRead " << s.bytesRead
              << ", filteredLookups " << s.filteredLookups << ", fileOpens " << s.fileOpens
              << ", fileCloses " << s.fileCloses << ", peakOpenFiles " << s.peakOpenFiles
              << ", brokenTextures " << s.brokenTextures << ", readSeconds " << s.readSeconds
              << "}";
}

namespace {

constexpr uint64_t kNoKey = ~uint64_t(0);
constexpr uint32_t kShardCount = 64;
constexpr uint32_t kChunkBits = 10;
constexpr uint32_t kChunkSize = 1u << kChunkBits;
constexpr uint32_t kMaxTextures = 1u << 20;  // pageKey() keeps 20 bits of texture id
constexpr uint32_t kMaxLevels = 32;          // 5 bits of level
constexpr uint32_t kMaxPagesPerAxis = 1u << 19;
constexpr uint32_t kPageTexels = kPageSizeTexels * kPageSizeTexels;
constexpr uint32_t kVictimWindow = 64;  // slots examined per eviction

struct Texture {
    std::shared_ptr<const detail::PageSource> source;  // null when the texture failed to open
    TextureInfo info;
    std::vector<BotLevel> pages;  // page counts per level, for range checks on the miss path
    std::atomic<bool> broken{false};
    std::atomic<bool> reported{false};
    // File pool state, guarded by Impl::fdMutex. An open file is mapped (map != nullptr, no
    // descriptor kept) or, where mapping failed, held as a descriptor.
    int fd = -1;
    const uint8_t* map = nullptr;
    size_t mapBytes = 0;
    uint32_t fdUsers = 0;
    uint64_t fdLastUse = 0;
    bool open() const { return fd >= 0 || map; }
    detail::PageFile file() const { return detail::PageFile{fd, map, mapBytes}; }
};

enum class EntryState : uint8_t { Loading, Ready, Failed };

struct Entry {
    uint32_t slot = 0;
    uint64_t generation = 0;
    EntryState state = EntryState::Loading;
};

struct alignas(64) Shard {
    std::mutex mutex;
    std::condition_variable loaded;
    detail::PageMap<Entry> map;
};

// Read by every hit (generation); written only when the slot is refilled.
struct alignas(64) SlotMeta {
    std::atomic<uint64_t> generation{1};  // odd: empty or being filled; even: holds `key`
    // Changed under Impl::evictMutex, except that the thread filling a slot publishes it (key,
    // then SlotStamp's resident and loading = false with release) without the lock; the evictor
    // reads loading first with acquire, so a slot it sees as not loading shows its key.
    std::atomic<uint64_t> key{kNoKey};
};

// The stamp is written by every hit; kept on its own line so those writes do not invalidate the
// generation line other readers are loading. The slot's state flags share the stamp's line, so
// that the victim scan (Impl::acquireSlot) reads one line per slot instead of two.
struct alignas(64) SlotStamp {
    std::atomic<uint64_t> stamp{0};
    std::atomic<bool> loading{false};   // being filled (or chosen as a victim)
    std::atomic<bool> resident{false};  // holds a published page
};

}  // namespace

struct TextureCache::Impl {
    TextureCacheOptions options;
    size_t slotFloats = 0;
    std::unique_ptr<SlotMeta[]> slots;
    std::unique_ptr<SlotStamp[]> stamps;
    float* data = nullptr;

    std::atomic<uint64_t> epoch{1};
    std::mutex evictMutex;
    std::vector<uint32_t> freeSlots;  // guarded by evictMutex; their generation is odd
    uint32_t hand = 0;                // guarded by evictMutex; where the next victim scan starts
    std::unique_ptr<Shard[]> shards;

    // Texture table: chunks of atomic pointers, so lookups resolve a handle without a lock.
    std::unique_ptr<std::atomic<std::atomic<Texture*>*>[]> chunks;
    mutable std::mutex registryMutex;
    std::unordered_map<std::string, uint32_t> byPath;
    std::vector<std::unique_ptr<Texture>> owned;
    std::vector<std::unique_ptr<std::atomic<Texture*>[]>> ownedChunks;

    mutable std::mutex fdMutex;
    std::condition_variable fdReleased;
    std::vector<Texture*> openTextures;
    uint64_t fdTick = 0;
    uint64_t peakOpenFiles = 0;

    // Miss-path counters that are not per thread (evictions, page reads and their bytes and
    // time are counted by the PerThread that did them, so misses on different threads do not
    // contend on shared counters).
    std::atomic<uint64_t> fileOpens{0}, fileCloses{0}, brokenTextures{0};

    mutable std::mutex threadsMutex;
    std::vector<PerThread*> threads;
    TextureCacheStats retired;

    std::function<void(const std::string&)> warningHandler;

    // What memoryBytes() reports; every change is charged to or released from the budget.
    std::atomic<uint64_t> accountedBytes{0};

    void account(uint64_t bytes) {
        accountedBytes.fetch_add(bytes, std::memory_order_relaxed);
        if (options.memoryBudget) options.memoryBudget->charge(cache::MemoryCategory::Textures, bytes);
    }
    void unaccount(uint64_t bytes) {
        if (options.memoryBudget) options.memoryBudget->release(cache::MemoryCategory::Textures, bytes);
        accountedBytes.fetch_sub(bytes, std::memory_order_relaxed);
    }

    Shard& shardFor(uint64_t key) {
        return shards[(key * 0xC2B2AE3D27D4EB4Full) >> 58];  // 64 shards
    }

    Texture* texture(uint32_t id) const {
        if (id >= kMaxTextures) return nullptr;
        std::atomic<Texture*>* chunk = chunks[id >> kChunkBits].load(std::memory_order_acquire);
        return chunk ? chunk[id & (kChunkSize - 1)].load(std::memory_order_acquire) : nullptr;
    }

    void warn(const std::string& message) const {
        if (warningHandler)
            warningHandler(message);
        else
            std::cerr << "pushpin: warning: " << message << "\n";
    }

    void markBroken(Texture& t, const std::string& why) {
        t.broken.store(true, std::memory_order_release);
        if (!t.reported.exchange(true)) {
            brokenTextures.fetch_add(1, std::memory_order_relaxed);
            warn("texture '" + t.info.path.string() + "' is broken (" + why +
                 "); its lookups return the default colour from now on");
        }
    }

    // Returns a slot to fill, with `loading` set and an odd generation. Evicts the least recently
    // stamped resident slot when none is free. Slots being filled by other threads are never
    // chosen; if every slot is being filled, waits for one to finish.
    uint32_t acquireSlot(bool& evicted) {
        std::unique_lock lock(evictMutex);
        evicted = false;
        for (;;) {
            if (!freeSlots.empty()) {
                const uint32_t s = freeSlots.back();
                freeSlots.pop_back();
                stamps[s].loading.store(true, std::memory_order_relaxed);
                return s;
            }
            // The victim is the least recently stamped of the next kVictimWindow slots from the
            // hand: with up to kVictimWindow slots that is every slot (exact LRU from one
            // thread); beyond, it keeps a miss at a bounded cost, a sampled approximation of LRU
            // in the manner of CLOCK. A window with nothing evictable moves on to the next.
            const uint32_t n = options.pageSlots;
            const uint32_t window = std::min(n, kVictimWindow);
            uint32_t victim = ~0u;
            uint64_t oldest = ~uint64_t(0);
            for (uint32_t scanned = 0; scanned < n && victim == ~0u;) {
                for (uint32_t k = 0; k < window && scanned < n; ++k, ++scanned) {
                    const uint32_t s = hand;
                    hand = (hand + 1 == n) ? 0 : hand + 1;
                    if (stamps[s].loading.load(std::memory_order_acquire) ||
                        !stamps[s].resident.load(std::memory_order_relaxed))
                        continue;
                    const uint64_t st = stamps[s].stamp.load(std::memory_order_relaxed);
                    if (st < oldest) {
                        oldest = st;
                        victim = s;
                    }
                }
            }
            if (victim == ~0u) {
                lock.unlock();
                std::this_thread::yield();
                lock.lock();
                continue;
            }
            SlotMeta& meta = slots[victim];
            const uint64_t oldKey = meta.key.load(std::memory_order_relaxed);
            {
                // Unmap first, then invalidate: while the entry is in the map under its shard
                // lock, the generation it records is current, so a thread that found it reads a
                // page that was valid at that moment and re-validates after copying.
                Shard& sh = shardFor(oldKey);
                std::lock_guard shardLock(sh.mutex);
                const Entry* e = sh.map.find(oldKey);
                if (e && e->state == EntryState::Ready && e->slot == victim) sh.map.erase(oldKey);
            }
            meta.generation.fetch_add(1, std::memory_order_relaxed);  // now odd
            meta.key.store(kNoKey, std::memory_order_relaxed);
            stamps[victim].resident.store(false, std::memory_order_relaxed);
            stamps[victim].loading.store(true, std::memory_order_relaxed);
            evicted = true;
            return victim;
        }
    }

    void releaseFailedSlot(uint32_t s) {
        std::lock_guard lock(evictMutex);
        slots[s].key.store(kNoKey, std::memory_order_relaxed);
        stamps[s].resident.store(false, std::memory_order_relaxed);
        stamps[s].loading.store(false, std::memory_order_relaxed);
        freeSlots.push_back(s);
    }

    // Makes a filled slot evictable. No lock: only this thread touches a loading slot.
    void publishSlot(uint32_t s, uint64_t key) {
        slots[s].key.store(key, std::memory_order_relaxed);
        stamps[s].resident.store(true, std::memory_order_relaxed);
        stamps[s].loading.store(false, std::memory_order_release);
    }

    // Opens t's file for the pool: checks that it is still as long as when it was registered
    // (so no page the tables describe lies past its end), then maps it, or keeps the descriptor
    // when mapping is off or fails. Caller holds fdMutex. Throws IoError / FormatError.
    void openFile(Texture& t) {
        const int fd = ::open(t.info.path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) throw IoError(t.info.path, "open texture", errno);
        struct stat st {};
        if (::fstat(fd, &st) != 0) {
            const int e = errno;
            ::close(fd);
            throw IoError(t.info.path, "stat texture", e);
        }
        const uint64_t need = t.source->fileBytes();
        if (uint64_t(st.st_size) < need) {
            ::close(fd);
            throw FormatError(t.info.path, "the file is now " + std::to_string(st.st_size) +
                                               " bytes, shorter than the " + std::to_string(need) +
                                               " it had when registered (truncated since?)");
        }
        fileOpens.fetch_add(1, std::memory_order_relaxed);
        if (options.mapFiles) {
            if (const uint8_t* m = detail::mapFile(fd, size_t(need))) {
                ::close(fd);  // the mapping keeps the file (its inode) alive
                t.map = m;
                t.mapBytes = size_t(need);
                return;
            }
        }
        t.fd = fd;
    }

    void closeFile(Texture& t) {
        if (t.map) detail::unmapFile(t.map, t.mapBytes);
        if (t.fd >= 0) ::close(t.fd);
        t.map = nullptr;
        t.mapBytes = 0;
        t.fd = -1;
    }

    // Returns the way to t's file (empty for a memory source), opening it if needed and closing
    // the least recently used idle file to stay under maxOpenFiles. Waits when every open file is
    // in use (each thread uses at most one at a time, so one frees up). Throws IoError or
    // FormatError when the file cannot be opened.
    detail::PageFile acquireFile(Texture& t) {
        if (!t.source->needsFile()) return {};
        std::unique_lock lock(fdMutex);
        ++fdTick;
        if (t.open()) {
            ++t.fdUsers;
            t.fdLastUse = fdTick;
            return t.file();
        }
        while (openTextures.size() >= options.maxOpenFiles) {
            auto lru = openTextures.end();
            for (auto it = openTextures.begin(); it != openTextures.end(); ++it)
                if ((*it)->fdUsers == 0 && (lru == openTextures.end() || (*it)->fdLastUse < (*lru)->fdLastUse))
                    lru = it;
            if (lru == openTextures.end()) {
                fdReleased.wait(lock);
                if (t.open()) {  // another thread opened it while we waited
                    ++t.fdUsers;
                    t.fdLastUse = ++fdTick;
                    return t.file();
                }
                continue;
            }
            closeFile(**lru);
            openTextures.erase(lru);
            fileCloses.fetch_add(1, std::memory_order_relaxed);
        }
        openFile(t);
        t.fdUsers = 1;
        t.fdLastUse = fdTick;
        openTextures.push_back(&t);
        peakOpenFiles = std::max<uint64_t>(peakOpenFiles, openTextures.size());
        return t.file();
    }

    void releaseFile(Texture& t) {
        if (!t.source->needsFile()) return;
        std::lock_guard lock(fdMutex);
        if (--t.fdUsers == 0) fdReleased.notify_one();
    }

    uint32_t addTexture(std::unique_ptr<Texture> t) {
        // Caller holds registryMutex.
        const uint32_t id = uint32_t(owned.size());
        if (id >= kMaxTextures) throw std::length_error("too many textures registered");
        const uint32_t c = id >> kChunkBits;
        size_t bytes = sizeof(Texture) + (t->source ? t->source->memoryBytes() : 0);
        if (!chunks[c].load(std::memory_order_relaxed)) {
            ownedChunks.push_back(std::make_unique<std::atomic<Texture*>[]>(kChunkSize));
            chunks[c].store(ownedChunks.back().get(), std::memory_order_release);
            bytes += kChunkSize * sizeof(std::atomic<Texture*>);
        }
        Texture* raw = t.get();
        owned.push_back(std::move(t));
        account(bytes);
        chunks[c].load(std::memory_order_relaxed)[id & (kChunkSize - 1)].store(
            raw, std::memory_order_release);
        return id;
    }

    // Fills t.info from the source, or returns why the texture cannot be used.
    // A texture that cannot be used from the start: no source, its path kept, reported once;
    // its lookups return the default colour.
    void markBroken(Texture& t, const std::filesystem::path& path, const std::string& why) {
        t.source.reset();
        t.info = TextureInfo{};
        t.info.path = path;
        t.broken.store(true);
        t.reported.store(true);
        brokenTextures.fetch_add(1, std::memory_order_relaxed);
        warn("cannot use texture '" + path.string() + "': " + why + "; its lookups return the default colour");
    }

    std::string describe(Texture& t) {
        const BotHeader& h = t.source->header();
        if (h.channels == 0 || h.channels > options.maxChannels)
            return "it has " + std::to_string(h.channels) + " channels; the cache holds 1 to " +
                   std::to_string(options.maxChannels);
        if (h.levels.empty() || h.levels.size() > kMaxLevels)
            return "it has " + std::to_string(h.levels.size()) + " mip levels";
        t.info.width = h.width;
        t.info.height = h.height;
        t.info.channels = h.channels;
        t.info.wrapS = h.wrapS;
        t.info.wrapT = h.wrapT;
        for (const BotLevel& lv : h.levels) {
            if (lv.width == 0 || lv.height == 0 || lv.pagesX >= kMaxPagesPerAxis ||
                lv.pagesY >= kMaxPagesPerAxis ||
                uint64_t(lv.pagesX) * kPageSizeTexels < lv.width ||
                uint64_t(lv.pagesY) * kPageSizeTexels < lv.height)
                return "a mip level has an invalid size";
            t.info.levels.push_back(
                TextureLevelInfo{lv.width, lv.height, float(lv.width), float(lv.height)});
            t.pages.push_back(lv);
        }
        return {};
    }
};

namespace {

// What the constructor allocates: slot texels and metadata, shards and the texture chunk table.
size_t fixedMemoryBytes(uint32_t pageSlots, size_t slotFloats) {
    return size_t(pageSlots) * (slotFloats * sizeof(float) + sizeof(SlotMeta) + sizeof(SlotStamp) +
                                sizeof(uint32_t)) +
           kShardCount * sizeof(Shard) +
           (kMaxTextures / kChunkSize) * sizeof(std::atomic<std::atomic<Texture*>*>);
}

}  // namespace

TextureCache::TextureCache(const TextureCacheOptions& options) : m_impl(std::make_unique<Impl>()) {
    if (options.pageSlots == 0) throw std::invalid_argument("TextureCache: pageSlots must be >= 1");
    if (options.maxChannels == 0 || options.maxChannels > 16)
        throw std::invalid_argument("TextureCache: maxChannels must be 1..16");
    if (options.maxOpenFiles == 0)
        throw std::invalid_argument("TextureCache: maxOpenFiles must be >= 1");
    Impl& im = *m_impl;
    im.options = options;
    im.warningHandler = options.warningHandler;
    im.slotFloats = size_t(kPageTexels) * options.maxChannels;
    im.slots = std::make_unique<SlotMeta[]>(options.pageSlots);
    im.stamps = std::make_unique<SlotStamp[]>(options.pageSlots);
    im.data = static_cast<float*>(
        ::operator new(size_t(options.pageSlots) * im.slotFloats * sizeof(float), std::align_val_t(64)));
    std::fill_n(im.data, size_t(options.pageSlots) * im.slotFloats, 0.0f);
    im.freeSlots.reserve(options.pageSlots);
    // Popped from the back, so slot 0 is filled first.
    for (uint32_t s = options.pageSlots; s-- > 0;) im.freeSlots.push_back(s);
    im.shards = std::make_unique<Shard[]>(kShardCount);
    im.chunks = std::make_unique<std::atomic<std::atomic<Texture*>*>[]>(kMaxTextures / kChunkSize);
    im.account(fixedMemoryBytes(options.pageSlots, im.slotFloats));
}

TextureCache::~TextureCache() {
    Impl& im = *m_impl;
    for (Texture* t : im.openTextures) im.closeFile(*t);
    ::operator delete(im.data, std::align_val_t(64));
    im.unaccount(im.accountedBytes.load(std::memory_order_relaxed));
}

TextureCache& TextureCache::process(const TextureCacheOptions& firstUseOptions) {
    static TextureCache cache(firstUseOptions);
    return cache;
}

TextureHandle TextureCache::registerFile(const std::filesystem::path& path) {
    Impl& im = *m_impl;
    const std::filesystem::path normal = std::filesystem::absolute(path).lexically_normal();
    std::lock_guard lock(im.registryMutex);
    if (auto it = im.byPath.find(normal.string()); it != im.byPath.end())
        return TextureHandle{it->second};
    auto t = std::make_unique<Texture>();
    t->info.path = normal;
    std::string why;
    try {
        t->source = detail::makeFilePageSource(BotFile::open(normal));
        why = im.describe(*t);
    } catch (const std::exception& ex) {
        why = ex.what();
    }
    if (!why.empty()) im.markBroken(*t, normal, why);
    const uint32_t id = im.addTexture(std::move(t));
    im.byPath.emplace(normal.string(), id);
    return TextureHandle{id};
}

TextureHandle TextureCache::registerSource(std::shared_ptr<const detail::PageSource> source) {
    if (!source) throw std::invalid_argument("TextureCache::registerSource: null source");
    Impl& im = *m_impl;
    std::lock_guard lock(im.registryMutex);
    auto t = std::make_unique<Texture>();
    t->info.path = source->path();
    t->source = std::move(source);
    if (const std::string why = im.describe(*t); !why.empty()) {
        const std::filesystem::path name = t->info.path;
        im.markBroken(*t, name, why);
    }
    return TextureHandle{im.addTexture(std::move(t))};
}

const TextureInfo* TextureCache::info(TextureHandle handle) const {
    const Texture* t = m_impl->texture(handle.id);
    return (t && t->source) ? &t->info : nullptr;
}

bool TextureCache::broken(TextureHandle handle) const {
    const Texture* t = m_impl->texture(handle.id);
    return !t || t->broken.load(std::memory_order_acquire);
}

size_t TextureCache::textureCount() const {
    std::lock_guard lock(m_impl->registryMutex);
    return m_impl->owned.size();
}

TextureCacheStats TextureCache::stats() const {
    const Impl& im = *m_impl;
    TextureCacheStats s;
    {
        std::lock_guard lock(im.threadsMutex);
        s = im.retired;
        for (const PerThread* pt : im.threads) s.merge(pt->stats());
    }
    s.fileOpens = im.fileOpens.load(std::memory_order_relaxed);
    s.fileCloses = im.fileCloses.load(std::memory_order_relaxed);
    s.brokenTextures = im.brokenTextures.load(std::memory_order_relaxed);
    {
        std::lock_guard lock(im.fdMutex);
        s.peakOpenFiles = im.peakOpenFiles;
    }
    return s;
}

uint32_t TextureCache::pageSlots() const { return m_impl->options.pageSlots; }
size_t TextureCache::bytesPerSlot() const { return m_impl->slotFloats * sizeof(float); }
size_t TextureCache::slotMemoryBytes() const { return bytesPerSlot() * pageSlots(); }
size_t TextureCache::memoryBytes() const {
    return size_t(m_impl->accountedBytes.load(std::memory_order_relaxed));
}

size_t TextureCache::openFileCount() const {
    std::lock_guard lock(m_impl->fdMutex);
    return m_impl->openTextures.size();
}

void TextureCache::setTraceWriter(LookupTraceWriter* writer) {
    m_trace.store(writer, std::memory_order_release);
}

void TextureCache::warn(const std::string& message) const { m_impl->warn(message); }

// ---------------------------------------------------------------- PerThread

TextureCache::PerThread::PerThread(TextureCache& cache)
    : m_cache(&cache),
      m_impl(cache.m_impl.get()),
      m_epoch(&cache.m_impl->epoch),
      m_micro(std::make_unique<MicroEntry[]>(size_t(1) << kMicroBits)),
      m_scratch(m_impl->slotFloats) {
    m_impl->account(heapBytes());
    std::lock_guard lock(m_impl->threadsMutex);
    m_impl->threads.push_back(this);
}

TextureCache::PerThread::~PerThread() {
    m_impl->unaccount(heapBytes());
    std::lock_guard lock(m_impl->threadsMutex);
    m_impl->retired.merge(stats());
    auto& v = m_impl->threads;
    v.erase(std::find(v.begin(), v.end(), this));
}

size_t TextureCache::PerThread::heapBytes() const {
    return sizeof(PerThread) + (size_t(1) << kMicroBits) * sizeof(MicroEntry) +
           m_scratch.capacity() * sizeof(float);
}

TextureCacheStats TextureCache::PerThread::stats() const {
    TextureCacheStats s;
    s.lookups = m_lookups.load(std::memory_order_relaxed);
    s.hits = m_hits.load(std::memory_order_relaxed);
    s.misses = m_misses.load(std::memory_order_relaxed);
    s.filteredLookups = m_filteredLookups.load(std::memory_order_relaxed);
    s.evictions = m_evictions.load(std::memory_order_relaxed);
    s.pagesRead = m_pagesRead.load(std::memory_order_relaxed);
    s.failedPages = m_failedPages.load(std::memory_order_relaxed);
    s.bytesRead = m_bytesRead.load(std::memory_order_relaxed);
    s.readSeconds = double(m_readNanos.load(std::memory_order_relaxed)) * 1e-9;
    return s;
}

// The shared path: find the page in its shard, wait for a thread that is loading it, or load it
// ourselves. Exactly one thread loads a given page: the first to miss inserts a Loading entry
// under the shard lock; later ones find it and wait on the shard's condition variable.
bool TextureCache::PerThread::refill(uint64_t key, TextureHandle handle, uint32_t level,
                                     uint32_t pageX, uint32_t pageY, MicroEntry& e,
                                     Outcome& outcome) {
    Impl& im = *m_impl;
    if (outcome != Outcome::Loaded) outcome = Outcome::SharedHit;
    Texture* t = im.texture(handle.id);
    if (!t || !t->source || t->broken.load(std::memory_order_acquire) || level >= t->pages.size() ||
        pageX >= t->pages[level].pagesX || pageY >= t->pages[level].pagesY) {
        if (outcome != Outcome::Loaded) outcome = Outcome::Rejected;
        return false;
    }
    auto fill = [&](uint32_t slot, uint64_t generation) {
        e.key = key;
        e.data = im.data + size_t(slot) * im.slotFloats;
        e.generation = &im.slots[slot].generation;
        e.generationValue = generation;
        e.stamp = &im.stamps[slot].stamp;
        e.channels = t->info.channels;
    };

    Shard& sh = im.shardFor(key);
    std::unique_lock lock(sh.mutex);
    for (;;) {
        const Entry* it = sh.map.find(key);
        if (!it) break;
        if (it->state == EntryState::Ready) {
            fill(it->slot, it->generation);
            lock.unlock();
            return true;
        }
        if (it->state == EntryState::Failed) {
            if (outcome != Outcome::Loaded) outcome = Outcome::Rejected;
            return false;
        }
        sh.loaded.wait(lock);
    }
    sh.map.insert(key);  // Loading
    lock.unlock();
    outcome = Outcome::Loaded;
    bump(m_lookups);
    bump(m_misses);

    bool evicted = false;
    const uint32_t slot = im.acquireSlot(evicted);
    if (evicted) bump(m_evictions);
    im.epoch.fetch_add(1, std::memory_order_relaxed);
    SlotMeta& meta = im.slots[slot];
    uint64_t bytes = 0;
    const auto start = std::chrono::steady_clock::now();
    try {
        const detail::PageFile file = im.acquireFile(*t);
        try {
            bytes = t->source->readPage(file, level, pageX, pageY, m_scratch.data());
        } catch (...) {
            im.releaseFile(*t);
            throw;
        }
        im.releaseFile(*t);
    } catch (const std::exception& ex) {
        im.releaseFailedSlot(slot);
        {
            std::lock_guard shardLock(sh.mutex);
            sh.map.find(key)->state = EntryState::Failed;
        }
        sh.loaded.notify_all();
        bump(m_failedPages);
        im.markBroken(*t, ex.what());
        return false;
    }
    bump(m_readNanos, uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now() - start)
                                   .count()));
    bump(m_pagesRead);
    bump(m_bytesRead, bytes);

    // Seqlock write: the generation went odd in acquireSlot (or was odd in a free slot); the
    // release fence orders that before the texel stores, and the even store publishes them.
    const uint64_t odd = meta.generation.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    float* dst = im.data + size_t(slot) * im.slotFloats;
    const size_t n = size_t(kPageTexels) * t->info.channels;
    for (size_t i = 0; i < n; ++i)
        std::atomic_ref<float>(dst[i]).store(m_scratch[i], std::memory_order_relaxed);
    im.stamps[slot].stamp.store(nextStamp(), std::memory_order_relaxed);
    const uint64_t even = odd + 1;
    meta.generation.store(even, std::memory_order_release);
    {
        std::lock_guard shardLock(sh.mutex);
        Entry& entry = *sh.map.find(key);
        entry.slot = slot;
        entry.generation = even;
        entry.state = EntryState::Ready;
    }
    sh.loaded.notify_all();
    // Only now may the slot be chosen as a victim: its map entry is Ready, so the evictor
    // will find and unmap it.
    im.publishSlot(slot, key);
    fill(slot, even);
    return true;
}

}  // namespace pushpin::texture
