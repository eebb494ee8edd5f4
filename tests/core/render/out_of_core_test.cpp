// Out-of-core rendering (core/render/renderer.h with a MemoryBudget): tessellations made per tile
// on first need, once per shape whatever its instances, dropped under a tight cap and made again,
// the same image whatever the cap, thread count and tile size, every charge released, and a tile
// whose triangles cannot fit at all stopping the render with MemoryCapError.
#include "core/render/renderer.h"

#include "cache/error.h"
#include "cache/memory_budget.h"
#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_settings.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "tests/support/ma_preamble.h"
#include "tests/support/stored_grid.h"

#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

using cache::MemoryBudget;
using cache::MemoryCategory;

// A `columns` × `rows` grid of polygon spheres `spacing` radii apart, each its own shape with
// `subdivisions` steps around and up; the last shape also has a second instance behind the
// others. Seen by a perspective camera, lit by a directional light.
std::string sphereGrid(int columns, int rows, int subdivisions, double radius, double spacing) {
    std::string text = test::maPreamble(7) + R"(createNode transform -n "sun";
	setAttr ".r" -type "double3" -40 30 0;
createNode directionalLight -n "sunShape" -p "sun";
)" + test::greyShadingGroup();
    int n = 0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c, ++n) {
            const std::string id = std::to_string(n);
            const double x = (c - (columns - 1) * 0.5) * spacing * radius, y = (r - (rows - 1) * 0.5) * spacing * radius;
            text += "createNode transform -n \"ball" + id + "\";\n\tsetAttr \".t\" -type \"double3\" " +
                    std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(-0.3 * ((c + r) % 3)) + ";\n";
            text += "createNode mesh -n \"ball" + id + "Shape\" -p \"ball" + id + "\";\n";
            text += "createNode polySphere -n \"ballCreator" + id + "\";\n\tsetAttr \".r\" " + std::to_string(radius) +
                    ";\n\tsetAttr \".sa\" " + std::to_string(subdivisions) + ";\n\tsetAttr \".sh\" " +
                    std::to_string(subdivisions) + ";\n";
            text += "connectAttr \"ballCreator" + id + ".out\" \"ball" + id + "Shape.i\";\n";
            text += "connectAttr \"ball" + id + "Shape.iog\" \"greySG.dsm\" -na;\n";
        }
    const std::string last = std::to_string(n - 1);
    text += "createNode transform -n \"copy\";\n\tsetAttr \".t\" -type \"double3\" 0.5 0.2 -3;\n";
    text += "parent -s -nc -r -add \"|ball" + last + "|ball" + last + "Shape\" \"copy\";\n";
    text += "connectAttr \"ball" + last + "Shape.iog[1]\" \"greySG.dsm\" -na;\n";
    return text;
}

struct Grid {
    scene::Graph graph;
    scene::RenderSetup setup;
    scene::Evaluator ev;
    RenderSettings settings;
    FrameScene frameScene;
    RenderCamera camera;

    // `onDemand`: built as under a memory cap, with meshes evaluated again by each tessellation.
    Grid(int columns, int rows, int subdivisions, double radius, int width, int height, double spacing = 2.5,
         bool onDemand = false)
        : graph(scene::MaReader::readString(sphereGrid(columns, rows, subdivisions, radius, spacing), "grid.ma")),
          setup(scene::extractRenderSetup(graph)), ev(graph, 1.0) {
        settings.width = width;
        settings.height = height;
        settings.deviceAspectRatio = double(width) / height;
        settings.tileWidth = settings.tileHeight = 16;
        settings.forceTileSize = true;  // the tests that want the memory-driven plan turn it off
        if (onDemand) settings.maximumMemoryBytes = uint64_t(1) << 40;
        frameScene = buildFrameScene(ev, setup, settings);
        settings.maximumMemoryBytes = 0;
        camera = makeRenderCamera(ev, graph.dagPaths(graph.find("perspShape")).at(0), width, height,
                                  settings.deviceAspectRatio);
    }
    Framebuffer render(const RenderSettings& s, RenderStats& stats, MemoryBudget* budget = nullptr) const {
        RenderOptions options;
        options.memoryBudget = budget;
        return renderFrame(frameScene, camera, s, stats, options);
    }
    // Bytes of every shape's tessellation, each shape once.
    uint64_t allTessellationBytes() const {
        uint64_t bytes = 0;
        std::vector<const geom::GeometryHandle*> seen;
        for (const RenderObject& o : frameScene.objects) {
            if (std::find(seen.begin(), seen.end(), o.geometry.get()) != seen.end()) continue;
            seen.push_back(o.geometry.get());
            bytes += o.geometry->tessellate().bytes();
        }
        return bytes;
    }
};

