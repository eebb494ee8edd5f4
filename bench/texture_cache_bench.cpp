// bench/texture_cache_bench.cpp: pushpin's TextureCache against OpenImageIO's TextureSystem in
// one run, on the same texture content and the same lookup streams.
//
//   texture_cache_bench [--quick] [--runs N] [--dir D] [--stream render|random|both] [--systems ours|oiio|both] [--micro-only] [--benchmark_* flags]
//
// Streams: (a) render order — a 1920×1080 perspective view of a textured ground plane, swept in
// 32×32 screen tiles (tiles handed out to threads in order), one trilinear lookup per pixel with
// analytic uv derivatives; (b) random — uniformly random (s, t) with a one-texel footprint.
// Caches: OIIO at max_memory_MB = 1 (its smallest), ours with the pages that fit in 1 MiB, and
// ours at the default 256 pages; ours reads the version-3 file, and in one row the version-2 file of
// the same texture. Each configuration is run several times from a cold cache;
// the table gives min / median / max. After the table, Google Benchmark times the hit paths.
#include "bench/bench_support.h"
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "texture/bot_file.h"
#include "texture/texture_cache.h"
#include "texture/texture_sampler.h"

namespace {

using namespace pushpin::texture;
namespace fs = std::filesystem;

struct Config {
    bool quick = false;
    bool tableRuns = true;  // false: only the hit-path micro-benchmarks
    std::string streams = "both";  // render, random or both
    std::string systems = "both";  // ours, oiio or both
    int runs = 5;
    int randomRuns = 3;
    uint32_t textureSize = 4096;
    uint32_t imageWidth = 1920, imageHeight = 1080;
    size_t randomLookups = 60000;
    fs::path dir;
};

// Procedural RGB content with detail at every scale (so pages compress like a real texture).
float contentAt(uint32_t x, uint32_t y, uint32_t c, uint32_t size) {
    const float fx = float(x) / float(size), fy = float(y) / float(size);
    uint32_t h = x * 0x9E3779B1u ^ y * 0x85EBCA77u ^ c * 0xC2B2AE3Du;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    const float noise = float(h & 0xff) / 255.0f;
    const float wave = 0.5f + 0.25f * std::sin(40.0f * fx + 7.0f * float(c)) * std::cos(33.0f * fy);
    const float bricks = ((x / 64 + y / 32) % 2) ? 0.15f : 0.0f;
    return std::clamp(wave + bricks + 0.15f * (noise - 0.5f), 0.0f, 1.0f);
}

struct Textures {
    fs::path bot, tx;
    fs::path bot2;  // the same texture as a version-2 file, for its page read time and one table row
};

// Whether a BOT file written by an earlier run still reads with this build: its tables and every
// page of its largest level (a file of an older layout of the same version number does not).
bool botReadsBack(const fs::path& path) {
    try {
        const std::shared_ptr<const BotFile> bot = BotFile::open(path);
        const int fd = ::open(path.c_str(), O_RDONLY);
        if (fd < 0) return false;
        std::vector<float> page(size_t(kPageSizeTexels) * kPageSizeTexels * bot->header().channels);
        const uint32_t pagesX = (bot->header().width + kPageSizeTexels - 1) / kPageSizeTexels;
        const uint32_t pagesY = (bot->header().height + kPageSizeTexels - 1) / kPageSizeTexels;
        bool ok = true;
        try {
            for (uint32_t py = 0; py < pagesY; ++py)
                for (uint32_t px = 0; px < pagesX; ++px) bot->readPage(fd, 0, px, py, page.data());
        } catch (const std::exception&) {
            ok = false;
        }
        ::close(fd);
        return ok;
    } catch (const std::exception&) {
        return false;
    }
}

Textures makeTextures(const Config& cfg) {
    fs::create_directories(cfg.dir);
    const uint32_t n = cfg.textureSize;
    Textures t{cfg.dir / ("bench_" + std::to_string(n) + "_v3.bot"), cfg.dir / ("bench_" + std::to_string(n) + ".tx"),
               cfg.dir / ("bench_" + std::to_string(n) + "_v2.bot")};
    if (fs::exists(t.tx) && botReadsBack(t.bot) && botReadsBack(t.bot2)) return t;
    std::fprintf(stderr, "writing %u×%u RGB test textures to %s ...\n", n, n, cfg.dir.c_str());
    std::vector<float> px(size_t(n) * n * 3);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (uint32_t c = 0; c < 3; ++c) px[(size_t(y) * n + x) * 3 + c] = contentAt(x, y, c, n);
    BotWriteOptions wo;
    wo.pixelType = PixelType::U8;
    wo.alphaChannel = -1;
    wo.version = 3;
    writeBot(t.bot, px.data(), n, n, 3, wo);
    wo.version = 2;
    writeBot(t.bot2, px.data(), n, n, 3, wo);
    OIIO::ImageSpec spec(static_cast<int>(n), static_cast<int>(n), 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf src(spec, px.data());
    OIIO::ImageSpec config;
    config.format = OIIO::TypeDesc::UINT8;
    config.tile_width = config.tile_height = 64;
    config.attribute("maketx:filtername", "box");
    config.attribute("wrapmodes", "periodic,periodic");
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src, t.tx.string(), config)) {
        std::fprintf(stderr, "make_texture failed: %s\n", OIIO::geterror().c_str());
        std::exit(1);
    }
    return t;
}

