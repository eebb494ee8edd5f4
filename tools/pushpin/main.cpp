// pushpin: renders Maya ASCII scenes. This front end parses the command line, loads the scene and
// runs the requested job; every error ends here as one line on stderr and a non-zero exit.
#include "cache/error.h"
#include "core/scene/demo_scene.h"
#include "core/scene/ma_reader.h"
#include "core/scene/scene_info.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitInput = 2;

void printUsage(std::FILE* out) {
    std::fputs(
        "usage: pushpin [options] scene.ma\n"
        "       pushpin --demo [options]\n"
        "\n"
        "options:\n"
        "  --info          print a JSON report of the scene (nodes, shapes, cameras, lights,\n"
        "                  shading groups, render globals, unsupported nodes, warnings)\n"
        "  --frame F       evaluate the scene at frame F (default: the scene's current frame)\n"
        "  --demo          use the built-in demo scene (soft-spotlight lesson) instead of a file\n"
        "  --print-demo    write the demo scene's .ma text to stdout\n"
        "  --no-references do not load referenced files (file -r)\n"
        "  -h, --help      show this help\n"
        "  --version       print the version\n",
        out);
}

// One line, whatever the message holds, so scripts can read the first line of stderr.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

std::optional<double> parseNumber(std::string_view text) {
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

struct Options {
    bool info = false;
    bool demo = false;
    bool printDemo = false;
    bool loadReferences = true;
    std::optional<double> frame;
    std::string scene;
};

int run(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        std::string_view a = argv[i];
        auto needValue = [&](std::string_view flag) -> std::string_view {
            if (i + 1 >= argc) throw pushpin::Error("option " + std::string(flag) + " needs a value");
            return argv[++i];
        };
        if (a == "-h" || a == "--help") {
            printUsage(stdout);
            return 0;
        } else if (a == "--version") {
            std::puts("pushpin 0.1.0");
            return 0;
        } else if (a == "--info") {
            opt.info = true;
        } else if (a == "--demo") {
            opt.demo = true;
        } else if (a == "--print-demo") {
            opt.printDemo = true;
        } else if (a == "--no-references") {
            opt.loadReferences = false;
        } else if (a == "--frame") {
            std::string_view v = needValue(a);
            opt.frame = parseNumber(v);
            if (!opt.frame) throw pushpin::Error("option --frame: '" + std::string(v) + "' is not a finite number");
        } else if (a.size() > 1 && a[0] == '-') {
            throw pushpin::Error("unknown option '" + std::string(a) + "' (see pushpin --help)");
        } else {
            if (!opt.scene.empty()) throw pushpin::Error("more than one scene given: '" + opt.scene + "' and '" + std::string(a) + "'");
            opt.scene = std::string(a);
        }
    }

    if (opt.printDemo) {
        std::string_view text = pushpin::scene::demoSceneText();
        std::fwrite(text.data(), 1, text.size(), stdout);
        return 0;
    }
    if (opt.demo && !opt.scene.empty()) throw pushpin::Error("give either --demo or a scene file, not both");
    if (!opt.demo && opt.scene.empty()) {
        printUsage(stderr);
        return kExitUsage;
    }
    if (!opt.info) throw pushpin::Error("no job given: use --info to report on the scene");

    pushpin::scene::ReadOptions readOptions;
    readOptions.loadReferences = opt.loadReferences;
    pushpin::scene::Graph graph =
        opt.demo ? pushpin::scene::MaReader::readString(pushpin::scene::demoSceneText(),
                                                         std::string(pushpin::scene::kDemoSceneName), readOptions)
                 : pushpin::scene::MaReader::readFile(opt.scene, readOptions);
    double frame = opt.frame ? *opt.frame : pushpin::scene::sceneCurrentFrame(graph);
    std::string json = pushpin::scene::sceneInfoJson(graph, frame);
    std::fwrite(json.data(), 1, json.size(), stdout);
    std::fflush(stdout);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const pushpin::scene::ParseError& e) {
        std::fprintf(stderr, "%s\n", oneLine(e.what()).c_str());
        return kExitInput;
    } catch (const pushpin::Error& e) {
        std::fprintf(stderr, "pushpin: %s\n", oneLine(e.what()).c_str());
        return kExitInput;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "pushpin: out of memory\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pushpin: internal error: %s\n", oneLine(e.what()).c_str());
        return 4;
    }
}
