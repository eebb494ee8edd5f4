// The memory cap of a frame (core/render/renderer.h frameMemory, renderFrame with a MemoryBudget;
// render_settings.h memoryCap): the sizes charged, a frame the cap cannot hold refused before any
// large allocation with pushpin::MemoryCapError, a cap that fits giving the same image as no cap,
// and every byte charged released again.
#include "core/render/frame_memory.h"
#include "core/render/renderer.h"

#include "cache/error.h"
#include "cache/memory_budget.h"
#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_settings.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "tests/support/ma_preamble.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

using cache::MemoryBudget;
using cache::MemoryCategory;

// A grey polyCube turned towards the camera and lit by a point light.
const std::string kScene = test::maPreamble(10) + R"(createNode transform -n "box";
	setAttr ".r" -type "double3" 30 40 0;
createNode mesh -n "boxShape" -p "box";
createNode polyCube -n "boxCreator";
connectAttr "boxCreator.out" "boxShape.i";
)" + test::greyShadingGroup() + R"(connectAttr "boxShape.iog" "greySG.dsm" -na;
createNode transform -n "bulb";
	setAttr ".t" -type "double3" 3 4 5;
createNode pointLight -n "bulbShape" -p "bulb";
)";

// The scene built once; cameras are made per test at the size asked for.
struct Frame {
    scene::Graph graph = scene::MaReader::readString(kScene, "memory.ma");
    scene::RenderSetup setup = scene::extractRenderSetup(graph);
    scene::Evaluator ev{graph, 1.0};
    RenderSettings settings;
    FrameScene frameScene;

    Frame(int width, int height) {
        settings.width = width;
        settings.height = height;
        settings.deviceAspectRatio = double(width) / height;
        frameScene = buildFrameScene(ev, setup, settings);
    }
    RenderCamera camera() {
        return makeRenderCamera(ev, graph.dagPaths(graph.find("perspShape")).at(0), settings.width, settings.height,
                                settings.deviceAspectRatio);
    }
};

// The process's peak resident set (VmHWM), in bytes; 0 where /proc does not say.
uint64_t peakResidentBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
    return 0;
}

// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        ::setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (m_old) ::setenv(m_name, m_old->c_str(), 1);
        else ::unsetenv(m_name);
    }

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

TEST(FrameMemory, LayoutIsTheRegionAndTheContrastMargins) {
    Frame f(64, 48);
    RenderSettings& s = f.settings;
    FrameLayout l = frameLayout(f.frameScene, f.camera(), s);
    EXPECT_EQ(l.region.x0, 0);
    EXPECT_EQ(l.region.y0, 0);
    EXPECT_EQ(l.region.x1, 64);
    EXPECT_EQ(l.region.y1, 48);
    // Maya's region counts rows from the bottom, inclusive; it is clamped to the frame.
    s.useRenderRegion = true;
    s.left = 10;
    s.rght = 19;
    s.bot = 5;
    s.top = 14;
    l = frameLayout(f.frameScene, f.camera(), s);
    EXPECT_EQ(l.region.x0, 10);
    EXPECT_EQ(l.region.x1, 20);
    EXPECT_EQ(l.region.y0, 48 - 1 - 14);
    EXPECT_EQ(l.region.y1, 48 - 5);
    s.rght = 500;
    EXPECT_EQ(frameLayout(f.frameScene, f.camera(), s).region.x1, 64);
    s.useRenderRegion = false;
    // Adaptive shading (and its margins) only at the Highest level with more maximum samples.
    s.edgeAntiAliasing = 0;
    s.shadingSamples = 1;
    s.maxShadingSamples = 1;
    EXPECT_FALSE(frameLayout(f.frameScene, f.camera(), s).adaptive);
    s.maxShadingSamples = 8;
    l = frameLayout(f.frameScene, f.camera(), s);
    EXPECT_TRUE(l.adaptive);
    EXPECT_EQ(l.marginLeft, 2);
    EXPECT_EQ(l.marginRight, 1);
    EXPECT_EQ(l.marginTop, 1);
    EXPECT_EQ(l.marginBottom, 0);
    s.edgeAntiAliasing = 1;
    l = frameLayout(f.frameScene, f.camera(), s);
    EXPECT_FALSE(l.adaptive);
    EXPECT_EQ(l.marginLeft + l.marginRight + l.marginTop + l.marginBottom, 0);
}