// Room for the fragment and shading buffers of the busiest tile on each thread, which the
// renderer charges as they grow (a few hundred kilobytes for these scenes).
constexpr uint64_t kFragmentRoom = uint64_t(2) << 20;

bool sameImage(const Framebuffer& a, const Framebuffer& b) {
    return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
           std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

TEST(OutOfCore, EachShapeIsTessellatedOnceAndInstancesShareIt) {
    const Grid g(4, 3, 16, 0.6, 96, 64);
    ASSERT_EQ(g.frameScene.objects.size(), 13u);
    RenderSettings s = g.settings;
    s.numCpusToUse = 1;
    RenderStats stats;
    MemoryBudget budget;
    (void)g.render(s, stats, &budget);
    EXPECT_EQ(stats.tessellationShapes, 12u);
    EXPECT_EQ(stats.tessellationInstances, 13u);
    EXPECT_EQ(stats.tessellationsMade, 12u) << "the two instances of the last shape share one";
    EXPECT_EQ(stats.tessellationsEvicted, 0u);
    EXPECT_EQ(stats.tessellationsRecomputed, 0u);
    EXPECT_GT(stats.objectTileVisits, stats.tessellationInstances) << "spheres reach several 16x16 tiles";
    EXPECT_EQ(stats.trianglesMade, 12u * (2 * 16 * 16 - 2 * 16));
    EXPECT_EQ(budget.usedBytes(), 0u);
    EXPECT_EQ(budget.peakBytes(MemoryCategory::Tessellation),
              frameMemory(g.frameScene, g.camera, s, {}, 1).geometryBytes + g.allTessellationBytes())
        << "every tessellation charged once, with the objects' views";
}

TEST(OutOfCore, TightCapDropsAndRemakesTessellationsAndKeepsTheImage) {
    const Grid g(4, 3, 64, 0.6, 192, 128);
    RenderSettings s = g.settings;
    s.numCpusToUse = 1;  // one worker: the growth of its buffers is the same every run
    MemoryBudget unlimited;
    RenderStats freeStats;
    const Framebuffer free = g.render(s, freeStats, &unlimited);
    const FrameMemory need = frameMemory(g.frameScene, g.camera, s, {}, 1);
    const uint64_t growth = unlimited.peakBytes(MemoryCategory::Fragments) - need.tileBytes;
    // Room for the buffers, the making of one sphere (its mesh, made when a tile first needs it,
    // and working memory) and four spheres' triangles: enough for the shapes that reach one tile
    // (at most four), far from all twelve.
    const uint64_t cap = need.totalBytes() + growth + need.largestTransientBytes + 4 * need.largestTessellationBytes;
    ASSERT_LT(cap, need.totalBytes() + growth + g.allTessellationBytes() * 3 / 4);
    MemoryBudget budget(cap);
    RenderStats stats;
    const Framebuffer capped = g.render(s, stats, &budget);
    EXPECT_TRUE(sameImage(capped, free));
    EXPECT_GT(stats.tessellationsEvicted, 0u);
    EXPECT_GT(stats.tessellationsRecomputed, 0u);
    EXPECT_EQ(stats.tessellationsMade, 12u + stats.tessellationsRecomputed);
    EXPECT_LE(budget.peakBytes(), cap);
    EXPECT_EQ(budget.usedBytes(), 0u) << "charged equals released";
    EXPECT_EQ(stats.memoryCapBytes, cap);
    EXPECT_EQ(stats.memoryPeakCharged, budget.peakBytes());
}

TEST(OutOfCore, SameImageWithAnyThreadCountTileSizeAndCap) {
    const Grid g(3, 2, 20, 1.2, 160, 112);
    RenderStats stats;
    const Framebuffer reference = g.render(g.settings, stats);
    const FrameMemory need = frameMemory(g.frameScene, g.camera, g.settings, {}, 2);
    struct Case {
        int threads, tileWidth, tileHeight;  // 0 × 0: the memory-driven plan
        uint64_t extra;  // bytes beyond the buffers; 0: unlimited
    };
    const Case cases[] = {{1, 16, 16, 0}, {2, 16, 16, 0}, {2, 64, 64, 0}, {1, 23, 17, 0}, {2, 160, 112, 0},
                          {1, 16, 16, 5 * need.largestTessellationBytes}, {2, 16, 16, 5 * need.largestTessellationBytes},
                          {2, 23, 17, 6 * need.largestTessellationBytes},
                          {2, 16, 16, need.largestTransientBytes + 2 * need.largestTessellationBytes},
                          {1, 0, 0, 2 * kFragmentRoom + 5 * need.largestTessellationBytes},
                          {2, 0, 0, 2 * kFragmentRoom + 6 * need.largestTessellationBytes}};
    const Grid onDemand(3, 2, 20, 1.2, 160, 112, 2.5, true);
    ASSERT_FALSE(onDemand.frameScene.objects.at(0).geometry->keepsSource());
    // What the tiles of one fixed layout count is the same with or without a cap, whatever tiles
    // were given up and rendered again alone.
    std::map<std::tuple<const Grid*, int, int>, RenderStats> counted;
    for (const Case& c : cases)
        for (const Grid* grid : {&g, &onDemand}) {
            RenderSettings s = grid->settings;
            s.numCpusToUse = c.threads;
            s.forceTileSize = c.tileWidth > 0;
            s.tileWidth = c.tileWidth;
            s.tileHeight = c.tileHeight;
            const FrameMemory n = frameMemory(grid->frameScene, grid->camera, s, {}, c.threads);
            MemoryBudget budget(c.extra ? n.totalBytes() + kFragmentRoom + c.extra : 0);
            RenderStats st;
            const Framebuffer image = grid->render(s, st, &budget);
            EXPECT_TRUE(sameImage(image, reference)) << c.threads << " threads, " << c.tileWidth << "x" << c.tileHeight
                                                     << " tiles, " << c.extra << " bytes over the buffers"
                                                     << (grid == &onDemand ? ", meshes evaluated on demand" : "");
            EXPECT_EQ(budget.usedBytes(), 0u);
            if (c.tileWidth == 0) continue;
            const auto key = std::make_tuple(grid, c.tileWidth, c.tileHeight);
            if (!counted.count(key)) {
                counted[key] = st;
                continue;
            }
            const RenderStats& first = counted[key];
            EXPECT_EQ(st.trianglesRasterized, first.trianglesRasterized) << c.threads << " threads, " << c.tileWidth;
            EXPECT_EQ(st.fragments, first.fragments) << c.threads << " threads, " << c.tileWidth;
            EXPECT_EQ(st.surfaces, first.surfaces) << c.threads << " threads, " << c.tileWidth;
            EXPECT_EQ(st.objectTileVisits, first.objectTileVisits) << c.threads << " threads, " << c.tileWidth;
        }
}

// A sun, the grey shading group, `ground` (the transform "ground" with its mesh "groundShape"),
// that shape shown again under "again" (placed by `againLines`), and a sphere in front.
std::string groundScene(const std::string& ground, std::string_view againLines) {
    return test::maPreamble(7) + R"(createNode transform -n "sun";
	setAttr ".r" -type "double3" -40 30 0;
createNode directionalLight -n "sunShape" -p "sun";
)" + test::greyShadingGroup() +
           ground + "connectAttr \"groundShape.iog\" \"greySG.dsm\" -na;\ncreateNode transform -n \"again\";\n" +
           std::string(againLines) + R"(parent -s -nc -r -add "|ground|groundShape" "again";
connectAttr "groundShape.iog[1]" "greySG.dsm" -na;
createNode transform -n "ball";
	setAttr ".t" -type "double3" -0.8 0.3 1.5;
createNode mesh -n "ballShape" -p "ball";
createNode polySphere -n "ballCreator";
	setAttr ".r" 1.1;
connectAttr "ballCreator.out" "ballShape.i";
connectAttr "ballShape.iog" "greySG.dsm" -na;
)";
}

