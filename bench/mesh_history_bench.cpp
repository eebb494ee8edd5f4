// bench/mesh_history_bench.cpp: the construction-history operations that rebuild real shapes
// (core/geom/poly_extrude.h, poly_extrude_edge.h, poly_split.h, poly_split_ring.h, poly_bevel.h,
// poly_merge.h, poly_dissolve.h, subdivide.h), each on a mesh large enough that per-face cost
// shows, with faces (or points) per second counters; then, when the real scenes are present, the
// time to evaluate every mesh shape of each of them.
//
//   mesh_history_bench [--benchmark_* flags]
//
// Micro-benchmarks use generated primitives (polyPlane, polyCylinder, polySphere grids); the
// scene figure walks ../shared/scenes/ma-projects and ma-public from the working folder, or the
// folder in PUSHPIN_SCENES.
#include <benchmark/benchmark.h>

#include "core/geom/poly_bevel.h"
#include "core/geom/poly_dissolve.h"
#include "core/geom/poly_extrude.h"
#include "core/geom/poly_extrude_edge.h"
#include "core/geom/poly_merge.h"
#include "core/geom/poly_primitives.h"
#include "core/geom/poly_split.h"
#include "core/geom/poly_split_ring.h"
#include "core/geom/subdivide.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/mesh_eval.h"
#include "core/scene/scene_info.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace pushpin;
namespace fs = std::filesystem;

geom::Mesh plane(int n) {
    geom::PolyPlaneParams p;
    p.subdivisionsWidth = n;
    p.subdivisionsHeight = n;
    return *geom::makePolyPlane(p);
}