TEST(FrameMemory, BytesAndCapsAreWrittenAsUsersGiveThem) {
    EXPECT_EQ(formatBytes(uint64_t(310) << 20), "310.0 MB");
    EXPECT_EQ(formatBytes((uint64_t(43) << 30) / 2), "21.5 GB");
    EXPECT_EQ(formatCap(uint64_t(2048) << 20), "2048 MB");
    EXPECT_EQ(formatCap((uint64_t(1) << 20) + (uint64_t(1) << 19)), "1.5 MB");
}

TEST(FrameMemory, CountsTheFramebufferAndTheWritersCopyPerPixel) {
    Frame f(32768, 32768);
    const RenderCamera cam = f.camera();
    const uint64_t pixels = uint64_t(32768) * 32768;
    EXPECT_EQ(imageOutputBytes(32768, 32768), pixels * 5 * sizeof(float));
    EXPECT_EQ(frameMemory(f.frameScene, cam, f.settings, {}, 1).framebufferBytes, pixels * (4 + 5) * sizeof(float));
    f.settings.depth = true;
    EXPECT_EQ(frameMemory(f.frameScene, cam, f.settings, {}, 1).framebufferBytes, pixels * (4 + 1 + 5) * sizeof(float));
    // Tile buffers grow with the thread count; geometry with the scene.
    const FrameMemory one = frameMemory(f.frameScene, cam, f.settings, {}, 1);
    const FrameMemory four = frameMemory(f.frameScene, cam, f.settings, {}, 4);
    EXPECT_GT(four.tileBytes, one.tileBytes);
    EXPECT_GT(one.geometryBytes, 0u);
    // The box comes straight from its creator: its mesh is made when a tile first needs it, so
    // nothing stays resident; making its tessellation needs the mesh and the working memory,
    // charged while it is made, whatever the threads.
    ASSERT_EQ(f.frameScene.objects.size(), 1u);
    EXPECT_FALSE(f.frameScene.objects[0].geometry->keepsSource());
    const geom::GeometryHandle& h = *f.frameScene.objects[0].geometry;
    EXPECT_EQ(one.sourceBytes, 0u);
    EXPECT_EQ(four.sourceBytes, 0u);
    EXPECT_EQ(one.largestTransientBytes, h.meshMakingBytes() + h.tessellationWorkBytesEstimate());
    EXPECT_EQ(four.largestTransientBytes, h.meshMakingBytes() + h.tessellationWorkBytesEstimate());
    EXPECT_GT(h.meshMakingBytes(), h.sourceBytes());
    EXPECT_EQ(one.totalBytes(), one.framebufferBytes + one.tileBytes + one.geometryBytes + one.sourceBytes);
}

TEST(FrameMemory, UnderACapMeshesAreEvaluatedOnDemandAndChargedWhileTessellated) {
    Frame f(64, 48);
    f.settings.maximumMemoryBytes = uint64_t(512) << 20;
    f.frameScene = buildFrameScene(f.ev, f.setup, f.settings);
    ASSERT_EQ(f.frameScene.objects.size(), 1u);
    const geom::GeometryHandle& h = *f.frameScene.objects[0].geometry;
    EXPECT_FALSE(h.keepsSource());
    EXPECT_GT(h.sourceBytes(), 0u);
    const RenderCamera cam = f.camera();
    const FrameMemory need = frameMemory(f.frameScene, cam, f.settings, {}, 3);
    EXPECT_EQ(need.sourceBytes, 0u);
    EXPECT_EQ(need.largestTransientBytes, h.meshMakingBytes() + h.tessellationWorkBytesEstimate());
    // Evaluated again, the mesh tessellates exactly as the kept one does.
    RenderSettings free = f.settings;
    free.maximumMemoryBytes = 0;
    const FrameScene kept = buildFrameScene(f.ev, f.setup, free);
    const geom::Tessellation a = h.tessellate(), b = kept.objects[0].geometry->tessellate();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.corners, b.corners);
    EXPECT_EQ(a.neighbors, b.neighbors);
    RenderStats s1, s2;
    const Framebuffer capped = renderFrame(f.frameScene, cam, f.settings, s1);
    const Framebuffer whole = renderFrame(kept, cam, free, s2);
    EXPECT_EQ(std::memcmp(capped.rgba.data(), whole.rgba.data(), whole.rgba.size() * sizeof(float)), 0);
}