// A stream is a list of tiles; each tile is a struct-of-arrays batch.
struct Tile {
    std::vector<float> s, t, dsdx, dsdy, dtdx, dtdy;
    LookupBatch batch() const {
        LookupBatch b;
        b.count = s.size();
        b.s = s.data();
        b.t = t.data();
        b.dsdx = dsdx.data();
        b.dsdy = dsdy.data();
        b.dtdx = dtdx.data();
        b.dtdy = dtdy.data();
        return b;
    }
};
using Stream = std::vector<Tile>;

// A camera 1 unit above the plane z = 0, pitched 35° down, 60° horizontal field of view; the
// plane's texture repeats every S units, with S chosen so the bottom centre of the image sees one
// level-0 texel per pixel. Derivatives follow from P = C + t·D with t = −h / D.z.
Stream renderOrderStream(const Config& cfg) {
    const double W = cfg.imageWidth, H = cfg.imageHeight, h = 1.0, pitch = 35.0 * M_PI / 180.0;
    const double f = (W / 2) / std::tan(30.0 * M_PI / 180.0);
    const double F[3] = {0, std::cos(pitch), -std::sin(pitch)}, U[3] = {0, std::sin(pitch), std::cos(pitch)};
    struct Hit {
        double px, py, dpxdx, dpydx, dpxdy, dpydy;
    };
    auto hit = [&](double x, double y) {
        const double a = (x - W / 2) / f, b = (H / 2 - y) / f;
        const double D[3] = {a + F[0], F[1] + b * U[1], F[2] + b * U[2]};
        const double dDdx[3] = {1 / f, 0, 0}, dDdy[3] = {0, -U[1] / f, -U[2] / f};
        const double t = -h / D[2];
        const double dtdx = h / (D[2] * D[2]) * dDdx[2], dtdy = h / (D[2] * D[2]) * dDdy[2];
        Hit r;
        r.px = t * D[0];
        r.py = t * D[1];
        r.dpxdx = t * dDdx[0] + D[0] * dtdx;
        r.dpydx = t * dDdx[1] + D[1] * dtdx;
        r.dpxdy = t * dDdy[0] + D[0] * dtdy;
        r.dpydy = t * dDdy[1] + D[1] * dtdy;
        return r;
    };
    const Hit bottom = hit(W / 2, H - 0.5);
    const double S = std::abs(bottom.dpxdx) * 4096.0;  // 4096 texels per repeat at full scale
    Stream stream;
    for (uint32_t ty = 0; ty < cfg.imageHeight; ty += 32)
        for (uint32_t tx = 0; tx < cfg.imageWidth; tx += 32) {
            Tile tile;
            for (uint32_t y = ty; y < std::min(ty + 32, cfg.imageHeight); ++y)
                for (uint32_t x = tx; x < std::min(tx + 32, cfg.imageWidth); ++x) {
                    const Hit p = hit(x + 0.5, y + 0.5);
                    tile.s.push_back(float(p.px / S + 0.5));
                    tile.t.push_back(float(p.py / S));
                    tile.dsdx.push_back(float(p.dpxdx / S));
                    tile.dtdx.push_back(float(p.dpydx / S));
                    tile.dsdy.push_back(float(p.dpxdy / S));
                    tile.dtdy.push_back(float(p.dpydy / S));
                }
            stream.push_back(std::move(tile));
        }
    return stream;
}