// A bumpy plane of 9,600 triangles (a point tweak keeps it from being made from its creator's
// counts), shown twice, tilted towards the camera (and turned by `turn` degrees) with a sphere in
// front of it; `againLines` place the second instance.
constexpr std::string_view kAgainTilted =
    "\tsetAttr \".t\" -type \"double3\" 1.5 -0.5 -2;\n\tsetAttr \".r\" -type \"double3\" 70 0 -10;\n";
std::string bumpyPlaneScene(double turn = 15.0, std::string_view againLines = kAgainTilted) {
    return groundScene(R"(createNode transform -n "ground";
	setAttr ".r" -type "double3" 60 0 )" + std::to_string(turn) + R"(;
createNode mesh -n "groundShape" -p "ground";
	setAttr ".pt[5]" -type "float3" 0 0.4 0;
	setAttr ".pt[700]" -type "float3" 0 -0.3 0;
createNode polyPlane -n "groundCreator";
	setAttr ".w" 9;
	setAttr ".h" 7;
	setAttr ".sw" 80;
	setAttr ".sh" 60;
connectAttr "groundCreator.out" "groundShape.i";
)",
                       againLines);
}

// 120 × 90 pixels in 16 × 16 tiles, for the ground scenes; `onDemand`: built as under a cap (no
// mesh kept), rendered without one.
struct GroundRender {
    scene::Graph graph;
    scene::RenderSetup setup;
    scene::Evaluator ev;
    RenderSettings settings;
    FrameScene scene;
    RenderCamera camera;
    GroundRender(const std::string& text, bool onDemand)
        : graph(scene::MaReader::readString(text, "ground.ma")), setup(scene::extractRenderSetup(graph)), ev(graph, 1.0) {
        settings.width = 120;
        settings.height = 90;
        settings.deviceAspectRatio = 120.0 / 90.0;
        settings.tileWidth = settings.tileHeight = 16;
        settings.forceTileSize = true;
        if (onDemand) settings.maximumMemoryBytes = uint64_t(1) << 40;
        scene = buildFrameScene(ev, setup, settings);
        settings.maximumMemoryBytes = 0;
        camera = makeRenderCamera(ev, graph.dagPaths(graph.find("perspShape")).at(0), 120, 90, 120.0 / 90.0);
    }
    // The scene with the ground's two instances (objects 0 and 1) given `ground` instead.
    FrameScene withGround(const std::shared_ptr<const geom::GeometryHandle>& ground) const {
        FrameScene out = scene;
        out.objects[0].geometry = out.objects[1].geometry = ground;
        return out;
    }
};