// With several shapes the frame holds no room for their meshes up front: the largest need while
// one is tessellated must fit, and each tessellation charges its own need while it is made.
TEST(FrameMemory, TheLargestNeedWhileTessellatingMustFitBesideTheFrame) {
    std::string text = test::maPreamble(10) + test::greyShadingGroup();
    for (int i = 0; i < 3; ++i) {
        const std::string n = std::to_string(i), steps = std::to_string(2 + 6 * i);
        text += "createNode transform -n \"box" + n + "\";\n\tsetAttr \".t\" -type \"double3\" " + std::to_string(i - 1) +
                " 0 0;\ncreateNode mesh -n \"box" + n + "Shape\" -p \"box" + n + "\";\ncreateNode polyCube -n \"box" + n +
                "Creator\";\n\tsetAttr \".sw\" " + steps + ";\n\tsetAttr \".sh\" " + steps + ";\n\tsetAttr \".sd\" " +
                steps + ";\nconnectAttr \"box" + n + "Creator.out\" \"box" + n + "Shape.i\";\nconnectAttr \"box" + n +
                "Shape.iog\" \"greySG.dsm\" -na;\n";
    }
    text += "createNode transform -n \"again\";\nparent -s -nc -r -add \"|box2|box2Shape\" \"again\";\n"
            "connectAttr \"box2Shape.iog[1]\" \"greySG.dsm\" -na;\n";
    scene::Graph graph = scene::MaReader::readString(text, "boxes.ma");
    const scene::RenderSetup setup = scene::extractRenderSetup(graph);
    scene::Evaluator ev(graph, 1.0);
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.maximumMemoryBytes = uint64_t(512) << 20;
    const FrameScene fs = buildFrameScene(ev, setup, settings);
    ASSERT_EQ(fs.objects.size(), 4u);
    std::vector<uint64_t> transient;
    for (size_t i = 0; i < 3; ++i) {
        const geom::GeometryHandle& h = *fs.objects[i].geometry;
        EXPECT_FALSE(h.keepsSource());
        transient.push_back(h.meshMakingBytes() + h.tessellationWorkBytesEstimate());
    }
    EXPECT_EQ(fs.objects[3].geometry, fs.objects[2].geometry);
    ASSERT_LT(transient[0], transient[1]);
    ASSERT_LT(transient[1], transient[2]);
    const RenderCamera cam = makeRenderCamera(ev, graph.dagPaths(graph.find("perspShape")).at(0), 64, 48, 64.0 / 48);
    for (int threads : {1, 2, 8}) {
        const FrameMemory need = frameMemory(fs, cam, settings, {}, threads);
        EXPECT_EQ(need.sourceBytes, 0u);
        EXPECT_EQ(need.largestTransientBytes, transient[2]);
    }
    // Rendered under a cap the three need between them, the geometry charged while tessellating
    // comes and goes, and nothing stays charged afterwards.
    MemoryBudget budget(uint64_t(512) << 20);
    RenderOptions options;
    options.memoryBudget = &budget;
    RenderStats stats;
    (void)renderFrame(fs, cam, settings, stats, options);
    EXPECT_GE(budget.snapshot().categoryPeakBytes[size_t(MemoryCategory::Geometry)], transient[2]);
    EXPECT_EQ(budget.usedBytes(), 0u);
}

