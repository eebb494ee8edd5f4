// bench/cache_hits_bench.cpp: measures how the texture cache does on your own BOT files.
//
//   cache_hits_bench [--pages N] [--threads T] [--stream sweep|random|trace FILE]
//                    [--lookups N] [--filter point|bilinear|trilinear] [--seed S]
//                    [--record FILE] files.bot...
//
// Streams:
//   sweep   every texel centre of level 0 of each file in raster order, file after file, with a
//           one-texel footprint (what a render of a texture-filling quad asks for)
//   random  uniformly random file, (s, t) and footprint width (1 texel up to the whole texture)
//   trace   the lookups a render recorded with LookupTraceWriter (texture/lookup_trace.h); the
//           trace names its textures, so no files are needed (files given replace them in order)
// --record FILE writes the lookups of this run as a trace (to replay later with other --pages).
// The stream is cut into batches of 256 lookups, handed to T threads in order. Prints the
// cache's hit ratio (page requests served without a read), misses per thousand lookups, bytes
// read and lookups per second, plus the raw counters.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cache/error.h"
#include "texture/lookup_trace.h"
#include "texture/texture_cache.h"
#include "texture/texture_sampler.h"

namespace {

using namespace pushpin::texture;

[[noreturn]] void usage(const char* why) {
    if (why) std::fprintf(stderr, "cache_hits_bench: %s\n", why);
    std::fprintf(stderr,
                 "usage: cache_hits_bench [--pages N] [--threads T] [--stream sweep|random|trace FILE]\n"
                 "                        [--lookups N] [--filter point|bilinear|trilinear] [--seed S]\n"
                 "                        [--record FILE] files.bot...\n");
    std::exit(2);
}

uint64_t parseCount(const char* s, const char* flag) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(s, &end, 10);
    if (!end || *end || v == 0) usage((std::string(flag) + " needs a positive integer").c_str());
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t pages = 256, threads = 1;
    uint64_t maxLookups = 1000000, seed = 1;
    std::string stream = "sweep", traceFile, recordFile;
    LookupOptions options;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> const char* {
            if (i + 1 >= argc) usage((a + " needs a value").c_str());
            return argv[++i];
        };
        if (a == "--pages") {
            pages = uint32_t(parseCount(next(), "--pages"));
        } else if (a == "--threads") {
            threads = uint32_t(parseCount(next(), "--threads"));
        } else if (a == "--lookups") {
            maxLookups = parseCount(next(), "--lookups");
        } else if (a == "--record") {
            recordFile = next();
        } else if (a == "--seed") {
            seed = parseCount(next(), "--seed");
        } else if (a == "--stream") {
            stream = next();
            if (stream == "trace") traceFile = next();
            else if (stream != "sweep" && stream != "random") usage("unknown stream");
        } else if (a == "--filter") {
            const std::string f = next();
            if (f == "point") options.filter = FilterMode::Point;
            else if (f == "bilinear") options.filter = FilterMode::Bilinear;
            else if (f == "trilinear") options.filter = FilterMode::Trilinear;
            else usage("unknown filter");
        } else if (a == "--help" || a == "-h") {
            usage(nullptr);
        } else if (!a.empty() && a[0] == '-') {
            usage(("unknown option " + a).c_str());
        } else {
            files.push_back(a);
        }
    }

    // The stream: batches of (texture index, SoA lookups, options).
    struct Batch {
        uint32_t texture = 0;
        LookupOptions options;
        std::vector<float> s, t, dsdx, dsdy, dtdx, dtdy;
    };
    std::vector<Batch> batches;
    try {
        if (stream == "trace") {
            LookupTrace trace = readLookupTrace(traceFile);
            std::vector<std::string> traceFiles;
            for (const auto& p : trace.textures) traceFiles.push_back(p.string());
            for (size_t k = 0; k < files.size() && k < traceFiles.size(); ++k) traceFiles[k] = files[k];
            files = traceFiles;
            uint64_t n = 0;
            for (TraceBatch& tb : trace.batches) {
                if (n >= maxLookups) break;
                Batch b;
                b.texture = tb.texture;
                b.options = tb.options;
                b.s = std::move(tb.s);
                b.t = std::move(tb.t);
                b.dsdx = std::move(tb.dsdx);
                b.dsdy = std::move(tb.dsdy);
                b.dtdx = std::move(tb.dtdx);
                b.dtdy = std::move(tb.dtdy);
                n += b.s.size();
                batches.push_back(std::move(b));
            }
        }
    } catch (const pushpin::Error& e) {
        std::fprintf(stderr, "cache_hits_bench: %s\n", e.what());
        return 1;
    }
    if (files.empty()) usage("no texture files given");

    TextureCacheOptions co;
    co.pageSlots = pages;
    TextureCache cache(co);
    std::vector<TextureHandle> handles;
    std::vector<const TextureInfo*> infos;
    for (const std::string& f : files) {
        handles.push_back(f.empty() ? TextureHandle{} : cache.registerFile(f));
        infos.push_back(cache.info(handles.back()));
        if (!f.empty() && !infos.back()) {
            std::fprintf(stderr, "cache_hits_bench: cannot use %s\n", f.c_str());
            return 1;
        }
    }

    if (stream == "sweep") {
        uint64_t n = 0;
        for (uint32_t k = 0; n < maxLookups; k = (k + 1) % uint32_t(files.size())) {
            const TextureInfo& info = *infos[k];
            const float w = info.levels[0].widthF, h = info.levels[0].heightF;
            Batch b;
            for (uint32_t y = 0; y < info.levels[0].height && n < maxLookups; ++y)
                for (uint32_t x = 0; x < info.levels[0].width && n < maxLookups; ++x, ++n) {
                    b.s.push_back((float(x) + 0.5f) / w);
                    b.t.push_back((float(y) + 0.5f) / h);
                    b.dsdx.push_back(1.0f / w);
                    b.dsdy.push_back(0.0f);
                    b.dtdx.push_back(0.0f);
                    b.dtdy.push_back(1.0f / h);
                    if (b.s.size() == 256) {
                        b.texture = k;
                        b.options = options;
                        batches.push_back(std::move(b));
                        b = Batch{};
                    }
                }
            if (!b.s.empty()) {
                b.texture = k;
                b.options = options;
                batches.push_back(std::move(b));
            }
        }
    } else if (stream == "random") {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<float> uv(0.0f, 1.0f);
        for (uint64_t n = 0; n < maxLookups;) {
            Batch b;
            b.options = options;
            b.texture = uint32_t(rng() % files.size());
            const TextureInfo& info = *infos[b.texture];
            const float maxLod = float(info.levels.size() - 1);
            for (int i = 0; i < 256 && n < maxLookups; ++i, ++n) {
                const float width = std::exp2(uv(rng) * maxLod);  // in level-0 texels
                b.s.push_back(uv(rng));
                b.t.push_back(uv(rng));
                b.dsdx.push_back(width / info.levels[0].widthF);
                b.dsdy.push_back(0.0f);
                b.dtdx.push_back(0.0f);
                b.dtdy.push_back(width / info.levels[0].heightF);
            }
            batches.push_back(std::move(b));
        }
    }
    uint64_t total = 0;
    for (const Batch& b : batches) total += b.s.size();

    std::unique_ptr<LookupTraceWriter> recorder;
    if (!recordFile.empty()) {
        try {
            recorder = std::make_unique<LookupTraceWriter>(recordFile);
        } catch (const pushpin::Error& e) {
            std::fprintf(stderr, "cache_hits_bench: %s\n", e.what());
            return 1;
        }
        cache.setTraceWriter(recorder.get());
    }

    std::atomic<size_t> next{0};
    std::vector<std::thread> pool;
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t t = 0; t < threads; ++t)
        pool.emplace_back([&] {
            TextureCache::PerThread pt(cache);
            std::vector<float> out(4 * 256);
            float* outs[4] = {out.data(), out.data() + 256, out.data() + 512, out.data() + 768};
            for (size_t k; (k = next.fetch_add(1)) < batches.size();) {
                const Batch& b = batches[k];
                if (!handles[b.texture].valid()) continue;
                for (size_t first = 0; first < b.s.size(); first += 256) {
                    LookupBatch lb;
                    lb.count = std::min<size_t>(256, b.s.size() - first);
                    lb.s = b.s.data() + first;
                    lb.t = b.t.data() + first;
                    lb.dsdx = b.dsdx.data() + first;
                    lb.dsdy = b.dsdy.data() + first;
                    lb.dtdx = b.dtdx.data() + first;
                    lb.dtdy = b.dtdy.data() + first;
                    sampleTexture(pt, handles[b.texture], b.options, lb, nullptr, 4, outs);
                }
            }
        });
    for (auto& t : pool) t.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const TextureCacheStats s = cache.stats();
    if (recorder) {
        cache.setTraceWriter(nullptr);
        try {
            recorder->close();
        } catch (const pushpin::Error& e) {
            std::fprintf(stderr, "cache_hits_bench: %s\n", e.what());
            return 1;
        }
    }

    std::printf("files            %zu\n", files.size());
    std::printf("stream           %s%s%s\n", stream.c_str(), traceFile.empty() ? "" : " ", traceFile.c_str());
    std::printf("cache            %u pages (%.1f KiB)\n", pages, double(cache.slotMemoryBytes()) / 1024.0);
    std::printf("threads          %u\n", threads);
    std::printf("lookups          %llu\n", static_cast<unsigned long long>(total));
    std::printf("hit ratio        %.4f  (%llu of %llu page requests)\n", s.hitRatio(),
                static_cast<unsigned long long>(s.hits), static_cast<unsigned long long>(s.lookups));
    std::printf("misses/1000      %.3f  (page misses per thousand lookups)\n",
                total ? 1000.0 * double(s.misses) / double(total) : 0.0);
    std::printf("bytes read       %llu  (%llu pages, %llu evictions, %.3f s in page reads)\n",
                static_cast<unsigned long long>(s.bytesRead), static_cast<unsigned long long>(s.pagesRead),
                static_cast<unsigned long long>(s.evictions), s.readSeconds);
    std::printf("lookups/s        %.0f  (%.3f s)\n", seconds > 0 ? double(total) / seconds : 0.0, seconds);
    if (s.brokenTextures) std::printf("broken textures  %llu\n", static_cast<unsigned long long>(s.brokenTextures));
    return s.brokenTextures ? 1 : 0;
}