TEST(OutOfCore, WithoutACapADenseTileOfTheGridIsSplit) {
    // 811,200 triangles in a 48×32 frame: the one 64×64 tile of the grid would hold every
    // fragment. Without a cap it is split (to 32×32 at most here), the threads share the pieces,
    // and the image is the one the single forced tile gives.
    const Grid g(3, 2, 260, 1.2, 48, 32);
    RenderSettings one = g.settings;
    one.tileWidth = one.tileHeight = 64;
    RenderStats wholeStats;
    const Framebuffer whole = g.render(one, wholeStats);
    EXPECT_EQ(wholeStats.tiles, 1u);
    EXPECT_EQ(wholeStats.maxTileCost, 0.0);
    for (int threads : {1, 2}) {
        RenderSettings s = one;
        s.forceTileSize = false;
        s.numCpusToUse = threads;
        RenderStats st;
        TilePlan plan;
        RenderOptions options;
        options.tilePlan = &plan;
        const Framebuffer split = renderFrame(g.frameScene, g.camera, s, st, options);
        EXPECT_TRUE(sameImage(split, whole)) << threads << " threads";
        EXPECT_GT(st.tiles, 1u);
        EXPECT_EQ(st.tiles, plan.tiles.size());
        EXPECT_LE(st.tileMaxSize, 32);
        EXPECT_GT(st.maxTileCost, 0.0);
        EXPECT_DOUBLE_EQ(plan.maxTileCost, st.maxTileCost);
    }
    // A sparse frame keeps the grid: no 64×64 tile of it passes the limit.
    const Grid sparse(3, 2, 12, 1.2, 160, 112);
    RenderSettings s = sparse.settings;
    s.forceTileSize = false;
    s.tileWidth = s.tileHeight = 64;
    RenderStats st;
    sparse.render(s, st);
    EXPECT_EQ(st.tiles, planTiles({0, 0, 160, 112}, 64, 64).size());
}