Stream randomStream(const Config& cfg) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> uv(0.0f, 1.0f);
    const float d = 1.0f / float(cfg.textureSize);
    Stream stream;
    for (size_t i = 0; i < cfg.randomLookups; i += 256) {
        Tile tile;
        for (size_t j = i; j < std::min(i + 256, cfg.randomLookups); ++j) {
            tile.s.push_back(uv(rng));
            tile.t.push_back(uv(rng));
            tile.dsdx.push_back(d);
            tile.dtdx.push_back(0);
            tile.dsdy.push_back(0);
            tile.dtdy.push_back(d);
        }
        stream.push_back(std::move(tile));
    }
    return stream;
}

size_t lookupCount(const Stream& s) {
    size_t n = 0;
    for (const Tile& t : s) n += t.s.size();
    return n;
}

struct RunResult {
    double lookupsPerSecond = 0;     // lookups / wall seconds
    double lookupsPerCpuSecond = 0;  // lookups / CPU seconds summed over the worker threads
    double hitRatio = 0;
    double loadsPer1000 = 0;  // pages (ours) or tiles (OIIO) read per thousand lookups
};

using pushpin::bench::threadCpuSeconds;

struct Timing {
    double wallSeconds = 0, cpuSeconds = 0;
};

// Hands tiles to `threads` workers in stream order; returns wall and summed thread CPU seconds
// (the machine may be shared, so CPU time is the steadier figure).
Timing runTiles(const Stream& stream, int threads, const std::function<void(int, const Tile&)>& work,
                const std::function<void(int)>& begin, const std::function<void(int)>& end) {
    std::atomic<size_t> next{0};
    std::atomic<int> ready{0};
    std::atomic<bool> go{false};
    std::vector<std::thread> pool;
    std::vector<double> cpu(threads, 0.0);
    std::chrono::steady_clock::time_point start;
    for (int i = 0; i < threads; ++i)
        pool.emplace_back([&, i] {
            begin(i);
            ready.fetch_add(1);
            while (!go.load()) std::this_thread::yield();
            const double c0 = threadCpuSeconds();
            for (size_t k; (k = next.fetch_add(1)) < stream.size();) work(i, stream[k]);
            cpu[i] = threadCpuSeconds() - c0;
            end(i);
        });
    while (ready.load() < threads) std::this_thread::yield();
    start = std::chrono::steady_clock::now();
    go.store(true);
    for (auto& t : pool) t.join();
    Timing timing;
    timing.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (double c : cpu) timing.cpuSeconds += c;
    return timing;
}

RunResult rates(const Stream& stream, const Timing& t, double hitRatio, double loads) {
    const double n = double(lookupCount(stream));
    return {n / t.wallSeconds, n / t.cpuSeconds, hitRatio, 1000.0 * loads / n};
}

