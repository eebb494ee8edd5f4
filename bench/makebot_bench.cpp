// makebot_bench: end-to-end comparison of `makebot` against OpenImageIO's `maketx` on two generated
// textures (4096^2 RGB 8-bit TIFF and 8192^2 RGBA half EXR; --quick uses 1024^2 and 2048^2).
// Each tool runs several times as a child process; the table gives min/median/max wall time, peak
// resident memory of the child (wait4 ru_maxrss) and output size, with maketx/makebot ratios.
//
// --suite runs both tools once on each image of a suite of real textures instead (see
// suiteImages below and bench/README.md) and adds the peak memory of each and the time to decode
// every page of the BOT file through texture::BotFile.
//
// usage: makebot_bench [--quick] [--runs N] [--filter box|lanczos3] [--dir DIR]
//                      [--makebot PATH] [--maketx PATH]
//        makebot_bench --suite [--only TEXT] [--bot-version N] [--filter F] [--dir DIR] [--makebot PATH]
//                      [--maketx PATH]
#include "bench/bench_support.h"
#include "texture/bot_file.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <Imath/half.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
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


// ------------------------------------------------------------------------------------------ suite

// The suite's images, in a fixed order: the textures of the Maya projects under
// /work/shared/scenes/ma-projects (every JPEG, PNG, TIFF, PSD, BMP and IFF file), the 4096^2
// artworks of Debian's gnome-backgrounds other than the wood and adwaita ones, and the float HDR
// environments of blender-data. A source that is not installed is skipped with a note.
std::vector<fs::path> suiteImages() {
    std::vector<fs::path> images;
    auto lower = [](std::string s) {
        for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
        return s;
    };
    auto collect = [&](const fs::path& root, const std::vector<std::string>& extensions, bool recursive,
                       const char* what) {
        std::vector<fs::path> found;
        std::error_code ec;
        if (!fs::is_directory(root, ec)) {
            std::printf("note: %s not found at %s, skipped\n", what, root.c_str());
            return found;
        }
        auto consider = [&](const fs::directory_entry& e) {
            if (!e.is_regular_file()) return;
            const std::string ext = lower(e.path().extension().string());
            if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) found.push_back(e.path());
        };
        if (recursive)
            for (const auto& e : fs::recursive_directory_iterator(root, ec)) consider(e);
        else
            for (const auto& e : fs::directory_iterator(root, ec)) consider(e);
        std::sort(found.begin(), found.end());
        if (found.empty()) std::printf("note: no %s under %s, skipped\n", what, root.c_str());
        return found;
    };
    for (const fs::path& p : collect("/work/shared/scenes/ma-projects",
                                     {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".psd", ".bmp", ".iff"}, true,
                                     "Maya project textures"))
        images.push_back(p);
    for (const fs::path& p :
         collect("/usr/share/backgrounds/gnome", {".webp", ".jpg", ".jpeg", ".png"}, false,
                 "gnome-backgrounds (apt-get install gnome-backgrounds)")) {
        const std::string name = p.filename().string();
        if (name.rfind("wood", 0) == 0 || name.rfind("adwaita", 0) == 0) continue;
        auto in = OIIO::ImageInput::open(p.string());
        if (!in) continue;
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.width == 4096 && spec.height == 4096) images.push_back(p);
    }
    for (const fs::path& p :
         collect("/usr/share/blender/datafiles/studiolights/world", {".exr"}, false, "blender-data environments"))
        images.push_back(p);
    return images;
}

