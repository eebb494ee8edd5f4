// bench/tile_cost_bench.cpp: what one crossing costs in tile buffers, setting by setting, against
// the model the memory-driven tile plan is built on (renderer.h tileBytesPerCrossing).
//
//   tile_cost_bench [--quick] [--tile N] [--objects N] [--seed S]
//
// A crossing is one triangle meeting one scanline of a tile, weighed by the fragments it leaves
// there; a tile's cost is its most expensive scanline (tile_plan.h tileCost) and the plan allows
// cost × tile height × tileBytesPerCrossing(settings) bytes of tile buffers per thread. The bench
// builds a scene of polygon and NURBS spheres of many sizes in front of one camera (640×360), then
// for each setting that changes what a crossing holds renders every tile of an N×N grid on its
// own (a render region of one fixed tile, one thread, under a budget that records what is
// charged) and reads what the tile buffers grew to beyond the per-thread share charged with the
// frame (the "fragments" category's peak less frameMemory's tileBytes): the plan's limit is on
// that growth, since the frame's own charges come off the budget before it is planned.
// Per setting it prints the model's bytes per crossing, the measured bytes per crossing (min /
// median / max over the tiles with any cost), their largest ratio to the model (at most 1: the
// plan's limit holds in every tile) and the time per crossing. Two more columns split the ratio:
// the fragments a tile really made per crossing its cost estimated (the estimate's accuracy), and
// the bytes the buffers grew by per fragment made (what a fragment holds, with the buffers' spare
// capacity). Settings: edge anti-aliasing Low … Highest, shading samples, adaptive shading up to
// maxShadingSamples, the 3×3 B-spline and a 3-pixel box filter. Motion blur and ray tracing,
// which the model will have to name, are not rendered yet and are not measured.
#include "bench/bench_support.h"

#include "cache/memory_budget.h"
#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_settings.h"
#include "core/render/renderer.h"
#include "core/render/tile_plan.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace pushpin;

std::string sceneText(int objects, unsigned seed) {
    std::string t = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "shot";
	setAttr ".t" -type "double3" 0 0 60;
createNode camera -n "shotShape" -p "shot";
	setAttr ".rnd" yes;
createNode transform -n "sun";
	setAttr ".r" -type "double3" -40 30 0;
createNode directionalLight -n "sunShape" -p "sun";
createNode lambert -n "grey";
createNode shadingEngine -n "greySG";
connectAttr "greySG.pa" ":renderPartition.st" -na;
connectAttr "grey.oc" "greySG.ss";
createNode blinn -n "shiny";
	setAttr ".c" -type "float3" 0.8 0.3 0.2;
createNode shadingEngine -n "shinySG";
connectAttr "shinySG.pa" ":renderPartition.st" -na;
connectAttr "shiny.oc" "shinySG.ss";
)";
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < objects; ++i) {
        const std::string n = std::to_string(i);
        const double z = -40.0 * u(rng), spread = 0.9 * (60.0 - z) * 0.35;
        const double x = (2 * u(rng) - 1) * spread * 16 / 9, y = (2 * u(rng) - 1) * spread;
        const double r = 0.5 + 4.0 * u(rng) * u(rng);
        char pos[160];
        std::snprintf(pos, sizeof pos, "\tsetAttr \".t\" -type \"double3\" %.4f %.4f %.4f;\n", x, y, z);
        const std::string sg = (i % 3 == 0) ? "shinySG" : "greySG";
        t += "createNode transform -n \"obj" + n + "\";\n" + pos;
        if (i % 4 == 3) {
            t += "createNode nurbsSurface -n \"objShape" + n + "\" -p \"obj" + n + "\";\n";
            t += "createNode makeNurbSphere -n \"make" + n + "\";\n\tsetAttr \".r\" " + std::to_string(r) + ";\n";
            t += "connectAttr \"make" + n + ".os\" \"objShape" + n + ".cr\";\n";
        } else {
            const int around = 8 + int(u(rng) * 56), height = 6 + int(u(rng) * 40);
            t += "createNode mesh -n \"objShape" + n + "\" -p \"obj" + n + "\";\n";
            t += "createNode polySphere -n \"make" + n + "\";\n\tsetAttr \".r\" " + std::to_string(r) + ";\n";
            t += "\tsetAttr \".sa\" " + std::to_string(around) + ";\n\tsetAttr \".sh\" " + std::to_string(height) + ";\n";
            t += "connectAttr \"make" + n + ".out\" \"objShape" + n + ".i\";\n";
        }
        t += "connectAttr \"objShape" + n + ".iog\" \"" + sg + ".dsm\" -na;\n";
    }
    return t;
}

struct Variant {
    const char* name;
    int eaa, ss, mss;
    bool filter;
    int filterType;
    double filterWidth;
};

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[size_t(q * double(v.size() - 1) + 0.5)];
}

}  // namespace