RunResult runOurs(const fs::path& bot, const Stream& stream, int threads, uint32_t pages,
                  bool mapFiles = true) {
    TextureCacheOptions o;
    o.pageSlots = pages;
    o.maxChannels = 3;
    o.mapFiles = mapFiles;
    TextureCache cache(o);
    const TextureHandle h = cache.registerFile(bot);
    std::vector<std::unique_ptr<TextureCache::PerThread>> per(threads);
    std::vector<std::vector<float>> out(threads * 3, std::vector<float>(1024));
    LookupOptions opt;  // trilinear
    const Timing timing = runTiles(
        stream, threads,
        [&](int i, const Tile& tile) {
            const LookupBatch b = tile.batch();
            float* outs[3] = {out[i * 3].data(), out[i * 3 + 1].data(), out[i * 3 + 2].data()};
            sampleTexture(*per[i], h, opt, b, nullptr, 3, outs);
            benchmark::DoNotOptimize(outs[0][0]);
        },
        [&](int i) { per[i] = std::make_unique<TextureCache::PerThread>(cache); },
        [&](int i) { per[i].reset(); });
    const TextureCacheStats s = cache.stats();
    if (cache.broken(h)) {
        std::fprintf(stderr, "texture %s is broken\n", bot.c_str());
        std::exit(1);
    }
    return rates(stream, timing, s.hitRatio(), double(s.pagesRead));
}

RunResult runOiio(const fs::path& tx, const Stream& stream, int threads, float memoryMB) {
    OIIO::TextureSystem* ts = OIIO::TextureSystem::create(false);
    ts->attribute("max_memory_MB", memoryMB);
    ts->attribute("max_open_files", 100);
    OIIO::TextureSystem::TextureHandle* handle = ts->get_texture_handle(OIIO::ustring(tx.string()));
    std::vector<OIIO::TextureSystem::Perthread*> per(threads, nullptr);
    OIIO::TextureOpt opt;
    opt.mipmode = OIIO::TextureOpt::MipModeTrilinear;
    opt.interpmode = OIIO::TextureOpt::InterpBilinear;
    opt.swrap = opt.twrap = OIIO::TextureOpt::WrapPeriodic;
    const Timing timing = runTiles(
        stream, threads,
        [&](int i, const Tile& tile) {
            OIIO::TextureOpt o = opt;
            float rgb[3];
            for (size_t k = 0; k < tile.s.size(); ++k) {
                ts->texture(handle, per[i], o, tile.s[k], tile.t[k], tile.dsdx[k], tile.dtdx[k],
                            tile.dsdy[k], tile.dtdy[k], 3, rgb);
                benchmark::DoNotOptimize(rgb[0]);
            }
        },
        [&](int i) { per[i] = ts->create_thread_info(); }, [](int) {});
    // Statistics first: OIIO 2.4 merges per-thread statistics of thread infos it still lists.
    // Tile requests (int64) and tiles read into the cache (int): the cache-miss ratio.
    long long calls = 0;
    int created = 0;
    if (!ts->getattribute("stat:find_tile_calls", OIIO::TypeDesc::INT64, &calls) ||
        !ts->getattribute("stat:tiles_created", OIIO::TypeInt, &created))
        std::fprintf(stderr, "OIIO did not report its tile statistics\n");
    for (OIIO::TextureSystem::Perthread* p : per) ts->destroy_thread_info(p);
    OIIO::TextureSystem::destroy(ts);
    return rates(stream, timing, calls ? 1.0 - double(created) / double(calls) : 0.0, double(created));
}

struct Summary {
    double min, median, max;
};
Summary summarize(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return {v.front(), v[v.size() / 2], v.back()};
}

