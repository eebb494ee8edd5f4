// tests/texture/texture_cache_test.cpp: TextureCache — counters as oracles, LRU order, build on
// miss exactly once, concurrent lookups, broken textures, the descriptor pool.
#include "texture/texture_cache.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <list>
#include <sstream>
#include <thread>

#include "cache/memory_budget.h"
#include "texture/texture_sampler.h"
#include "texture_test_support.h"

namespace pushpin::texture {
namespace {

using testing::ProbeSource;
using testing::TempDir;
using testing::WarningLog;

float readOne(TextureCache::PerThread& pt, TextureHandle h, uint32_t level, uint32_t px,
              uint32_t py, bool* ok = nullptr) {
    const uint8_t off = 9;
    float v[kMaxChannels];  // one texel of as many channels as the texture has; channel 0 returned
    v[0] = -1.0f;
    const bool r = pt.readTexels(h, level, px, py, &off, 1, v);
    if (ok) *ok = r;
    return v[0];
}

void expectConsistent(const TextureCacheStats& s) {
    EXPECT_EQ(s.lookups, s.hits + s.misses) << s;
    EXPECT_EQ(s.misses, s.pagesRead + s.failedPages) << s;
}

TEST(TextureCache, SweepOverTextureThatFitsMissesEachPageOnce) {
    TextureCache cache;
    auto src = std::make_shared<ProbeSource>("probe", 64, 48);  // 8 × 6 pages at level 0
    const TextureHandle h = cache.registerSource(src);
    {
        TextureCache::PerThread pt(cache);
        for (int pass = 0; pass < 3; ++pass)
            for (uint32_t py = 0; py < 6; ++py)
                for (uint32_t px = 0; px < 8; ++px)
                    EXPECT_EQ(readOne(pt, h, 0, px, py), ProbeSource::pageValue(0, px, py));
        const TextureCacheStats s = pt.stats();
        EXPECT_EQ(s.lookups, 3u * 48u);
        EXPECT_EQ(s.misses, 48u);
        EXPECT_EQ(s.hits, 2u * 48u);
    }
    const TextureCacheStats s = cache.stats();
    EXPECT_EQ(s.misses, 48u);
    EXPECT_EQ(s.pagesRead, 48u);
    EXPECT_EQ(s.evictions, 0u);
    EXPECT_EQ(src->reads.load(), 48u);
    expectConsistent(s);
}

TEST(TextureCache, FilteredSweepMissesExactlyThePageCount) {
    // Point lookups at every texel centre of level 0: every page is touched, each loaded once.
    TextureCache cache;
    const auto src = testing::memoryTexture("ramp", 40, 24, 2, [](uint32_t x, uint32_t y, uint32_t c) {
        return float(x + 100 * y + 10000 * c);
    });
    const TextureHandle h = cache.registerSource(src);
    TextureCache::PerThread pt(cache);
    LookupOptions opt;
    opt.filter = FilterMode::Point;
    for (uint32_t y = 0; y < 24; ++y)
        for (uint32_t x = 0; x < 40; ++x) {
            float v[2];
            ASSERT_TRUE(sampleTexture(pt, h, opt, (x + 0.5f) / 40, (y + 0.5f) / 24, 0, 0, 0, 0,
                                      nullptr, 2, v));
            EXPECT_EQ(v[0], float(x + 100 * y));
            EXPECT_EQ(v[1], float(x + 100 * y + 10000));
        }
    const TextureCacheStats s = cache.stats();
    EXPECT_EQ(s.misses, 5u * 3u);
    EXPECT_EQ(s.lookups, 40u * 24u);
    EXPECT_EQ(s.filteredLookups, 40u * 24u);
    expectConsistent(s);
}

TEST(TextureCache, EvictionOrderMatchesLruModel) {
    TextureCacheOptions o;
    o.pageSlots = 4;
    TextureCache cache(o);
    auto src = std::make_shared<ProbeSource>("probe", 64, 64);
    const TextureHandle h = cache.registerSource(src);
    TextureCache::PerThread pt(cache);
    std::list<uint32_t> model;  // most recent first
    uint64_t modelEvictions = 0;
    std::mt19937 rng(7);
    for (int i = 0; i < 500; ++i) {
        const uint32_t page = std::uniform_int_distribution<uint32_t>(0, 6)(rng);
        auto it = std::find(model.begin(), model.end(), page);
        const bool expectHit = it != model.end();
        if (expectHit) {
            model.erase(it);
        } else if (model.size() == 4) {
            model.pop_back();
            ++modelEvictions;
        }
        model.push_front(page);
        const uint64_t missesBefore = pt.stats().misses;
        EXPECT_EQ(readOne(pt, h, 0, page, 0), ProbeSource::pageValue(0, page, 0));
        EXPECT_EQ(pt.stats().misses - missesBefore, expectHit ? 0u : 1u) << "access " << i;
    }
    EXPECT_EQ(cache.stats().evictions, modelEvictions);
    // The four most recent pages are resident: reading them again loads nothing.
    const uint64_t reads = src->reads.load();
    for (uint32_t page : model) readOne(pt, h, 0, page, 0);
    EXPECT_EQ(src->reads.load(), reads);
}

TEST(TextureCache, TwoThreadsMissingOnePageLoadItOnce) {
    TextureCache cache;
    auto src = std::make_shared<ProbeSource>("slow", 32, 32);
    src->delayMilliseconds = 50;
    const TextureHandle h = cache.registerSource(src);
    std::vector<std::thread> threads;
    std::atomic<int> wrong{0};
    for (int i = 0; i < 4; ++i)
        threads.emplace_back([&] {
            TextureCache::PerThread pt(cache);
            if (readOne(pt, h, 0, 2, 3) != ProbeSource::pageValue(0, 2, 3)) ++wrong;
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_EQ(src->reads.load(), 1u);
    const TextureCacheStats s = cache.stats();
    EXPECT_EQ(s.misses, 1u);
    EXPECT_EQ(s.hits, 3u);
    expectConsistent(s);
}

TEST(TextureCache, ThrashingTinyCacheNeverReturnsAnotherPagesTexels) {
    // Two slots and several threads reading many pages: slots are evicted while other threads
    // read them; the generation check must send those readers back to the map.
    TextureCacheOptions o;
    o.pageSlots = 2;
    TextureCache cache(o);
    auto src = std::make_shared<ProbeSource>("thrash", 64, 64);
    const TextureHandle h = cache.registerSource(src);
    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            TextureCache::PerThread pt(cache);
            std::mt19937 rng(t);
            for (int i = 0; i < 20000; ++i) {
                const uint32_t px = rng() % 8, py = rng() % 3;
                uint8_t off[4] = {0, 17, 42, 63};
                float v[4];
                if (!pt.readTexels(h, 0, px, py, off, 4, v)) {
                    ++wrong;
                    continue;
                }
                for (float x : v)
                    if (x != ProbeSource::pageValue(0, px, py)) ++wrong;
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(wrong.load(), 0);
    const TextureCacheStats s = cache.stats();
    EXPECT_GE(s.lookups, 80000u);  // a page reloaded within one request counts twice
    EXPECT_GT(s.evictions, 0u);
    expectConsistent(s);
}

// Ten BOT files of distinct content, written with the BOT writer.
std::vector<std::filesystem::path> writeTextures(const TempDir& dir, int count, uint32_t size) {
    std::vector<std::filesystem::path> paths;
    for (int i = 0; i < count; ++i) {
        const std::vector<float> img =
            testing::makeImage(size, size, 3, [i, size](uint32_t x, uint32_t y, uint32_t c) {
                return float((x * (3 + i) + y * (5 + c) + 31 * i) % size) / float(size);
            });
        BotWriteOptions wo;
        wo.threads = 1;
        paths.push_back(dir.path() / ("tex" + std::to_string(i) + ".bot"));
        writeBot(paths.back(), img.data(), size, size, 3, wo);
    }
    return paths;
}

struct RandomLookup {
    uint32_t texture;
    float s, t, dsdx, dsdy, dtdx, dtdy;
};

std::vector<RandomLookup> randomLookups(size_t n, uint32_t textures, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uv(-0.5f, 1.5f), logd(-9.0f, -2.0f);
    std::vector<RandomLookup> out(n);
    for (RandomLookup& l : out) {
        l.texture = rng() % textures;
        l.s = uv(rng);
        l.t = uv(rng);
        const float d = std::exp2(logd(rng));
        l.dsdx = d;
        l.dtdx = 0.3f * d;
        l.dsdy = -0.2f * d;
        l.dtdy = 1.5f * d;
    }
    return out;
}

void runLookups(TextureCache& cache, const std::vector<TextureHandle>& handles,
                const std::vector<RandomLookup>& lookups, size_t first, size_t stride,
                std::vector<float>& out) {
    TextureCache::PerThread pt(cache);
    LookupOptions opt;
    opt.maxAnisotropy = 4;
    for (size_t i = first; i < lookups.size(); i += stride) {
        const RandomLookup& l = lookups[i];
        sampleTexture(pt, handles[l.texture], opt, l.s, l.t, l.dsdx, l.dsdy, l.dtdx, l.dtdy,
                      nullptr, 3, &out[3 * i]);
    }
}

TEST(TextureCache, ConcurrentLookupsReturnWhatOneThreadReturns) {
    TempDir dir("tc-conc");
    const auto paths = writeTextures(dir, 10, 128);
    const auto lookups = randomLookups(30000, 10, 11);
    std::vector<float> single(lookups.size() * 3), parallel(lookups.size() * 3, -1.0f);
    TextureCacheStats singleStats;
    {
        TextureCache cache;  // 256 slots
        std::vector<TextureHandle> handles;
        for (const auto& p : paths) handles.push_back(cache.registerFile(p));
        runLookups(cache, handles, lookups, 0, 1, single);
        singleStats = cache.stats();
    }
    for (int threadCount : {2, 4}) {
        TextureCache cache;
        std::vector<TextureHandle> handles;
        for (const auto& p : paths) handles.push_back(cache.registerFile(p));
        std::vector<std::thread> threads;
        for (int t = 0; t < threadCount; ++t)
            threads.emplace_back([&, t] { runLookups(cache, handles, lookups, t, threadCount, parallel); });
        for (auto& t : threads) t.join();
        for (size_t i = 0; i < single.size(); ++i)
            ASSERT_EQ(single[i], parallel[i]) << "value " << i << " with " << threadCount << " threads";
        const TextureCacheStats s = cache.stats();
        expectConsistent(s);
        EXPECT_EQ(s.filteredLookups, lookups.size());
        EXPECT_EQ(s.failedPages, 0u);
        EXPECT_GT(s.evictions, 0u);  // 10 textures do not fit in 256 pages
        EXPECT_GT(s.bytesRead, 0u);
        EXPECT_EQ(s.evictions, s.pagesRead - std::min<uint64_t>(s.pagesRead, 256));
    }
    expectConsistent(singleStats);
    EXPECT_EQ(singleStats.filteredLookups, lookups.size());
}

TEST(TextureCache, CorruptPageMarksTextureBrokenOnceAndCountsTheMiss) {
    WarningLog log;
    TextureCacheOptions o;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    auto src = std::make_shared<ProbeSource>("corrupt.bot", 64, 64);
    src->failLevel = 0;
    src->failPageX = 1;
    src->failPageY = 1;
    const TextureHandle h = cache.registerSource(src);
    TextureCache::PerThread pt(cache);
    bool ok = false;
    EXPECT_EQ(readOne(pt, h, 0, 0, 0, &ok), ProbeSource::pageValue(0, 0, 0));
    EXPECT_TRUE(ok);
    EXPECT_FALSE(cache.broken(h));

    LookupOptions opt;
    opt.filter = FilterMode::Point;
    const float fill[2] = {0.25f, 0.75f};
    float v[2];
    EXPECT_FALSE(sampleTexture(pt, h, opt, 12.5f / 64, 12.5f / 64, 0, 0, 0, 0, fill, 2, v));
    EXPECT_EQ(v[0], 0.25f);
    EXPECT_EQ(v[1], 0.75f);
    EXPECT_TRUE(cache.broken(h));
    // From now on every lookup gets the default colour, pages that loaded before included.
    EXPECT_FALSE(sampleTexture(pt, h, opt, 0.5f / 64, 0.5f / 64, 0, 0, 0, 0, fill, 2, v));
    EXPECT_EQ(v[0], 0.25f);
    EXPECT_FALSE(sampleTexture(pt, h, opt, 12.5f / 64, 12.5f / 64, 0, 0, 0, 0, fill, 2, v));
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find("corrupt.bot"), std::string::npos) << log.messages[0];
    EXPECT_NE(log.messages[0].find("checksum mismatch"), std::string::npos) << log.messages[0];
    const TextureCacheStats s = cache.stats();
    EXPECT_EQ(s.failedPages, 1u);
    EXPECT_EQ(s.misses, 2u);
    EXPECT_EQ(s.brokenTextures, 1u);
    EXPECT_EQ(src->reads.load(), 2u);
    expectConsistent(s);
}

TEST(TextureCache, CorruptBotFileIsBrokenMidRender) {
    TempDir dir("tc-corrupt");
    const auto paths = writeTextures(dir, 1, 64);
    // Damage the stored bytes of the last page of level 0.
    const auto bot = BotFile::open(paths[0]);
    const BotPageEntry entry = bot->pageEntry(bot->pageIndex(0, 7, 7));
    {
        const int fd = ::open(paths[0].c_str(), O_RDWR);
        ASSERT_GE(fd, 0);
        std::vector<uint8_t> junk(entry.storedBytes, 0xA5);
        ASSERT_EQ(::pwrite(fd, junk.data(), junk.size(), off_t(entry.offsetBytes)), ssize_t(junk.size()));
        ::close(fd);
    }
    WarningLog log;
    TextureCacheOptions o;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    const TextureHandle h = cache.registerFile(paths[0]);
    ASSERT_FALSE(cache.broken(h));
    TextureCache::PerThread pt(cache);
    LookupOptions opt;
    opt.filter = FilterMode::Bilinear;
    const float fill[3] = {1, 0, 1};
    float v[3];
    EXPECT_TRUE(sampleTexture(pt, h, opt, 0.1f, 0.1f, 0, 0, 0, 0, fill, 3, v));
    EXPECT_FALSE(sampleTexture(pt, h, opt, 0.95f, 0.95f, 0, 0, 0, 0, fill, 3, v));
    EXPECT_EQ(v[0], 1.0f);
    EXPECT_EQ(v[1], 0.0f);
    EXPECT_EQ(v[2], 1.0f);
    EXPECT_TRUE(cache.broken(h));
    EXPECT_FALSE(sampleTexture(pt, h, opt, 0.1f, 0.1f, 0, 0, 0, 0, fill, 3, v));
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find(paths[0].filename().string()), std::string::npos) << log.messages[0];
    EXPECT_EQ(cache.stats().failedPages, 1u);
}

TEST(TextureCache, MissingFileWarnsOnceWithThePathAndGivesDefaultColour) {
    WarningLog log;
    TextureCacheOptions o;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    const TextureHandle h = cache.registerFile("/nonexistent/dir/wood.bot");
    ASSERT_TRUE(h.valid());
    EXPECT_TRUE(cache.broken(h));
    EXPECT_EQ(cache.info(h), nullptr);
    EXPECT_EQ(cache.registerFile("/nonexistent/dir/../dir/wood.bot"), h);
    TextureCache::PerThread pt(cache);
    const float fill[3] = {0.5f, 0.5f, 0.5f};
    float v[3];
    EXPECT_FALSE(sampleTexture(pt, h, LookupOptions{}, 0.3f, 0.3f, 0.01f, 0, 0, 0.01f, fill, 3, v));
    EXPECT_EQ(v[0], 0.5f);
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find("/nonexistent/dir/wood.bot"), std::string::npos);
    EXPECT_EQ(cache.stats().lookups, 0u);
}

TEST(TextureCache, MoreTexturesThanTheOpenFileLimit) {
    TempDir dir("tc-fds");
    const auto paths = writeTextures(dir, 12, 32);
    const auto lookups = randomLookups(4000, 12, 5);
    std::vector<float> reference(lookups.size() * 3), limited(lookups.size() * 3);
    {
        TextureCache cache;
        std::vector<TextureHandle> handles;
        for (const auto& p : paths) handles.push_back(cache.registerFile(p));
        runLookups(cache, handles, lookups, 0, 1, reference);
        EXPECT_EQ(cache.stats().fileCloses, 0u);
        EXPECT_EQ(cache.openFileCount(), 12u);
    }
    TextureCacheOptions o;
    o.maxOpenFiles = 3;
    o.pageSlots = 16;  // small, so pages of every file keep being re-read
    TextureCache cache(o);
    std::vector<TextureHandle> handles;
    for (const auto& p : paths) handles.push_back(cache.registerFile(p));
    std::vector<std::thread> threads;
    for (int t = 0; t < 2; ++t)
        threads.emplace_back([&, t] { runLookups(cache, handles, lookups, t, 2, limited); });
    for (auto& t : threads) t.join();
    EXPECT_EQ(reference, limited);
    const TextureCacheStats s = cache.stats();
    EXPECT_LE(cache.openFileCount(), 3u);
    EXPECT_LE(s.peakOpenFiles, 3u);
    EXPECT_GT(s.fileOpens, 12u);
    EXPECT_EQ(s.fileOpens - s.fileCloses, cache.openFileCount());
    expectConsistent(s);
}

TEST(TextureCache, StatsMergeAddsCountersAndKeepsPeak) {
    TextureCacheStats a, b;
    a.lookups = 10;
    a.hits = 7;
    a.peakOpenFiles = 4;
    a.readSeconds = 0.5;
    b.lookups = 5;
    b.hits = 1;
    b.peakOpenFiles = 2;
    b.readSeconds = 0.25;
    a.merge(b);
    EXPECT_EQ(a.lookups, 15u);
    EXPECT_EQ(a.hits, 8u);
    EXPECT_EQ(a.peakOpenFiles, 4u);
    EXPECT_DOUBLE_EQ(a.readSeconds, 0.75);
    std::ostringstream os;
    os << a;
    EXPECT_NE(os.str().find("lookups 15"), std::string::npos);
}

TEST(TextureCache, RejectsBadOptionsAndTexturesWiderThanItsSlots) {
    TextureCacheOptions o;
    o.pageSlots = 0;
    EXPECT_THROW(TextureCache{o}, std::invalid_argument);
    o.pageSlots = 8;
    o.maxOpenFiles = 0;
    EXPECT_THROW(TextureCache{o}, std::invalid_argument);
    o.maxOpenFiles = 4;
    o.maxChannels = 2;
    WarningLog log;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    const TextureHandle h = cache.registerSource(
        testing::memoryTexture("rgb", 8, 8, 3, [](uint32_t, uint32_t, uint32_t) { return 1.0f; }));
    EXPECT_TRUE(cache.broken(h));
    EXPECT_EQ(log.count(), 1u);
    EXPECT_EQ(cache.slotMemoryBytes(), 8u * 64u * 2u * sizeof(float));
    EXPECT_GT(cache.memoryBytes(), cache.slotMemoryBytes());
}

TEST(TextureCache, ChargedBytesEqualMemoryBytesAtAllTimes) {
    TempDir dir("tc-budget");
    const auto paths = writeTextures(dir, 3, 128);
    const auto lookups = randomLookups(3000, 3, 21);
    cache::MemoryBudget budget;
    budget.charge(cache::MemoryCategory::Tessellation, 12345);  // someone else's memory
    auto charged = [&] { return budget.usedBytes(cache::MemoryCategory::Textures); };
    {
        TextureCacheOptions o;
        o.pageSlots = 32;  // small, so the lookups below evict
        o.memoryBudget = &budget;
        TextureCache cache(o);
        EXPECT_EQ(charged(), cache.memoryBytes());
        EXPECT_GE(cache.memoryBytes(), cache.slotMemoryBytes());
        size_t before = cache.memoryBytes();
        std::vector<TextureHandle> handles;
        for (const auto& p : paths) {
            handles.push_back(cache.registerFile(p));
            // Each texture adds at least its page table (one entry per page).
            EXPECT_GE(cache.memoryBytes(), before + BotFile::open(p)->pageCount() * sizeof(BotPageEntry));
            EXPECT_EQ(charged(), cache.memoryBytes());
            before = cache.memoryBytes();
        }
        EXPECT_EQ(cache.registerFile(paths[0]), handles[0]);  // already registered: no new charge
        EXPECT_EQ(charged(), before);
        cache.registerSource(std::make_shared<ProbeSource>("probe", 16, 16));
        EXPECT_GE(cache.memoryBytes(), before + ProbeSource::kMemoryBytes);
        EXPECT_EQ(charged(), cache.memoryBytes());
        const size_t registered = cache.memoryBytes();
        {
            TextureCache::PerThread a(cache), b(cache);
            EXPECT_GT(cache.memoryBytes(), registered + 2 * 48 * 1024);
            EXPECT_EQ(charged(), cache.memoryBytes());
            std::vector<float> out(lookups.size() * 3);
            LookupOptions opt;
            const float fill[3] = {0, 0, 0};
            for (size_t i = 0; i < lookups.size(); ++i) {
                const RandomLookup& l = lookups[i];
                sampleTexture(i % 2 ? a : b, handles[l.texture], opt, l.s, l.t, l.dsdx, l.dsdy,
                              l.dtdx, l.dtdy, fill, 3, &out[i * 3]);
                if (i % 500 == 0) {
                    EXPECT_EQ(charged(), cache.memoryBytes());
                }
            }
            EXPECT_GT(cache.stats().evictions, 0u);
            EXPECT_EQ(charged(), cache.memoryBytes());  // eviction reuses slots: no change
        }
        EXPECT_EQ(cache.memoryBytes(), registered);
        EXPECT_EQ(charged(), registered);
        EXPECT_GT(budget.peakBytes(cache::MemoryCategory::Textures), registered);
    }
    EXPECT_EQ(charged(), 0u);
    EXPECT_EQ(budget.usedBytes(), 12345u);
}

TEST(TextureCache, CacheWithoutBudgetStillReportsItsMemory) {
    TextureCacheOptions o;
    o.pageSlots = 4;
    TextureCache cache(o);
    const size_t empty = cache.memoryBytes();
    EXPECT_GE(empty, cache.slotMemoryBytes());
    cache.registerSource(std::make_shared<ProbeSource>("probe", 16, 16));
    EXPECT_GE(cache.memoryBytes(), empty + ProbeSource::kMemoryBytes);
}

TEST(TextureCache, MappedAndPreadReadsGiveTheSameTexelsAndCounts) {
    TempDir dir("tc-map");
    const auto paths = writeTextures(dir, 4, 96);
    const auto lookups = randomLookups(6000, 4, 8);
    std::vector<float> out[2];
    TextureCacheStats stats[2];
    for (int mapped = 0; mapped < 2; ++mapped) {
        TextureCacheOptions o;
        o.pageSlots = 24;
        o.maxOpenFiles = 2;  // files keep being closed and reopened (unmapped and mapped again)
        o.mapFiles = mapped == 1;
        TextureCache cache(o);
        std::vector<TextureHandle> handles;
        for (const auto& p : paths) handles.push_back(cache.registerFile(p));
        out[mapped].assign(lookups.size() * 3, -1.0f);
        runLookups(cache, handles, lookups, 0, 1, out[mapped]);
        stats[mapped] = cache.stats();
        EXPECT_LE(cache.openFileCount(), 2u);
    }
    EXPECT_EQ(out[0], out[1]);
    EXPECT_EQ(stats[0].lookups, stats[1].lookups);
    EXPECT_EQ(stats[0].misses, stats[1].misses);
    EXPECT_EQ(stats[0].bytesRead, stats[1].bytesRead);
    EXPECT_EQ(stats[0].fileOpens, stats[1].fileOpens);
    EXPECT_EQ(stats[0].fileCloses, stats[1].fileCloses);
    EXPECT_GT(stats[1].fileCloses, 0u);
    expectConsistent(stats[1]);
}

// Truncates `path` to `bytes` in place (as `cp other path` or a crashed writer would).
void truncateInPlace(const std::filesystem::path& path, off_t bytes) {
    const int fd = ::open(path.c_str(), O_WRONLY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::ftruncate(fd, bytes), 0);
    ::close(fd);
}

TEST(TextureCache, FileTruncatedAfterRegistrationIsBrokenWithAClearError) {
    for (bool mapped : {false, true}) {
        TempDir dir("tc-trunc");
        const auto paths = writeTextures(dir, 1, 64);
        WarningLog log;
        TextureCacheOptions o;
        o.mapFiles = mapped;
        o.warningHandler = log.handler();
        TextureCache cache(o);
        const TextureHandle h = cache.registerFile(paths[0]);
        ASSERT_FALSE(cache.broken(h));
        truncateInPlace(paths[0], off_t(std::filesystem::file_size(paths[0]) - 10));
        TextureCache::PerThread pt(cache);
        bool ok = true;
        readOne(pt, h, 0, 0, 0, &ok);
        EXPECT_FALSE(ok);
        EXPECT_TRUE(cache.broken(h));
        ASSERT_EQ(log.count(), 1u);
        EXPECT_NE(log.messages[0].find(paths[0].string()), std::string::npos) << log.messages[0];
        EXPECT_NE(log.messages[0].find("shorter"), std::string::npos) << log.messages[0];
        EXPECT_EQ(cache.stats().failedPages, 1u);
        EXPECT_EQ(cache.stats().fileOpens, 0u);
    }
}

TEST(TextureCache, FileTruncatedWhileMappedBreaksTheTextureNotTheProcess) {
    TempDir dir("tc-shrink");
    const auto paths = writeTextures(dir, 1, 1024);  // several hundred KiB, many OS pages
    const auto bot = BotFile::open(paths[0]);
    const BotLevel& l0 = bot->header().levels[0];
    const BotPageEntry last = bot->pageEntry(bot->pageIndex(0, l0.pagesX - 1, l0.pagesY - 1));
    ASSERT_GT(last.offsetBytes, 3u * 65536u);
    WarningLog log;
    TextureCacheOptions o;
    o.warningHandler = log.handler();
    TextureCache cache(o);
    const TextureHandle h = cache.registerFile(paths[0]);
    TextureCache::PerThread pt(cache);
    bool ok = false;
    readOne(pt, h, 0, 0, 0, &ok);  // maps the file
    ASSERT_TRUE(ok);
    ASSERT_EQ(cache.openFileCount(), 1u);
    // Far below the last page, so reading it touches whole OS pages past the new end.
    truncateInPlace(paths[0], off_t(65536));
    readOne(pt, h, 0, l0.pagesX - 1, l0.pagesY - 1, &ok);
    EXPECT_FALSE(ok);
    EXPECT_TRUE(cache.broken(h));
    ASSERT_EQ(log.count(), 1u);
    EXPECT_NE(log.messages[0].find(paths[0].string()), std::string::npos) << log.messages[0];
    EXPECT_NE(log.messages[0].find("level 0 page (" + std::to_string(l0.pagesX - 1) + ", " +
                                   std::to_string(l0.pagesY - 1) + ")"),
              std::string::npos)
        << log.messages[0];
    EXPECT_NE(log.messages[0].find("while mapped"), std::string::npos) << log.messages[0];
    EXPECT_EQ(cache.stats().failedPages, 1u);
    // The thread goes on working: other textures still load.
    const TextureHandle probe = cache.registerSource(std::make_shared<ProbeSource>("probe", 16, 16));
    EXPECT_EQ(readOne(pt, probe, 0, 1, 1, &ok), ProbeSource::pageValue(0, 1, 1));
    EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace pushpin::texture