// One render of the ground scene with its ground in pieces: threads, tile size, and the bytes the
// budget allows beyond the frame's buffers and the room left for fragments (0: no cap).
struct PiecedCase {
    int threads, tile;
    uint64_t extra;
    uint64_t fragmentRoom = kFragmentRoom;
};

// Renders `pieced` (g's scene with the ground given `pieces`) for each case and checks that the
// image is g's whole-ground image, that every charge is given back and the cap held, that without
// a cap each piece is made once for both instances, and that the triangles are the whole shape's.
// Returns each case's stats.
std::vector<RenderStats> expectPiecesRenderAsWhole(const GroundRender& g, const FrameScene& pieced,
                                                   const geom::GeometryHandle& pieces,
                                                   std::span<const PiecedCase> cases) {
    RenderStats wholeStats;
    const Framebuffer reference = renderFrame(g.scene, g.camera, g.settings, wholeStats);
    std::vector<RenderStats> out;
    for (const PiecedCase& c : cases) {
        SCOPED_TRACE(std::to_string(c.threads) + " threads, tiles of " + std::to_string(c.tile) + ", " +
                     std::to_string(c.extra) + " bytes over the buffers");
        RenderSettings s = g.settings;
        s.numCpusToUse = c.threads;
        s.tileWidth = s.tileHeight = c.tile;
        const FrameMemory n = frameMemory(pieced, g.camera, s, {}, c.threads);
        MemoryBudget budget(c.extra ? n.totalBytes() + c.fragmentRoom + c.extra : 0);
        RenderStats st;
        RenderOptions options;
        options.memoryBudget = &budget;
        const Framebuffer image = renderFrame(pieced, g.camera, s, st, options);
        EXPECT_TRUE(sameImage(image, reference));
        EXPECT_EQ(budget.usedBytes(), 0u);
        if (c.extra) {
            EXPECT_LE(budget.peakBytes(), budget.capBytes());
        } else {
            EXPECT_LE(st.tessellationsMade, pieces.pieceCount() + 1);
            EXPECT_EQ(st.tessellationsRecomputed, 0u);
        }
        EXPECT_EQ(st.triangles, wholeStats.triangles);
        out.push_back(st);
    }
    return out;
}

