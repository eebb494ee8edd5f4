// botinfo: prints the levels, page counts and sizes of a BOT texture, as text or JSON, and with
// --verify reads every page and checks its checksum.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cache/error.h"
#include "texture/bot_file.h"

namespace {

using namespace pushpin;
using namespace pushpin::texture;

const char* kUsage = "usage: botinfo [--json] [--verify] file.bot\n";

struct LevelFigures {
    uint64_t pages = 0, storedBytes = 0, rawBytes = 0;
};

std::string jsonEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += c;
        }
    }
    return out;
}

int run(const std::string& path, bool json, bool verify) {
    const auto file = BotFile::open(path);
    const BotHeader& h = file->header();
    std::vector<LevelFigures> figures(h.levels.size());
    LevelFigures total;
    uint64_t pagesOfKind[kBotPageKinds] = {};
    for (uint32_t l = 0; l < h.levels.size(); ++l) {
        const BotLevel& lv = h.levels[l];
        for (uint32_t py = 0; py < lv.pagesY; ++py)
            for (uint32_t px = 0; px < lv.pagesX; ++px) {
                const BotPageEntry& e = file->pageEntry(file->pageIndex(l, px, py));
                figures[l].pages += 1;
                figures[l].storedBytes += e.storedBytes;
                figures[l].rawBytes += file->pageRawBytes();
                ++pagesOfKind[unsigned(e.kind)];
            }
        total.pages += figures[l].pages;
        total.storedBytes += figures[l].storedBytes;
        total.rawBytes += figures[l].rawBytes;
    }

    uint64_t badPages = 0;
    if (verify) {
        const int fd = ::open(path.c_str(), O_RDONLY);
        if (fd < 0) throw IoError(path, "cannot open", errno);
        std::vector<float> page(kPageSizeTexels * kPageSizeTexels * h.channels);
        for (uint32_t l = 0; l < h.levels.size(); ++l)
            for (uint32_t py = 0; py < h.levels[l].pagesY; ++py)
                for (uint32_t px = 0; px < h.levels[l].pagesX; ++px) {
                    try {
                        file->readPage(fd, l, px, py, page.data());
                    } catch (const FormatError& e) {
                        std::fprintf(stderr, "botinfo: %s\n", e.what());
                        ++badPages;
                    }
                }
        ::close(fd);
    }

    auto ratio = [](const LevelFigures& f) { return f.rawBytes ? double(f.storedBytes) / double(f.rawBytes) : 0.0; };
    if (json) {
        std::printf("{\n  \"file\": \"%s\",\n  \"fileBytes\": %llu,\n  \"width\": %u,\n  \"height\": %u,\n"
                    "  \"channels\": %u,\n  \"pixelType\": \"%s\",\n  \"colorSpace\": \"%s\",\n"
                    "  \"wrapS\": \"%s\",\n  \"wrapT\": \"%s\",\n  \"pageFilter\": \"%s\",\n"
                    "  \"version\": %u,\n  \"bands\": %llu,\n"
                    "  \"dictionaryBytes\": %u,\n  \"pagesOfKind\": {\"raw\": %llu, \"frame\": %llu, \"block\": %llu, "
                    "\"literals\": %llu, \"rans\": %llu, \"constant\": %llu},\n  \"levels\": [\n",
                    jsonEscape(path).c_str(), (unsigned long long)file->fileBytes(), h.width, h.height, h.channels,
                    pixelTypeName(h.pixelType), colorSpaceName(h.colorSpace), wrapModeName(h.wrapS),
                    wrapModeName(h.wrapT), pageFilterName(file->pageFilter()), file->version(),
                    (unsigned long long)file->bandCount(), file->dictionaryBytes(),
                    (unsigned long long)pagesOfKind[0], (unsigned long long)pagesOfKind[1],
                    (unsigned long long)pagesOfKind[2], (unsigned long long)pagesOfKind[3],
                    (unsigned long long)pagesOfKind[4], (unsigned long long)pagesOfKind[5]);
        for (size_t l = 0; l < h.levels.size(); ++l) {
            const BotLevel& lv = h.levels[l];
            std::printf("    {\"level\": %zu, \"width\": %u, \"height\": %u, \"pagesX\": %u, \"pagesY\": %u, "
                        "\"pages\": %llu, \"compressedBytes\": %llu, \"uncompressedBytes\": %llu, \"ratio\": %.4f}%s\n",
                        l, lv.width, lv.height, lv.pagesX, lv.pagesY, (unsigned long long)figures[l].pages,
                        (unsigned long long)figures[l].storedBytes, (unsigned long long)figures[l].rawBytes,
                        ratio(figures[l]), l + 1 < h.levels.size() ? "," : "");
        }
        std::printf("  ],\n  \"pages\": %llu,\n  \"compressedBytes\": %llu,\n  \"uncompressedBytes\": %llu,\n"
                    "  \"ratio\": %.4f",
                    (unsigned long long)total.pages, (unsigned long long)total.storedBytes,
                    (unsigned long long)total.rawBytes, ratio(total));
        if (verify) std::printf(",\n  \"verified\": %s,\n  \"badPages\": %llu", badPages ? "false" : "true",
                                (unsigned long long)badPages);
        std::printf("\n}\n");
    } else {
        std::printf("%s: %ux%u, %u channels, %s, %s, wrap %s,%s, %zu levels, %llu bytes, dictionary %u bytes\n",
                    path.c_str(), h.width, h.height, h.channels, pixelTypeName(h.pixelType),
                    colorSpaceName(h.colorSpace), wrapModeName(h.wrapS), wrapModeName(h.wrapT), h.levels.size(),
                    (unsigned long long)file->fileBytes(), file->dictionaryBytes());
        if (file->version() == 3)
            std::printf("version 3, %llu bands, first band's page filter %s; pages stored raw %llu, rANS %llu, "
                        "constant %llu\n",
                        (unsigned long long)file->bandCount(), pageFilterName(file->pageFilter()),
                        (unsigned long long)pagesOfKind[0], (unsigned long long)pagesOfKind[4],
                        (unsigned long long)pagesOfKind[5]);
        else
            std::printf("version 2, page filter %s; pages stored raw %llu, as zstd frames %llu, blocks %llu, "
                        "literals %llu\n",
                        pageFilterName(file->pageFilter()), (unsigned long long)pagesOfKind[0],
                        (unsigned long long)pagesOfKind[1], (unsigned long long)pagesOfKind[2],
                        (unsigned long long)pagesOfKind[3]);
        std::printf("%5s %13s %11s %8s %14s %14s %7s\n", "level", "size", "pages", "count", "compressed", "uncompressed",
                    "ratio");
        for (size_t l = 0; l < h.levels.size(); ++l) {
            const BotLevel& lv = h.levels[l];
            const std::string size = std::to_string(lv.width) + "x" + std::to_string(lv.height);
            const std::string pages = std::to_string(lv.pagesX) + "x" + std::to_string(lv.pagesY);
            std::printf("%5zu %13s %11s %8llu %14llu %14llu %7.3f\n", l, size.c_str(), pages.c_str(),
                        (unsigned long long)figures[l].pages, (unsigned long long)figures[l].storedBytes,
                        (unsigned long long)figures[l].rawBytes, ratio(figures[l]));
        }
        std::printf("%5s %13s %11s %8llu %14llu %14llu %7.3f\n", "total", "", "", (unsigned long long)total.pages,
                    (unsigned long long)total.storedBytes, (unsigned long long)total.rawBytes, ratio(total));
        if (verify)
            std::printf("verify: %llu of %llu pages bad\n", (unsigned long long)badPages, (unsigned long long)total.pages);
    }
    return badPages ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    bool json = false, verify = false;
    std::string path;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--json") {
            json = true;
        } else if (a == "--verify") {
            verify = true;
        } else if (a == "-h" || a == "--help") {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (a.size() > 1 && a[0] == '-') {
            std::fprintf(stderr, "botinfo: unknown option %s\n%s", a.c_str(), kUsage);
            return 2;
        } else if (path.empty()) {
            path = a;
        } else {
            std::fprintf(stderr, "botinfo: more than one file given\n%s", kUsage);
            return 2;
        }
    }
    if (path.empty()) {
        std::fprintf(stderr, "%s", kUsage);
        return 2;
    }
    try {
        return run(path, json, verify);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "botinfo: %s\n", e.what());
        return 1;
    }
}