// Reads every page of a BOT file held in memory, level by level in raster order, and returns the
// mean nanoseconds per page (the best of two passes; the first also warms the caches).
double pageDecodeNs(const fs::path& bot, uint64_t& pages) {
    std::ifstream f(bot, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto file = pushpin::texture::BotFile::parse(bytes.data(), bytes.size(), bot);
    const pushpin::texture::BotHeader& h = file->header();
    std::vector<float> texels(size_t(pushpin::texture::kPageSizeTexels) * pushpin::texture::kPageSizeTexels *
                              h.channels);
    pages = file->pageCount();
    double best = HUGE_VAL;
    for (int pass = 0; pass < 2; ++pass) {
        const auto t0 = std::chrono::steady_clock::now();
        for (uint32_t l = 0; l < h.levels.size(); ++l)
            for (uint32_t py = 0; py < h.levels[l].pagesY; ++py)
                for (uint32_t px = 0; px < h.levels[l].pagesX; ++px)
                    file->readPageFromMemory(bytes.data(), bytes.size(), l, px, py, texels.data());
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best * 1e9 / double(std::max<uint64_t>(pages, 1));
}

// The name a suite image is shown by: its path below the suite's roots.
std::string suiteName(const fs::path& p) {
    std::string s = p.string();
    for (const char* root : {"/work/shared/scenes/ma-projects/", "/usr/share/backgrounds/gnome/",
                             "/usr/share/blender/datafiles/studiolights/world/"})
        if (s.rfind(root, 0) == 0) return s.substr(std::strlen(root));
    return s;
}

int runSuite(const std::string& only, const std::string& filter, const std::string& botVersion, const fs::path& dir,
             const fs::path& makebot, const fs::path& maketx) {
    if (!fs::exists(maketx)) {
        std::fprintf(stderr, "maketx not found at %s (use --maketx)\n", maketx.c_str());
        return 1;
    }
    std::vector<fs::path> images = suiteImages();
    if (!only.empty())
        std::erase_if(images, [&](const fs::path& p) { return suiteName(p).find(only) == std::string::npos; });
    std::printf("makebot vs maketx on %zu real images, filter %s, BOT version %s, one run each, %ld cores\n",
                images.size(), filter.c_str(), botVersion.empty() ? "(makebot's default)" : botVersion.c_str(),
                sysconf(_SC_NPROCESSORS_ONLN));
    std::printf("%-44s %11s %-9s %11s %11s %6s %7s %7s %8s %8s %7s\n", "image", "pixels", "type", "maketx B",
                "makebot B", "size", "time", "tx s", "tx MB", "bot MB", "ns/page");
    struct Total {
        uint64_t txBytes = 0, botBytes = 0, pages = 0;
        double txS = 0, botS = 0, decodeS = 0, worstSize = 0;
        long txPeakKiB = 0, botPeakKiB = 0;
        int images = 0, larger = 0;
    } total;
    const fs::path botOut = dir / "suite.bot", txOut = dir / "suite.tx";
    for (const fs::path& image : images) {
        const std::string name = suiteName(image);
        auto in = OIIO::ImageInput::open(image.string());
        if (!in) {
            std::printf("%-44s unreadable by OpenImageIO, skipped\n", name.c_str());
            continue;
        }
        const OIIO::ImageSpec spec = in->spec();
        in.reset();
        const Summary t = measure({maketx.string(), "--filter", filter, "-o", txOut.string(), image.string()}, txOut, 1);
        std::vector<std::string> botArgs = {makebot.string(), "--filter", filter};
        if (!botVersion.empty()) botArgs.insert(botArgs.end(), {"--bot-version", botVersion});
        botArgs.insert(botArgs.end(), {image.string(), botOut.string()});
        const Summary b = measure(botArgs, botOut, 1);
        if (!t.ok || !b.ok) {
            std::printf("%-44s %s failed, skipped\n", name.c_str(), t.ok ? "makebot" : "maketx");
            continue;
        }
        uint64_t pages = 0;
        double ns = 0;
        try {
            ns = pageDecodeNs(botOut, pages);
        } catch (const std::exception& e) {
            std::printf("%-44s cannot read the BOT file back: %s\n", name.c_str(), e.what());
            continue;
        }
        const double sizeRatio = double(b.outBytes) / double(t.outBytes);
        const std::string pixels = std::to_string(spec.width) + "x" + std::to_string(spec.height);
        const std::string type = std::to_string(spec.nchannels) + " " + spec.format.c_str();
        std::printf("%-44s %11s %-9s %11llu %11llu %6.3f %7.3f %7.2f %8.1f %8.1f %7.0f\n", name.c_str(),
                    pixels.c_str(), type.c_str(), (unsigned long long)t.outBytes, (unsigned long long)b.outBytes,
                    sizeRatio, b.medS / t.medS, t.medS, t.peakKiB / 1024.0, b.peakKiB / 1024.0, ns);
        total.txBytes += t.outBytes;
        total.botBytes += b.outBytes;
        total.txS += t.medS;
        total.botS += b.medS;
        total.decodeS += ns * 1e-9 * double(pages);
        total.pages += pages;
        total.txPeakKiB = std::max(total.txPeakKiB, t.peakKiB);
        total.botPeakKiB = std::max(total.botPeakKiB, b.peakKiB);
        total.worstSize = std::max(total.worstSize, sizeRatio);
        total.larger += b.outBytes > t.outBytes;
        ++total.images;
    }
    if (total.images == 0) return 1;
    std::printf("%-44s %11s %-9s %11llu %11llu %6.3f %7.3f %7.2f %8.1f %8.1f %7.0f\n", "total", "", "",
                (unsigned long long)total.txBytes, (unsigned long long)total.botBytes,
                double(total.botBytes) / double(total.txBytes), total.botS / total.txS, total.txS,
                total.txPeakKiB / 1024.0, total.botPeakKiB / 1024.0, total.decodeS * 1e9 / double(total.pages));
    std::printf("%d images; makebot larger than maketx on %d, worst size ratio %.3f; total makebot %.1f s, maketx "
                "%.1f s; peak MB is the largest of any image\n",
                total.images, total.larger, total.worstSize, total.botS, total.txS);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, suite = false;
    std::string only, botVersion;
    int runs = 3;
    std::string filter = "box";
    fs::path dir = fs::temp_directory_path() / "pushpin_makebot_bench";
    fs::path makebot = fs::canonical("/proc/self/exe").parent_path().parent_path() / "makebot";
    fs::path maketx = "/usr/bin/maketx";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--quick") quick = true;
        else if (a == "--suite") suite = true;
        else if (a == "--only") only = next();
        else if (a == "--bot-version") botVersion = next();
        else if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
        else if (a == "--filter") filter = next();
        else if (a == "--dir") dir = next();
        else if (a == "--makebot") makebot = next();
        else if (a == "--maketx") maketx = next();
        else {
            std::fprintf(stderr,
                         "usage: makebot_bench [--quick] [--runs N] [--filter F] [--dir D] [--makebot P] [--maketx P]\n"
                         "       makebot_bench --suite [--only TEXT] [--bot-version N] [--filter F] [--dir D] [--makebot P]\n"
                         "                     [--maketx P]\n");
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
    if (suite) return runSuite(only, filter, botVersion, dir, makebot, maketx);

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