TEST(OutOfCore, AShapeInPiecesRendersAsItDoesWhole) {
    for (const bool onDemand : {false, true}) {
        SCOPED_TRACE(onDemand ? "meshes evaluated on demand" : "meshes kept");
        const GroundRender g(bumpyPlaneScene(), onDemand);
        const RenderSettings& settings = g.settings;
        const FrameScene& whole = g.scene;
        const RenderCamera& camera = g.camera;
        ASSERT_EQ(whole.objects.size(), 3u);
        // The plane's two instances share one handle; split it into pieces of at most 700 triangles.
        const std::shared_ptr<const geom::GeometryHandle> plane = whole.objects[0].geometry;
        ASSERT_EQ(whole.objects[1].geometry, plane);
        ASSERT_EQ(plane->triangleCount(), 9600u);
        EXPECT_EQ(plane->keepsSource(), !onDemand);
        ASSERT_EQ(plane->pieceCount(), 1u);
        const std::shared_ptr<const geom::GeometryHandle> pieces = plane->withPieces(700);
        ASSERT_GE(pieces->pieceCount(), 14u);
        const FrameScene pieced = g.withGround(pieces);

        const FrameMemory need = frameMemory(pieced, camera, settings, {}, 2);
        EXPECT_LT(need.largestTessellationBytes, plane->tessellationBytesEstimate() / 8);
        const PiecedCase cases[] = {
            {1, 16, 0},
            {2, 16, 0},
            {2, 37, 0},
            {1, 16, need.largestTransientBytes + 4 * need.largestTessellationBytes, kFragmentRoom / 2},
            {2, 23, need.largestTransientBytes + 6 * need.largestTessellationBytes + plane->meshMakingBytes()}};
        expectPiecesRenderAsWhole(g, pieced, *pieces, cases);
    }
}

// A NURBS torus of 11 divisions a span (8 × 4 spans: 7,744 triangle ids), shown twice, tilted
// towards the camera with a sphere in front of it.
std::string nurbsTorusScene() {
    return groundScene(R"(createNode transform -n "ground";
	setAttr ".r" -type "double3" 60 0 15;
	setAttr ".s" -type "double3" 2.5 2.5 2.5;
createNode nurbsSurface -n "groundShape" -p "ground";
	setAttr ".nu" 7;
	setAttr ".nv" 7;
createNode makeNurbTorus -n "groundCreator";
	setAttr ".hr" 0.4;
connectAttr "groundCreator.os" "groundShape.cr";
)",
                       kAgainTilted);
}

TEST(OutOfCore, ANurbsSurfaceInPiecesRendersAsItDoesWhole) {
    const GroundRender g(nurbsTorusScene(), false);
    const RenderSettings& settings = g.settings;
    const FrameScene& whole = g.scene;
    const RenderCamera& camera = g.camera;
    ASSERT_EQ(whole.objects.size(), 3u);
    const std::shared_ptr<const geom::GeometryHandle> torus = whole.objects[0].geometry;
    ASSERT_EQ(whole.objects[1].geometry, torus);
    ASSERT_FALSE(torus->isMesh());
    ASSERT_EQ(torus->triangleCount(), 7744u);
    ASSERT_EQ(torus->pieceCount(), 1u);
    const std::shared_ptr<const geom::GeometryHandle> pieces = torus->withPieces(300);
    ASSERT_GE(pieces->pieceCount(), 26u);
    const FrameScene pieced = g.withGround(pieces);

    const FrameMemory need = frameMemory(pieced, camera, settings, {}, 2);
    EXPECT_LT(need.largestTessellationBytes, torus->tessellationBytesEstimate() / 8);
    EXPECT_LT(need.largestTransientBytes, torus->tessellationWorkBytesEstimate() / 4);
    const PiecedCase cases[] = {
        {1, 16, 0},
        {2, 37, 0},
        {1, 16, need.largestTransientBytes + 4 * need.largestTessellationBytes, kFragmentRoom / 2},
        {2, 23, 2 * need.largestTransientBytes + 6 * need.largestTessellationBytes + (3u << 20)}};
    const std::vector<RenderStats> st = expectPiecesRenderAsWhole(g, pieced, *pieces, cases);
    // On one thread the tiles meet the pieces in one order: the cap holds a few at a time.
    EXPECT_GT(st[2].tessellationsEvicted, 0u);
}

