// makebot_bench: end-to-end comparison of `makebot` against OpenImageIO's `maketx` on two generated
// textures (4096^2 RGB 8-bit TIFF and 8192^2 RGBA half EXR; --quick uses 1024^2 and 2048^2).
// Each tool runs several times as a child process; the table gives min/median/max wall time, peak
// resident memory of the child (wait4 ru_maxrss) and output size, with maketx/makebot ratios.
//
// usage: makebot_bench [--quick] [--runs N] [--filter box|lanczos3] [--dir DIR]
//                      [--makebot PATH] [--maketx PATH]
#include "bench/bench_support.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <Imath/half.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;

// Deterministic noise in [0, 1) from integer coordinates.
float hashNoise(uint32_t x, uint32_t y, uint32_t c) {
    uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ c * 0xcb1ab31fu;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    h ^= h >> 12;
    h *= 0x297a2d39u;
    h ^= h >> 15;
    return float(h >> 8) * (1.0f / 16777216.0f);
}

// Smooth gradients, a few sinusoidal details, hard-edged shapes and fine noise.
float content(uint32_t x, uint32_t y, uint32_t c, uint32_t size) {
    const float u = float(x) / float(size), v = float(y) / float(size);
    float val = 0.15f + 0.35f * u + 0.25f * v * (c == 1 ? 1.0f : 0.5f);
    val += 0.12f * std::sin(40.0f * u + 7.0f * c) * std::cos(33.0f * v);
    val += 0.05f * std::sin(400.0f * u * v + c);
    const float dx = u - 0.5f, dy = v - 0.5f;
    if ((int(std::floor(std::sqrt(dx * dx + dy * dy) * 24.0f)) & 1) == 0) val += 0.1f;  // rings with hard edges
    val += (hashNoise(x, y, c) - 0.5f) * 0.03f;
    return std::clamp(val, 0.0f, 1.0f);
}

bool generate(const fs::path& path, uint32_t size, int channels, OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) return false;
    OIIO::ImageSpec spec(static_cast<int>(size), static_cast<int>(size), channels, type);
    spec.attribute("compression", "zip");
    if (channels == 4) spec.alpha_channel = 3;
    if (!out->open(path.string(), spec)) return false;
    const uint32_t band = 64;
    std::vector<float> rows(size_t(size) * channels * band);
    for (uint32_t y0 = 0; y0 < size; y0 += band) {
        const uint32_t n = std::min(band, size - y0);
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < size; ++x)
                for (int c = 0; c < channels; ++c) {
                    float v = content(x, y0 + y, uint32_t(c), size);
                    if (c == 3) v = 0.5f + 0.5f * std::sin(float(x + y0 + y) * 0.01f);  // alpha
                    if (type == OIIO::TypeDesc::HALF && c < 3) v *= 4.0f;                // some HDR range
                    rows[(size_t(y) * size + x) * channels + c] = v;
                }
        if (!out->write_scanlines(int(y0), int(y0 + n), 0, OIIO::TypeDesc::FLOAT, rows.data())) return false;
    }
    return out->close();
}

struct Summary {
    double minS = 0, medS = 0, maxS = 0;
    long peakKiB = 0;
    uint64_t outBytes = 0;
    bool ok = true;
};

Summary measure(const std::vector<std::string>& args, const fs::path& output, int runs) {
    std::vector<double> times;
    Summary s;
    for (int i = 0; i < runs; ++i) {
        fs::remove(output);
        const pushpin::bench::ChildRun r = pushpin::bench::runChild(args);
        if (r.exitCode != 0) {
            std::fprintf(stderr, "failed (%d): %s\n", r.exitCode, args[0].c_str());
            s.ok = false;
            return s;
        }
        times.push_back(r.seconds);
        s.peakKiB = std::max(s.peakKiB, r.peakKiB);
    }
    std::sort(times.begin(), times.end());
    s.minS = times.front();
    s.maxS = times.back();
    s.medS = times[times.size() / 2];
    s.outBytes = fs::file_size(output);
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int runs = 3;
    std::string filter = "box";
    fs::path dir = fs::temp_directory_path() / "pushpin_makebot_bench";
    fs::path makebot = fs::canonical("/proc/self/exe").parent_path().parent_path() / "makebot";
    fs::path maketx = "/usr/bin/maketx";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--quick") quick = true;
        else if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
        else if (a == "--filter") filter = next();
        else if (a == "--dir") dir = next();
        else if (a == "--makebot") makebot = next();
        else if (a == "--maketx") maketx = next();
        else {
            std::fprintf(stderr, "usage: makebot_bench [--quick] [--runs N] [--filter F] [--dir D] [--makebot P] [--maketx P]\n");
            return 2;
        }
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rows appear as they are measured
    if (!fs::exists(makebot)) {
        std::fprintf(stderr, "makebot not found at %s (use --makebot)\n", makebot.c_str());
        return 1;
    }
    const bool haveMaketx = fs::exists(maketx);
    fs::create_directories(dir);

    struct Case {
        std::string name;
        fs::path input;
        uint32_t size;
        int channels;
        OIIO::TypeDesc type;
    };
    std::vector<Case> cases = {
        {"RGB u8", dir / (quick ? "rgb8_quick.tif" : "rgb8.tif"), quick ? 1024u : 4096u, 3, OIIO::TypeDesc::UINT8},
        {"RGBA half", dir / (quick ? "rgbah_quick.exr" : "rgbah.exr"), quick ? 2048u : 8192u, 4, OIIO::TypeDesc::HALF},
    };
    std::printf("makebot vs maketx, filter %s, %d runs each, %ld cores\n", filter.c_str(), runs, sysconf(_SC_NPROCESSORS_ONLN));
    std::printf("%-10s %-11s %-8s %8s %8s %8s %10s %11s\n", "image", "size", "tool", "min s", "median s", "max s",
                "peak MB", "output MB");
    for (const Case& c : cases) {
        if (!fs::exists(c.input) && !generate(c.input, c.size, c.channels, c.type)) {
            std::fprintf(stderr, "cannot write %s: %s\n", c.input.c_str(), OIIO::geterror().c_str());
            return 1;
        }
        const std::string sizeName = std::to_string(c.size) + "^2";
        const fs::path botOut = dir / "out.bot", txOut = dir / "out.tx";
        const Summary b = measure({makebot.string(), "--filter", filter, c.input.string(), botOut.string()}, botOut, runs);
        std::printf("%-10s %-11s %-8s %8.3f %8.3f %8.3f %10.1f %11.2f\n", c.name.c_str(), sizeName.c_str(), "makebot",
                    b.minS, b.medS, b.maxS, b.peakKiB / 1024.0, b.outBytes / 1e6);
        if (!haveMaketx) continue;
        const Summary t = measure({maketx.string(), "--filter", filter, "-o", txOut.string(), c.input.string()}, txOut, runs);
        std::printf("%-10s %-11s %-8s %8.3f %8.3f %8.3f %10.1f %11.2f\n", c.name.c_str(), sizeName.c_str(), "maketx",
                    t.minS, t.medS, t.maxS, t.peakKiB / 1024.0, t.outBytes / 1e6);
        if (b.ok && t.ok)
            std::printf("%-10s %-11s %-8s speedup (median) %.2fx, memory %.2f of maketx, output %.3f of maketx\n",
                        c.name.c_str(), sizeName.c_str(), "ratio", t.medS / b.medS, double(b.peakKiB) / double(t.peakKiB),
                        double(b.outBytes) / double(t.outBytes));
    }
    return 0;
}