void runTable(const Config& cfg, const Textures& tex) {
    const uint32_t pagesIn1MB = uint32_t((1u << 20) / (64 * 3 * sizeof(float)));
    struct Row {
        const char* stream;
        const Stream* data;
        int runs;
    };
    const Stream render = renderOrderStream(cfg);
    const Stream random = randomStream(cfg);
    std::printf("\ntexture %u×%u RGB u8; render-order stream %zu lookups (%u×%u, 32×32 tiles); "
                "random stream %zu lookups\n",
                cfg.textureSize, cfg.textureSize, lookupCount(render), cfg.imageWidth,
                cfg.imageHeight, lookupCount(random));
    std::printf("our cache: %u pages = 1 MiB at 768 B/page (RGB float), or 256 pages = 192 KiB\n\n",
                pagesIn1MB);
    std::printf("| stream | threads | cache | memory | M lookups/s wall (min / median / max) | M lookups per CPU-s (min / median / max) | hit ratio %% (min / median / max) | reads per 1000 lookups (median) |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const Row& row : {Row{"render order", &render, cfg.runs}, Row{"random", &random, cfg.randomRuns}})
        for (int threads : {1, 2}) {
            if (cfg.streams != "both" && (cfg.streams == "render") != (row.data == &render)) continue;
            struct Sys {
                const char* name;
                const char* memory;
                std::function<RunResult()> run;
            };
            const Sys systems[] = {
                {"OIIO TextureSystem", "1 MB", [&] { return runOiio(tex.tx, *row.data, threads, 1.0f); }},
                {"pushpin TextureCache", "1 MiB",
                 [&] { return runOurs(tex.bot, *row.data, threads, pagesIn1MB); }},
                {"pushpin TextureCache, pread", "1 MiB",
                 [&] { return runOurs(tex.bot, *row.data, threads, pagesIn1MB, false); }},
                {"pushpin TextureCache", "256 pages", [&] { return runOurs(tex.bot, *row.data, threads, 256); }},
                {"pushpin TextureCache, version 2 file", "1 MiB",
                 [&] { return runOurs(tex.bot2, *row.data, threads, pagesIn1MB); }},
            };
            // Runs are interleaved across systems (OIIO, ours, …, OIIO, ours, …), so a change in
            // the machine's load during the table affects every system alike.
            struct Results {
                std::vector<double> rate, cpuRate, hit, loads;
            };
            std::vector<const Sys*> chosen;
            for (const Sys& sys : systems) {
                const bool isOiio = std::strncmp(sys.name, "OIIO", 4) == 0;
                if ((cfg.systems == "ours" && isOiio) || (cfg.systems == "oiio" && !isOiio)) continue;
                chosen.push_back(&sys);
            }
            std::vector<Results> results(chosen.size());
            for (int r = 0; r < row.runs; ++r)
                for (size_t k = 0; k < chosen.size(); ++k) {
                    const RunResult res = chosen[k]->run();
                    results[k].rate.push_back(res.lookupsPerSecond * 1e-6);
                    results[k].cpuRate.push_back(res.lookupsPerCpuSecond * 1e-6);
                    results[k].hit.push_back(res.hitRatio * 100.0);
                    results[k].loads.push_back(res.loadsPer1000);
                }
            for (size_t k = 0; k < chosen.size(); ++k) {
                const Sys& sys = *chosen[k];
                const Summary a = summarize(results[k].rate), c = summarize(results[k].cpuRate),
                              b = summarize(results[k].hit);
                std::printf("| %s | %d | %s | %s | %.3f / %.3f / %.3f | %.3f / %.3f / %.3f | %.2f / %.2f / %.2f | %.2f |\n",
                            row.stream, threads, sys.name, sys.memory, a.min, a.median, a.max, c.min,
                            c.median, c.max, b.min, b.median, b.max, summarize(results[k].loads).median);
            }
            std::fflush(stdout);
        }
}

// ---------------------------------------------------------------- hit-path micro-benchmarks

struct HitFixture {
    std::unique_ptr<TextureCache> cache;
    TextureHandle handle;
    Stream warmStream;  // a 480×270 render-order stream whose pages all fit in the cache
    std::shared_ptr<const BotFile> bot;
    std::shared_ptr<const BotFile> bot2;  // the version-2 file of the same texture
};
HitFixture* g_hit = nullptr;

// Repeated reads of texels of one resident page: the microcache path.
void BM_MicrocacheHit(benchmark::State& state) {
    TextureCache::PerThread pt(*g_hit->cache);
    const uint8_t off[4] = {0, 1, 8, 9};
    float v[12];
    uint32_t page = 0;
    for (auto _ : state) {
        pt.readTexels(g_hit->handle, 0, page & 3, 0, off, 4, v);
        benchmark::DoNotOptimize(v[0]);
        ++page;
    }
    const TextureCacheStats s = pt.stats();
    state.counters["hitRatio"] = s.hitRatio();
}

// Cycles through more pages than the microcache holds, all resident: the shard-map path.
void BM_SharedHit(benchmark::State& state) {
    TextureCache::PerThread pt(*g_hit->cache);
    const uint8_t off[4] = {0, 1, 8, 9};
    float v[12];
    uint32_t i = 0;
    for (auto _ : state) {
        // 2048 distinct pages of level 0 (a 64×32 block): resident in the 4096-page cache.
        const uint32_t k = (i * 2654435761u) & 2047;
        pt.readTexels(g_hit->handle, 0, k & 63, k >> 6, off, 4, v);
        benchmark::DoNotOptimize(v[0]);
        ++i;
    }
    state.counters["hitRatio"] = pt.stats().hitRatio();
}

// One trilinear lookup on resident pages.
void BM_TrilinearLookup(benchmark::State& state) {
    TextureCache::PerThread pt(*g_hit->cache);
    float v[3];
    uint32_t i = 0;
    const float d = 1.5f / 4096.0f;
    for (auto _ : state) {
        const float s = float(i % 97) * (1.0f / 4096.0f), t = float(i % 89) * (1.0f / 4096.0f);
        sampleTexture(pt, g_hit->handle, LookupOptions{}, s, t, d, 0, 0, d, nullptr, 3, v);
        benchmark::DoNotOptimize(v[0]);
        ++i;
    }
    state.counters["hitRatio"] = pt.stats().hitRatio();
}

// The render-order stream on a cache that already holds every page it needs: the cost of the
// filter and the hit path alone, per lookup.
void BM_RenderOrderWarm(benchmark::State& state) {
    TextureCache::PerThread pt(*g_hit->cache);
    std::vector<float> out(3 * 1024);
    float* outs[3] = {out.data(), out.data() + 1024, out.data() + 2048};
    auto pass = [&] {
        for (const Tile& tile : g_hit->warmStream) {
            const LookupBatch b = tile.batch();
            sampleTexture(pt, g_hit->handle, LookupOptions{}, b, nullptr, 3, outs);
        }
    };
    pass();
    const TextureCacheStats before = pt.stats();
    for (auto _ : state) pass();
    const TextureCacheStats after = pt.stats();
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(lookupCount(g_hit->warmStream)));
    state.counters["hitRatio"] = double(after.hits - before.hits) / double(after.lookups - before.lookups);
}