TEST(OutOfCore, ATileThatMeetsMorePiecesThanTheCapHoldsCopiesTheirTriangles) {
    // The bumpy plane turned so that its rows of faces (and so its pieces) run up the screen: a
    // 16-pixel tile meets many pieces, and a small part of each.
    const std::string text = bumpyPlaneScene(95.0, "\tsetAttr \".t\" -type \"double3\" 30 0 0;\n");
    for (const bool onDemand : {false, true}) {
        SCOPED_TRACE(onDemand ? "meshes evaluated on demand" : "meshes kept");
        const GroundRender g(text, onDemand);
        RenderStats wholeStats;
        const Framebuffer reference = renderFrame(g.scene, g.camera, g.settings, wholeStats);
        const std::shared_ptr<const geom::GeometryHandle> plane = g.scene.objects[0].geometry;
        const std::shared_ptr<const geom::GeometryHandle> pieces = plane->withPieces(150);
        const FrameScene pieced = g.withGround(pieces);
        const FrameMemory n = frameMemory(pieced, g.camera, g.settings, {}, 1);
        // One thread: the smallest cap (to a kilobyte) that renders, with and without copies.
        auto renders = [&](uint64_t cap, bool copies, RenderStats& st, int threads = 1) {
            RenderSettings s = g.settings;
            s.numCpusToUse = threads;
            MemoryBudget budget(cap);
            RenderOptions options;
            options.memoryBudget = &budget;
            options.copyPinnedTriangles = copies;
            bool finished = true;
            try {
                const Framebuffer image = renderFrame(pieced, g.camera, s, st, options);
                EXPECT_TRUE(sameImage(image, reference)) << cap << " bytes, " << threads << " threads";
                EXPECT_EQ(st.triangles, wholeStats.triangles);
                EXPECT_LE(budget.peakBytes(), budget.capBytes());
                if (!copies) {
                    EXPECT_EQ(st.tileCopies, 0u);
                }
            } catch (const MemoryCapError&) {
                finished = false;
            }
            EXPECT_EQ(budget.usedBytes(), 0u);
            return finished;
        };
        auto smallestCap = [&](bool copies, int threads) {
            uint64_t lo = n.totalBytes(), hi = n.totalBytes() + kFragmentRoom + n.largestTransientBytes +
                                                200 * n.largestTessellationBytes + plane->meshMakingBytes();
            RenderStats st;
            EXPECT_TRUE(renders(hi, copies, st, threads));
            while (hi - lo > 1024) {
                const uint64_t mid = lo + (hi - lo) / 2;
                RenderStats at;
                (renders(mid, copies, at, threads) ? hi : lo) = mid;
            }
            return hi;
        };
        const uint64_t copying = smallestCap(true, 1), notCopying = smallestCap(false, 1);
        RenderStats st;
        EXPECT_TRUE(renders(copying, true, st));
        EXPECT_LT(copying, notCopying);
        EXPECT_GT(st.tileCopies, 0u);
        // Two threads: which tiles wait for the others to finish depends on timing, so the
        // smallest cap varies, but every render down to it gives the same image.
        (void)smallestCap(true, 2);
    }
}

