// makebot: converts any image OpenImageIO or libwebp reads into a BOT texture
// (texture/BOT_FORMAT.md). The input is read in bands of rows (texture/row_source.h: WebP stills by
// libwebp as they decode, the rest through OpenImageIO, loaded only then) and streamed through the
// mip cascade, so memory stays bounded whatever the image size; reading ahead overlaps the work on
// the bands already read. The output is written under a temporary name and renamed into place; on
// any error nothing is left behind and an existing output is untouched.
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "cache/error.h"
#include "cache/output_file.h"
#include "texture/bot_file.h"
#include "texture/mipmap.h"
#include "texture/row_source.h"
#include "tools/makebot/oiio_module.h"

namespace {

using namespace pushpin;
using namespace pushpin::texture;

struct Options {
    std::string input, output;
    MipFilter filter = MipFilter::Box;
    std::optional<PixelType> format;
    std::optional<ColorSpace> colorSpace;
    WrapMode wrapS = WrapMode::Periodic, wrapT = WrapMode::Periodic;
    int threads = 0;
    bool verbose = false;
    int compressionLevel = 1;
    BotDictionary dictionary = BotDictionary::Auto;
    std::optional<PageFilter> pageFilter;  // unset: chosen from the first pages (per band in version 3)
    uint32_t version = 3;
};

const char* kUsage =
    "usage: makebot [options] input output.bot\n"
    "Converts an image into a BOT texture. WebP stills are read by libwebp; every other format\n"
    "OpenImageIO reads, through makebot-oiio.so beside makebot.\n"
    "  --filter box|triangle|lanczos3   mip filter (default box)\n"
    "  --format u8|u16|half|float       stored pixel type (default: the input's)\n"
    "  --wrap MODE | --wrap S,T         periodic|clamp|black|mirror (default periodic)\n"
    "  --colorspace linear|srgb         default: srgb for 8-bit inputs without other colour-space\n"
    "                                   metadata, else linear\n"
    "  --threads N                      worker threads (default: all)\n"
    "  --bot-version 3|2                file version (default 3: rANS-coded pages; 2: zstd pages,\n"
    "                                   about 1.6x the size, a page decoding in about 0.97 of the time)\n"
    "  --zstd-level N                   version 2: zstd level for pages with a trained or no dictionary\n"
    "                                   (default 1; literal-dictionary pages use zstd's fast level)\n"
    "  --dictionary auto|none|trained|literal\n"
    "                                   version 2: per-file zstd dictionary (default auto: the kind that codes\n"
    "                                   the first pages smallest)\n"
    "  --no-dictionary                  the same as --dictionary none\n"
    "  --page-filter auto|med|mean|none page prediction (default auto: the one whose residuals code\n"
    "                                   smaller, per band in version 3, on the first pages in version 2)\n"
    "  --no-predict                     the same as --page-filter none\n"
    "  -v                               print levels, sizes, time and compression ratio\n"
    "exit status: 0 done; 1 the input cannot be read whole (missing, truncated, damaged,\n"
    "unsupported); 2 usage; 75 the output cannot be written (full disk, I/O error); 130/143 after\n"
    "SIGINT/SIGTERM. On failure no output is left and an existing output is unchanged.\n";

[[noreturn]] void usageError(const std::string& msg) {
    std::fprintf(stderr, "makebot: %s\n%s", msg.c_str(), kUsage);
    std::exit(2);
}

std::optional<WrapMode> parseWrap(const std::string& s) {
    if (s == "periodic") return WrapMode::Periodic;
    if (s == "clamp") return WrapMode::Clamp;
    if (s == "black") return WrapMode::Black;
    if (s == "mirror") return WrapMode::Mirror;
    return std::nullopt;
}

Options parseArgs(int argc, char** argv) {
    Options o;
    std::vector<std::string> positional;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usageError("missing value after " + a);
            return argv[++i];
        };
        if (a == "--filter") {
            const std::string v = value();
            const auto f = parseMipFilter(v);
            if (!f) usageError("unknown filter '" + v + "'");
            o.filter = *f;
        } else if (a == "--format") {
            const std::string v = value();
            if (v == "u8") o.format = PixelType::U8;
            else if (v == "u16") o.format = PixelType::U16;
            else if (v == "half") o.format = PixelType::Half;
            else if (v == "float") o.format = PixelType::Float;
            else usageError("unknown format '" + v + "'");
        } else if (a == "--wrap") {
            const std::string v = value();
            const size_t comma = v.find(',');
            const auto s = parseWrap(v.substr(0, comma));
            const auto t = comma == std::string::npos ? s : parseWrap(v.substr(comma + 1));
            if (!s || !t) usageError("unknown wrap mode '" + v + "'");
            o.wrapS = *s;
            o.wrapT = *t;
        } else if (a == "--colorspace") {
            const std::string v = value();
            if (v == "linear") o.colorSpace = ColorSpace::Linear;
            else if (v == "srgb") o.colorSpace = ColorSpace::SRGB;
            else usageError("unknown colour space '" + v + "'");
        } else if (a == "--threads") {
            const std::string v = value();
            char* end = nullptr;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (v.empty() || *end || n < 0 || n > 4096) usageError("bad thread count '" + v + "'");
            o.threads = int(n);
        } else if (a == "--zstd-level") {
            const std::string v = value();
            char* end = nullptr;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (v.empty() || *end || n < 1 || n > 22) usageError("bad zstd level '" + v + "'");
            o.compressionLevel = int(n);
        } else if (a == "--bot-version") {
            const std::string v = value();
            if (v == "2") o.version = 2;
            else if (v == "3") o.version = 3;
            else usageError("bad BOT version '" + v + "' (2 or 3)");
        } else if (a == "--dictionary") {
            const std::string v = value();
            const auto kind = parseBotDictionary(v);
            if (!kind) usageError("bad dictionary kind '" + v + "'");
            o.dictionary = *kind;
        } else if (a == "--no-dictionary") {
            o.dictionary = BotDictionary::None;
        } else if (a == "--page-filter") {
            const std::string v = value();
            if (v == "auto") {
                o.pageFilter.reset();
            } else if (auto f = parsePageFilter(v)) {
                o.pageFilter = *f;
            } else {
                usageError("bad page filter '" + v + "'");
            }
        } else if (a == "--no-predict") {
            o.pageFilter = PageFilter::None;
        } else if (a == "-v" || a == "--verbose") {
            o.verbose = true;
        } else if (a == "-h" || a == "--help") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (a.size() > 1 && a[0] == '-') {
            usageError("unknown option " + a);
        } else {
            positional.push_back(a);
        }
    }
    if (positional.size() != 2) usageError("expected an input and an output file");
    o.input = positional[0];
    o.output = positional[1];
    return o;
}