// One page read as the cache's miss path does it, over level-0 pages in raster order: with one
// pread per page (mapped:0) or from a mapping of the whole file (mapped:1), from the version-3
// file (version:3, the one the cache reads) or the version-2 file of the same texture. Checksum,
// decoding and conversion to float included.
void BM_PageRead(benchmark::State& state) {
    const BotFile& bot = state.range(1) == 2 ? *g_hit->bot2 : *g_hit->bot;
    const bool mapped = state.range(0) != 0;
    const int fd = ::open(bot.path().c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        state.SkipWithError("cannot open the BOT file");
        return;
    }
    const size_t bytes = size_t(bot.fileBytes());
    void* map = mapped ? ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, fd, 0) : nullptr;
    if (map == MAP_FAILED) {
        ::close(fd);
        state.SkipWithError("mmap failed");
        return;
    }
    const BotLevel& l0 = bot.header().levels[0];
    std::vector<float> page(64 * bot.header().channels);
    uint64_t i = 0;
    for (auto _ : state) {
        const uint32_t px = uint32_t(i % l0.pagesX), py = uint32_t((i / l0.pagesX) % l0.pagesY);
        if (mapped)
            bot.readPageFromMapping(static_cast<const uint8_t*>(map), bytes, 0, px, py, page.data());
        else
            bot.readPage(fd, 0, px, py, page.data());
        benchmark::DoNotOptimize(page[0]);
        ++i;
    }
    if (map) ::munmap(map, bytes);
    ::close(fd);
}

}  // namespace