TEST(OutOfCore, AStoredMeshInPiecesIsNeverMadeWhole) {
    // A stored 80 × 60 grid (9,601 faces) tilted towards the camera, shown twice, a sphere in front.
    const GroundRender g(groundScene(test::storedGridMesh("ground", 80, 60, "\".dsm\" 0;", false,
                                                          "\tsetAttr \".t\" -type \"double3\" -4 -2 0;\n"
                                                          "\tsetAttr \".r\" -type \"double3\" 60 0 15;\n"),
                                     "\tsetAttr \".t\" -type \"double3\" -2 -2.5 -2;\n"
                                     "\tsetAttr \".r\" -type \"double3\" 70 0 -10;\n"),
                         true);
    const RenderSettings& settings = g.settings;
    const FrameScene& whole = g.scene;
    const RenderCamera& camera = g.camera;
    ASSERT_EQ(whole.objects.size(), 3u);
    const std::shared_ptr<const geom::GeometryHandle> grid = whole.objects[0].geometry;
    ASSERT_EQ(whole.objects[1].geometry, grid);
    ASSERT_FALSE(grid->keepsSource());
    const std::shared_ptr<const geom::GeometryHandle> pieces = grid->withPieces(700);
    ASSERT_GE(pieces->pieceCount(), 14u);
    ASSERT_TRUE(pieces->makesPiecesAlone());
    // Making a piece needs its window, not the grid.
    for (size_t k = 0; k < pieces->pieceCount(); ++k) EXPECT_LT(pieces->pieceWorkBytesEstimate(k), grid->meshMakingBytes());
    const FrameScene pieced = g.withGround(pieces);

    RenderStats wholeStats;
    const Framebuffer reference = renderFrame(whole, camera, settings, wholeStats);
    EXPECT_GT(wholeStats.trianglesRasterized, 5000u);
    const FrameMemory need = frameMemory(pieced, camera, settings, {}, 2);
    for (const int threads : {1, 2}) {
        for (const uint64_t extra :
             {uint64_t(0), uint64_t(threads) * need.largestTransientBytes + 10 * need.largestTessellationBytes}) {
            RenderSettings s = settings;
            s.numCpusToUse = threads;
            const FrameMemory n = frameMemory(pieced, camera, s, {}, threads);
            MemoryBudget budget(extra ? n.totalBytes() + kFragmentRoom + extra : 0);
            RenderStats st;
            RenderOptions options;
            options.memoryBudget = &budget;
            const Framebuffer image = renderFrame(pieced, camera, s, st, options);
            EXPECT_TRUE(sameImage(image, reference)) << threads << " threads, " << extra << " bytes over the buffers";
            EXPECT_EQ(budget.usedBytes(), 0u);
            EXPECT_EQ(st.meshesMade, 0u);  // no piece needed the whole grid
            EXPECT_EQ(st.triangles, wholeStats.triangles);
        }
    }
}

TEST(OutOfCore, TileWhoseTrianglesCannotFitStopsTheRenderWithMemoryCapError) {
    // Two large spheres overlapping everywhere on screen: every tile needs both tessellations.
    const Grid g(2, 1, 40, 4.0, 48, 32, 0.3);
    const FrameMemory need = frameMemory(g.frameScene, g.camera, g.settings, {}, 1);
    RenderSettings s = g.settings;
    s.numCpusToUse = 1;
    // The buffers and the making of the largest shape fit (so the frame starts), two shapes do not.
    MemoryBudget budget(need.totalBytes() + need.largestTransientBytes + need.largestTessellationBytes +
                        need.largestTessellationBytes / 4);
    RenderStats stats;
    try {
        (void)g.render(s, stats, &budget);
        FAIL() << "expected MemoryCapError";
    } catch (const MemoryCapError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("tile at"), std::string::npos) << message;
        // What ran out of room: a sphere's triangles, or (once the tile copied the first sphere's
        // triangles to make room for the second) its fragments.
        EXPECT_TRUE(message.find("ball") != std::string::npos || message.find("its fragments") != std::string::npos)
            << message;
        EXPECT_NE(message.find("memory cap"), std::string::npos) << message;
    }
    EXPECT_EQ(budget.usedBytes(), 0u) << "charged equals released, also on failure";
    EXPECT_LE(budget.peakBytes(), budget.capBytes());
}

TEST(OutOfCore, CapBelowTheLargestShapeFailsBeforeAnyTile) {
    const Grid g(2, 1, 40, 1.0, 48, 32);
    const FrameMemory need = frameMemory(g.frameScene, g.camera, g.settings, {}, 1);
    RenderSettings s = g.settings;
    s.numCpusToUse = 1;
    MemoryBudget budget(need.totalBytes() + need.largestTessellationBytes / 2);
    RenderStats stats;
    try {
        (void)g.render(s, stats, &budget);
        FAIL() << "expected MemoryCapError";
    } catch (const MemoryCapError& e) {
        EXPECT_NE(std::string(e.what()).find("largest shape"), std::string::npos) << e.what();
    }
    EXPECT_EQ(stats.tiles, 0u);
    EXPECT_EQ(budget.usedBytes(), 0u);
}

}  // namespace
}  // namespace pushpin::render