// The loaded scene's stored values are charged to the cap before any frame, and the frame's
// message then names what is already in use.
TEST(FrameMemory, TheScenesStoredValuesCountAgainstTheCap) {
    RenderSettings settings;
    settings.maximumMemoryBytes = uint64_t(1) << 20;
    MemoryBudget budget(uint64_t(1) << 20);
    try {
        (void)chargeScene(budget, uint64_t(3) << 20, settings);
        ADD_FAILURE() << "3 MB of stored values fit under a 1 MB cap";
    } catch (const MemoryCapError& e) {
        EXPECT_EQ(std::string(e.what()), "the loaded scene holds 3.0 MB, over the memory cap of 1 MB (-mm)");
    }
    EXPECT_EQ(budget.usedBytes(), 0u);
    {
        const cache::MemoryCharge held = chargeScene(budget, 300 << 10, settings);
        EXPECT_EQ(budget.usedBytes(), uint64_t(300) << 10);
        EXPECT_EQ(budget.snapshot().categoryBytes[size_t(MemoryCategory::Scene)], uint64_t(300) << 10);
        Frame f(64, 48);
        f.settings.maximumMemoryBytes = settings.maximumMemoryBytes;
        RenderOptions options;
        options.memoryBudget = &budget;
        RenderStats stats;
        const Framebuffer image = renderFrame(f.frameScene, f.camera(), f.settings, stats, options);
        EXPECT_EQ(image.width, 64);
        EXPECT_EQ(budget.usedBytes(), uint64_t(300) << 10);
    }
    EXPECT_EQ(budget.usedBytes(), 0u);
}

TEST(FrameMemory, FrameOverTheCapFailsAtOnceWithNothingAllocated) {
    Frame f(32768, 32768);
    const RenderCamera cam = f.camera();
    MemoryBudget budget(uint64_t(2048) << 20);
    RenderOptions options;
    options.memoryBudget = &budget;
    RenderStats stats;
    const uint64_t residentBefore = peakResidentBytes();
    const auto t0 = std::chrono::steady_clock::now();
    try {
        (void)renderFrame(f.frameScene, cam, f.settings, stats, options);
        ADD_FAILURE() << "a 32768x32768 frame was rendered under a 2048 MB cap";
    } catch (const MemoryCapError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("the 32768x32768 frame needs 36.0 GB of buffers"), std::string::npos) << message;
        EXPECT_NE(message.find("over the memory cap of 2048 MB"), std::string::npos) << message;
        EXPECT_EQ(e.capBytes(), uint64_t(2048) << 20);
        EXPECT_GT(e.neededBytes(), e.capBytes());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 1.0);
    // Nothing was charged, so nothing was held, and the process never touched gigabytes.
    EXPECT_EQ(budget.usedBytes(), 0u);
    EXPECT_EQ(budget.peakBytes(), 0u);
    EXPECT_EQ(stats.tiles, 0u);
    EXPECT_LT(peakResidentBytes() - residentBefore, uint64_t(256) << 20);
}

TEST(FrameMemory, MaximumMemoryBytesIsTheCapWithoutABudget) {
    Frame f(32768, 32768);
    const RenderCamera cam = f.camera();
    f.settings.maximumMemoryBytes = uint64_t(2048) << 20;
    RenderStats stats;
    try {
        (void)renderFrame(f.frameScene, cam, f.settings, stats);
        ADD_FAILURE() << "rendered over the -mm cap";
    } catch (const MemoryCapError& e) {
        EXPECT_NE(std::string(e.what()).find("over the memory cap of 2048 MB (-mm)"), std::string::npos) << e.what();
    }
}

TEST(FrameMemory, SlurmMemoryPerNodeIsTheCapWhenNoneIsGiven) {
    Frame f(640, 480);
    const RenderCamera cam = f.camera();
    RenderStats stats;
    {
        ScopedEnv env("SLURM_MEM_PER_NODE", "1");  // 1 MiB: far less than a 640x480 frame
        EXPECT_EQ(memoryCapBytes(f.settings), uint64_t(1) << 20);
        try {
            (void)renderFrame(f.frameScene, cam, f.settings, stats);
            ADD_FAILURE() << "rendered over the scheduler's cap";
        } catch (const MemoryCapError& e) {
            EXPECT_NE(std::string(e.what()).find("over the memory cap of 1 MB ($SLURM_MEM_PER_NODE)"), std::string::npos)
                << e.what();
        }
    }
    ScopedEnv env("SLURM_MEM_PER_NODE", "4096");
    EXPECT_NO_THROW((void)renderFrame(f.frameScene, cam, f.settings, stats));
}