int main(int argc, char** argv) {
    Config cfg;
    const char* tmp = std::getenv("TMPDIR");
    cfg.dir = fs::path(tmp && *tmp ? tmp : "/tmp") / "pushpin-texture-bench";
    std::vector<char*> rest{argv[0]};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--quick") {
            cfg.quick = true;
        } else if (a == "--runs" && i + 1 < argc) {
            cfg.runs = std::max(1, std::atoi(argv[++i]));
            cfg.randomRuns = std::min(cfg.randomRuns, cfg.runs);
        } else if (a == "--stream" && i + 1 < argc) {
            cfg.streams = argv[++i];
        } else if (a == "--systems" && i + 1 < argc) {
            cfg.systems = argv[++i];
        } else if (a == "--micro-only") {
            cfg.tableRuns = false;
        } else if (a == "--dir" && i + 1 < argc) {
            cfg.dir = argv[++i];
        } else if (a == "--help" || a == "-h") {
            std::printf("usage: texture_cache_bench [--quick] [--runs N] [--dir D] [--stream render|random|both] [--systems ours|oiio|both] [--micro-only] [--benchmark_* ...]\n");
            return 0;
        } else {
            rest.push_back(argv[i]);
        }
    }
    if (cfg.quick) {
        cfg.runs = 3;
        cfg.randomRuns = 3;
        cfg.textureSize = 1024;
        cfg.imageWidth = 480;
        cfg.imageHeight = 270;
        cfg.randomLookups = 5000;
    }
    const Textures tex = makeTextures(cfg);
    if (cfg.tableRuns) runTable(cfg, tex);

    // Hit-path timings on a warm cache big enough for everything they touch.
    TextureCacheOptions o;
    o.pageSlots = 16384;  // 12 MiB: every page the micro-benchmarks touch stays resident
    o.maxChannels = 3;
    HitFixture fixture{std::make_unique<TextureCache>(o), {}, {}, {}, {}};
    fixture.handle = fixture.cache->registerFile(tex.bot);
    fixture.bot = BotFile::open(tex.bot);
    fixture.bot2 = BotFile::open(tex.bot2);
    Config warm = cfg;
    warm.imageWidth = 480;
    warm.imageHeight = 270;
    fixture.warmStream = renderOrderStream(warm);
    g_hit = &fixture;
    benchmark::RegisterBenchmark("TextureCache/microcacheHit", BM_MicrocacheHit);
    benchmark::RegisterBenchmark("TextureCache/sharedMapHit", BM_SharedHit);
    benchmark::RegisterBenchmark("TextureCache/trilinearLookup", BM_TrilinearLookup);
    benchmark::RegisterBenchmark("TextureCache/renderOrderWarm", BM_RenderOrderWarm);
    benchmark::RegisterBenchmark("BotFile/pageRead", BM_PageRead)
        ->ArgNames({"mapped", "version"})
        ->Args({0, 3})
        ->Args({1, 3})
        ->Args({0, 2})
        ->Args({1, 2});
    int n = int(rest.size());
    benchmark::Initialize(&n, rest.data());
    std::printf("\n");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    g_hit = nullptr;
    return 0;
}