int main(int argc, char** argv) {
    int tile = 32, objects = 400;
    unsigned seed = 7;
    bool quick = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "tile_cost_bench: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--quick") quick = true;
        else if (a == "--tile") tile = std::max(16, std::atoi(next()));
        else if (a == "--objects") objects = std::max(1, std::atoi(next()));
        else if (a == "--seed") seed = unsigned(std::atoi(next()));
        else {
            std::fprintf(stderr, "usage: tile_cost_bench [--quick] [--tile N] [--objects N] [--seed S]\n");
            return 2;
        }
    }
    if (quick) objects = std::min(objects, 60);
    const int width = quick ? 320 : 640, height = quick ? 180 : 360;

    const std::string text = sceneText(objects, seed);
    scene::Graph graph = scene::MaReader::readString(text, "tile_cost.ma", {});
    const scene::RenderSetup setup = scene::extractRenderSetup(graph);
    scene::Evaluator ev(graph, 1.0);
    std::vector<std::string> notes;
    render::RenderSettings base = render::readRenderSettings(ev, setup, notes);
    base.width = width;
    base.height = height;
    base.deviceAspectRatio = double(width) / height;
    base.numCpusToUse = 1;
    base.forceTileSize = true;
    base.tileWidth = base.tileHeight = tile;
    base.useRenderRegion = true;
    const render::FrameScene frameScene = render::buildFrameScene(ev, setup, base);
    const render::RenderCamera camera =
        render::makeRenderCamera(ev, graph.dagPaths(graph.find("shotShape")).at(0), width, height, base.deviceAspectRatio);
    uint64_t triangles = 0;
    for (const render::RenderObject& o : frameScene.objects) triangles += o.geometry->triangleCount();
    std::printf("## Tile buffers per crossing\n\n%zu objects, %llu triangles, %dx%d, tiles of %dx%d rendered one at a "
                "time on one thread (seed %u)\n\n",
                frameScene.objects.size(), (unsigned long long)triangles, width, height, tile, tile, seed);

    const Variant variants[] = {
        {"eaa 3 (Low), ss 1", 3, 1, 1, false, 0, 0},
        {"eaa 2 (Medium), ss 1", 2, 1, 1, false, 0, 0},
        {"eaa 1 (High), ss 1", 1, 1, 1, false, 0, 0},
        {"eaa 0 (Highest), ss 1, mss 1", 0, 1, 1, false, 0, 0},
        {"eaa 3, ss 4", 3, 4, 4, false, 0, 0},
        {"eaa 0, ss 1, mss 8 (adaptive)", 0, 1, 8, false, 0, 0},
        {"eaa 0, ss 2, mss 16 (adaptive)", 0, 2, 16, false, 0, 0},
        {"eaa 3, 3x3 B-spline filter", 3, 1, 1, true, 6, 0},
        {"eaa 3, box filter 3 px", 3, 1, 1, true, 0, 3.0},
    };
    std::printf("| setting | model B/crossing | measured B/crossing (min / median / max) | measured / model (max) | "
                "fragments per estimated crossing (median / max) | B per fragment (median / max) | tiles | "
                "ns per crossing |\n|---|---|---|---|---|---|---|---|\n");
    for (const Variant& v : variants) {
        render::RenderSettings s = base;
        s.edgeAntiAliasing = v.eaa;
        s.shadingSamples = v.ss;
        s.maxShadingSamples = v.mss;
        s.useMultiPixelFilter = v.filter;
        s.pixelFilterType = v.filterType;
        if (v.filterWidth > 0) s.pixelFilterWidthX = s.pixelFilterWidthY = v.filterWidth;
        const double model = double(render::tileBytesPerCrossing(s));
        std::vector<double> perCrossing, ratio, fragmentsPerCrossing, perFragment;
        double seconds = 0.0, crossings = 0.0;
        for (int ty = 0; ty + tile <= height; ty += tile) {
            for (int tx = 0; tx + tile <= width; tx += tile) {
                s.left = tx;
                s.rght = tx + tile - 1;
                s.top = height - 1 - ty;  // Maya's regions count rows from the bottom
                s.bot = height - tile - ty;
                cache::MemoryBudget budget(uint64_t(16) << 30);
                render::TilePlan plan;
                render::RenderOptions options;
                options.memoryBudget = &budget;
                options.tilePlan = &plan;
                render::RenderStats stats;
                const render::FrameMemory need = render::frameMemory(frameScene, camera, s, options, 1);
                const auto t0 = std::chrono::steady_clock::now();
                (void)render::renderFrame(frameScene, camera, s, stats, options);
                seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                if (plan.cost.size() != 1 || !(plan.cost[0] > 0.0)) continue;
                const double tileCrossings = plan.cost[0] * tile;
                // What the worker's buffers grew to beyond the share charged with the frame: the
                // plan's limit is on this growth (the frame's charges come off the budget first).
                const uint64_t peak = budget.peakBytes(cache::MemoryCategory::Fragments);
                const double held = peak > need.tileBytes ? double(peak - need.tileBytes) : 0.0;
                crossings += tileCrossings;
                perCrossing.push_back(held / tileCrossings);
                fragmentsPerCrossing.push_back(double(stats.fragments) / tileCrossings);
                if (stats.fragments > 0 && held > 0.0) perFragment.push_back(held / double(stats.fragments));
                ratio.push_back(held / tileCrossings / model);
            }
        }
        std::printf("| %s | %.0f | %.0f / %.0f / %.0f | %.2f | %.2f / %.2f | %.0f / %.0f | %zu | %.0f |\n", v.name, model,
                    quantile(perCrossing, 0.0), quantile(perCrossing, 0.5), quantile(perCrossing, 1.0), quantile(ratio, 1.0),
                    quantile(fragmentsPerCrossing, 0.5), quantile(fragmentsPerCrossing, 1.0), quantile(perFragment, 0.5),
                    quantile(perFragment, 1.0), perCrossing.size(), crossings > 0 ? 1e9 * seconds / crossings : 0.0);
    }
    return 0;
}