void BM_ExtrudeAllFacesTogether(benchmark::State& state) {
    const geom::Mesh base = plane(int(state.range(0)));
    geom::ExtrudeFacesParams p;
    p.faces.assign(base.faceCount(), true);
    p.localTranslate = {0, 0, 0.1};
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::extrudeFaces(m, p));
    }
    state.counters["faces/s"] = benchmark::Counter(double(base.faceCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ExtrudeAllFacesTogether)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_ExtrudeEveryFaceApart(benchmark::State& state) {
    const geom::Mesh base = plane(int(state.range(0)));
    geom::ExtrudeFacesParams p;
    p.faces.assign(base.faceCount(), true);
    p.keepFacesTogether = false;
    p.localTranslate = {0, 0, 0.1};
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::extrudeFaces(m, p));
    }
    state.counters["faces/s"] = benchmark::Counter(double(base.faceCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ExtrudeEveryFaceApart)->Arg(100)->Arg(300)->Arg(600)->Unit(benchmark::kMillisecond);

void BM_SplitRingRoundACylinder(benchmark::State& state) {
    geom::PolyCylinderParams cp;
    cp.subdivisionsAxis = int(state.range(0));
    cp.subdivisionsHeight = 100;
    geom::Mesh base = *geom::makePolyCylinder(cp);
    geom::completeEdges(base, true);
    // The vertical edges of the lowest band form a closed ring.
    geom::SplitRingParams p;
    p.edges.assign(base.edges.size(), false);
    for (size_t e = 0; e < base.edges.size(); ++e) {
        const glm::vec3 a = base.points[base.edges[e].v0], b = base.points[base.edges[e].v1];
        p.edges[e] = std::abs(a.x - b.x) < 1e-6f && std::abs(a.z - b.z) < 1e-6f && std::min(a.y, b.y) < -0.99f;
    }
    size_t ringPoints = 0;
    for (auto _ : state) {
        geom::Mesh m = base;
        geom::SplitRingResult r;
        benchmark::DoNotOptimize(geom::splitRing(m, p, &r));
        ringPoints = r.newPoints;
    }
    state.counters["ring"] = double(ringPoints);
    state.counters["faces/s"] = benchmark::Counter(double(base.faceCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SplitRingRoundACylinder)->Arg(200)->Arg(2000)->Unit(benchmark::kMillisecond);

void BM_SplitAcrossAGrid(benchmark::State& state) {
    // One cut straight across an n × n grid, through the middle of every edge it crosses.
    const int n = int(state.range(0));
    geom::Mesh base = plane(n);
    geom::completeEdges(base, true);
    geom::SplitParams p;
    const float across = 0.5f / float(n);  // inside the row of quads just above z = 0
    for (size_t e = 0; e < base.edges.size(); ++e) {
        const glm::vec3 a = base.points[base.edges[e].v0], b = base.points[base.edges[e].v1];
        if (std::abs(a.x - b.x) < 1e-6f && std::min(a.z, b.z) < across && std::max(a.z, b.z) > across)
            p.points.push_back({geom::SplitPoint::Kind::Edge, int64_t(e), 0.5, {}});
    }
    std::sort(p.points.begin(), p.points.end(), [&](const geom::SplitPoint& x, const geom::SplitPoint& y) {
        return base.points[base.edges[size_t(x.index)].v0].x < base.points[base.edges[size_t(y.index)].v0].x;
    });
    size_t cut = 0;
    for (auto _ : state) {
        geom::Mesh m = base;
        geom::SplitResult r;
        benchmark::DoNotOptimize(geom::splitFaces(m, p, &r));
        cut = r.newFaces;
    }
    state.counters["faces cut"] = double(cut);
    state.counters["faces/s"] = benchmark::Counter(double(base.faceCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SplitAcrossAGrid)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_ExtrudeEveryEdge(benchmark::State& state) {
    geom::Mesh base = plane(int(state.range(0)));
    geom::completeEdges(base, true);
    geom::ExtrudeEdgesParams p;
    p.edges.assign(base.edges.size(), true);
    p.localTranslate = {0, 0, 0.1};
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::extrudeEdges(m, p));
    }
    state.counters["edges/s"] = benchmark::Counter(double(base.edges.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ExtrudeEveryEdge)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_BevelEveryEdge(benchmark::State& state) {
    geom::PolySphereParams sp;
    sp.subdivisionsAxis = int(state.range(0));
    sp.subdivisionsHeight = int(state.range(0)) / 2;
    geom::Mesh base = *geom::makePolySphere(sp);
    geom::completeEdges(base, true);
    geom::BevelParams p;
    p.edges.assign(base.edges.size(), true);
    p.offset = 0.2;
    p.offsetAsFraction = true;
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::bevelEdges(m, p));
    }
    state.counters["edges/s"] = benchmark::Counter(double(base.edges.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BevelEveryEdge)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_MergeCoincidentPoints(benchmark::State& state) {
    // A grid of separate quads: every inner point four times over.
    const int n = int(state.range(0));
    geom::Mesh base;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t b = uint32_t(base.points.size());
            base.points.push_back({float(x), 0, float(y)});
            base.points.push_back({float(x + 1), 0, float(y)});
            base.points.push_back({float(x + 1), 0, float(y + 1)});
            base.points.push_back({float(x), 0, float(y + 1)});
            base.addFace({b, b + 3, b + 2, b + 1});
        }
    geom::MergeVerticesParams p;
    p.points.assign(base.points.size(), true);
    p.distance = 1e-3;
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::mergeVertices(m, p));
    }
    state.counters["points/s"] = benchmark::Counter(double(base.points.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_MergeCoincidentPoints)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_DissolveEveryOtherEdge(benchmark::State& state) {
    geom::Mesh base = plane(int(state.range(0)));
    geom::completeEdges(base, true);
    std::vector<bool> edges(base.edges.size(), false);
    for (size_t e = 0; e < edges.size(); e += 7) edges[e] = true;
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::dissolveEdges(m, edges));
    }
    state.counters["faces/s"] = benchmark::Counter(double(base.faceCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DissolveEveryOtherEdge)->Arg(100)->Arg(300)->Unit(benchmark::kMillisecond);

void BM_SubdivideSphere(benchmark::State& state) {
    geom::PolySphereParams sp;
    sp.subdivisionsAxis = 200;
    sp.subdivisionsHeight = 100;
    const geom::Mesh base = *geom::makePolySphere(sp);
    geom::SubdivideParams p;
    p.levels = int(state.range(0));
    size_t faces = 0;
    for (auto _ : state) {
        geom::Mesh m = base;
        benchmark::DoNotOptimize(geom::subdivideMesh(m, p));
        faces = m.faceCount();
    }
    state.counters["out faces/s"] = benchmark::Counter(double(faces), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SubdivideSphere)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// Every mesh shape of every real scene, evaluated as --info and a render evaluate them.
void realScenes() {
    const char* env = std::getenv("PUSHPIN_SCENES");
    const fs::path root = env ? fs::path(env) : fs::path("../shared/scenes");
    if (!fs::exists(root)) {
        std::printf("real scenes: %s not found; skipped\n", root.c_str());
        return;
    }
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file() && e.path().extension() == ".ma") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::printf("\n%-48s %8s %8s %10s %10s\n", "scene (mesh shapes, all evaluated)", "shapes", "faces", "eval ms", "load ms");
    double total = 0;
    for (const fs::path& file : files) {
        const auto t0 = std::chrono::steady_clock::now();
        scene::Graph g;
        try {
            g = scene::MaReader::readFile(file);
        } catch (const std::exception&) {
            continue;
        }
        const auto t1 = std::chrono::steady_clock::now();
        scene::Evaluator ev(g, scene::sceneCurrentFrame(g));
        size_t shapes = 0, faces = 0;
        for (scene::NodeId n = 0; n < g.size(); ++n) {
            if (g.node(n).type != "mesh") continue;
            const scene::MeshEvaluation e = scene::evaluateMeshShape(ev, n);
            ++shapes;
            if (e.mesh) faces += e.mesh->faceCount();
        }
        const auto t2 = std::chrono::steady_clock::now();
        const double evalMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
        total += evalMs;
        if (evalMs >= 20.0)
            std::printf("%-48.48s %8zu %8zu %10.1f %10.1f\n", file.filename().c_str(), shapes, faces, evalMs,
                        std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::printf("%zu scenes, every mesh shape evaluated in %.1f ms in all (scenes under 20 ms not listed)\n",
                files.size(), total);
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    realScenes();
    return 0;
}