int run(const Options& o) {
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<RowSource> source = openRowSource(o.input, makebot::openOiioRowSourceFromModule);
    const RowSourceInfo& info = source->info();
    const uint32_t width = info.width, height = info.height, channels = info.channels;

    BotWriteOptions wo;
    wo.pixelType = o.format ? *o.format : info.pixelType;
    wo.colorSpace = o.colorSpace ? *o.colorSpace : info.colorSpace;
    wo.wrapS = o.wrapS;
    wo.wrapT = o.wrapT;
    wo.filter = mipFilterName(o.filter);
    wo.threads = o.threads;
    wo.alphaChannel = info.alphaChannel;
    wo.compressionLevel = o.compressionLevel;
    wo.dictionary = o.dictionary;
    wo.pageFilter = o.pageFilter;
    wo.version = o.version;

    BotWriteStats stats;
    std::vector<BotLevel> levels;
    auto convert = [&] {
        BotWriter writer(o.output, width, height, channels, wo);
        MipCascade cascade(width, height, channels, o.filter, wo.colorSpace, wo.alphaChannel,
                           [&](uint32_t level, uint32_t firstRow, uint32_t rowCount, const float* rows, bool linear) {
                               writer.addRows(level, firstRow, rowCount, rows, linear);
                           });
        // Four bands ahead: decoding keeps going while a finished band of pages is coded.
        RowPrefetcher bands(*source, 4);
        for (RowPrefetcher::Band b = bands.next(); b.rows; b = bands.next()) cascade.pushRows(b.values, b.rows);
        levels = writer.header().levels;
        stats = writer.finish();
    };
    // An arena of its own even at the default thread count: run from the implicit arena, the
    // conversion of a 4096^2 WebP image measured as slow as on one thread (1.69 s against 1.15 s in
    // an arena of two on two cores).
    tbb::task_arena arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic);
    arena.execute(convert);

    if (o.verbose) {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%s: %ux%u, %u channels, %s, %s, filter %s, read by %s\n", o.input.c_str(), width, height,
                    channels, pixelTypeName(wo.pixelType), colorSpaceName(wo.colorSpace), wo.filter.c_str(),
                    info.reader);
        for (size_t l = 0; l < levels.size(); ++l)
            std::printf("  level %2zu: %6u x %-6u %6u x %-6u pages\n", l, levels[l].width, levels[l].height,
                        levels[l].pagesX, levels[l].pagesY);
        std::printf("%s: %llu pages, %llu bytes raw, %llu bytes written (ratio %.3f), dictionary %u bytes, %.3f s\n",
                    o.output.c_str(), (unsigned long long)stats.pages, (unsigned long long)stats.rawBytes,
                    (unsigned long long)stats.fileBytes, double(stats.fileBytes) / double(std::max<uint64_t>(1, stats.rawBytes)),
                    stats.dictionaryBytes, seconds);
        if (stats.version == 3)
            std::printf("%s: version 3, %llu bands, first band's page filter %s; pages stored as", o.output.c_str(),
                        (unsigned long long)stats.bands, pageFilterName(stats.pageFilter));
        else
            std::printf("%s: version 2, page filter %s, %s dictionary; pages stored as", o.output.c_str(),
                        pageFilterName(stats.pageFilter), botDictionaryName(stats.dictionary));
        const char* separator = "";
        for (uint32_t k = 0; k < kBotPageKinds; ++k) {
            if (!stats.pagesOfKind[k]) continue;
            std::printf("%s %s %llu", separator, pageKindName(BotPageKind(k)), (unsigned long long)stats.pagesOfKind[k]);
            separator = ",";
        }
        std::printf("\n");
    }
    return 0;
}

}  // namespace

// Exit status: 0 done; 1 the input cannot be converted (unreadable, truncated, damaged,
// unsupported); 2 usage; 75 the output cannot be written (full disk, I/O error: worth a retry);
// 130 and 143 after SIGINT and SIGTERM. On every failure no output file is left, and an existing
// output is untouched.
int main(int argc, char** argv) {
    pushpin::cache::installTemporaryFileCleanup();
    const Options o = parseArgs(argc, argv);
    try {
        return run(o);
    } catch (const pushpin::OutputError& e) {
        std::fprintf(stderr, "makebot: %s\n", e.what());
        return 75;
    } catch (const pushpin::Error& e) {
        std::fprintf(stderr, "makebot: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "makebot: %s -> %s: %s\n", o.input.c_str(), o.output.c_str(), e.what());
    }
    return 1;
}