TEST(FrameMemory, CapThatFitsGivesTheSameImageAndReleasesEveryCharge) {
    Frame f(64, 48);
    f.settings.depth = true;
    const RenderCamera cam = f.camera();
    RenderStats stats;
    const Framebuffer free = renderFrame(f.frameScene, cam, f.settings, stats);

    const int threads = 2;
    f.settings.numCpusToUse = threads;
    const FrameMemory need = frameMemory(f.frameScene, cam, f.settings, {}, threads);
    uint64_t tessellations = 0;  // what the tessellation cache will hold: every shape once
    for (const RenderObject& o : f.frameScene.objects) tessellations += o.geometry->tessellate().bytes();
    ASSERT_GT(need.largestTessellationBytes, 0u);
    // What the frame charges up front, the tessellations, and room for the tile buffers' growth.
    const uint64_t growth = uint64_t(1) << 20;
    MemoryBudget budget(need.totalBytes() + tessellations + growth);
    RenderOptions options;
    options.memoryBudget = &budget;
    const Framebuffer capped = renderFrame(f.frameScene, cam, f.settings, stats, options);
    EXPECT_EQ(stats.tessellationsEvicted, 0u);

    ASSERT_EQ(capped.rgba.size(), free.rgba.size());
    ASSERT_EQ(capped.depth.size(), free.depth.size());
    EXPECT_EQ(std::memcmp(capped.rgba.data(), free.rgba.data(), free.rgba.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(capped.depth.data(), free.depth.data(), free.depth.size() * sizeof(float)), 0);
    // Charged equals released: nothing is held after the render, and the peaks show what was.
    EXPECT_EQ(budget.usedBytes(), 0u);
    EXPECT_GE(budget.peakBytes(), need.totalBytes() + tessellations);
    EXPECT_LE(budget.peakBytes(), budget.capBytes());
    EXPECT_EQ(budget.peakBytes(MemoryCategory::Framebuffer), need.framebufferBytes);
    // Geometry: the kept sources, and while a tessellation was made its working memory and itself.
    EXPECT_GE(budget.peakBytes(MemoryCategory::Geometry), need.sourceBytes + need.largestTransientBytes);
    EXPECT_GE(budget.peakBytes(MemoryCategory::Fragments), need.tileBytes);
    EXPECT_LE(budget.peakBytes(MemoryCategory::Fragments), need.tileBytes + growth);
    EXPECT_EQ(budget.peakBytes(MemoryCategory::Tessellation), need.geometryBytes + tessellations);
    EXPECT_EQ(stats.memoryPeakCharged, budget.peakBytes());
    EXPECT_EQ(stats.memoryCapBytes, budget.capBytes());
    for (size_t c = 0; c < cache::kMemoryCategoryCount; ++c) EXPECT_EQ(budget.usedBytes(MemoryCategory(c)), 0u);
}

TEST(FrameMemory, OneByteShortFailsAndLeavesNothingCharged) {
    Frame f(64, 48);
    const RenderCamera cam = f.camera();
    f.settings.numCpusToUse = 1;
    const FrameMemory need = frameMemory(f.frameScene, cam, f.settings, {}, 1);
    MemoryBudget budget(need.totalBytes() - 1);
    RenderOptions options;
    options.memoryBudget = &budget;
    RenderStats stats;
    EXPECT_THROW((void)renderFrame(f.frameScene, cam, f.settings, stats, options), MemoryCapError);
    EXPECT_EQ(budget.usedBytes(), 0u);  // the categories charged before the refusal were given back
    EXPECT_EQ(stats.tiles, 0u);

    // Memory others hold counts against the cap too, and the message says so.
    MemoryBudget shared(need.totalBytes());
    shared.charge(MemoryCategory::Textures, 4096);
    options.memoryBudget = &shared;
    try {
        (void)renderFrame(f.frameScene, cam, f.settings, stats, options);
        ADD_FAILURE() << "rendered over a shared cap";
    } catch (const MemoryCapError& e) {
        EXPECT_NE(std::string(e.what()).find("already in use"), std::string::npos) << e.what();
    }
    EXPECT_EQ(shared.usedBytes(), 4096u);
}

}  // namespace
}  // namespace pushpin::render
