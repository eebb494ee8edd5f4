// Whole-frame tests of the renderer: analytic shading and coverage, determinism across threads
// and tiles, adaptive shading, culling and clipping, transparency, the default light, and every
// public scene.
#include "core/render/renderer.h"

#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/render_settings.h"
#include "core/render/tile_plan.h"
#include "core/scene/demo_scene.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"
#include "tests/support/ma_corpus.h"
#include "tests/support/ma_preamble.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace pushpin;

struct Rendered {
    render::Framebuffer image;
    render::RenderStats stats;
    std::vector<uint8_t> adaptive;
};

// Everything a render needs, kept alive together.
struct Scene {
    scene::Graph graph;
    double frame = 1.0;
    scene::RenderSetup setup;
    render::RenderSettings settings;

    explicit Scene(const std::string& text, const std::string& name = "test.ma")
        : graph(scene::MaReader::readString(text, name)) {
        frame = scene::sceneCurrentFrame(graph);
        setup = scene::extractRenderSetup(graph);
        scene::Evaluator ev(graph, frame);
        std::vector<std::string> notes;
        settings = render::readRenderSettings(ev, setup, notes);
    }

    // Renders the first renderable camera (or the camera named).
    Rendered render(const render::RenderSettings& s, const std::string& cameraName = {}, bool skipOccluded = true) const {
        scene::Evaluator ev(graph, frame);
        render::FrameScene fs = render::buildFrameScene(ev, setup, s);
        const scene::CameraInfo* cam = nullptr;
        for (const scene::CameraInfo& c : setup.cameras)
            if (cameraName.empty() ? c.renderable : c.transformName == cameraName) {
                cam = &c;
                break;
            }
        EXPECT_NE(cam, nullptr);
        render::RenderCamera camera = render::makeRenderCamera(ev, cam->path, s.width, s.height, s.deviceAspectRatio);
        Rendered r;
        render::RenderOptions options;
        options.adaptiveMask = &r.adaptive;
        options.skipOccluded = skipOccluded;
        r.image = render::renderFrame(fs, camera, s, r.stats, options);
        return r;
    }
};

std::string header() {
    return "//Maya ASCII 2018 scene\n"
           "requires maya \"2018\";\n"
           "currentUnit -l centimeter -a degree -t film;\n";
}

// An orthographic camera at z = 10 looking down −Z, `width` scene units across.
std::string orthoCamera(double width) {
    return "createNode transform -n \"cam\";\n"
           "\tsetAttr \".t\" -type \"double3\" 0 0 10;\n"
           "createNode camera -n \"camShape\" -p \"cam\";\n"
           "\tsetAttr \".rnd\" yes;\n"
           "\tsetAttr \".o\" yes;\n"
           "\tsetAttr \".ow\" " + std::to_string(width) + ";\n";
}

std::string resolution(int w, int h) {
    return "select -ne :defaultResolution;\n"
           "\tsetAttr \".w\" " + std::to_string(w) + ";\n"
           "\tsetAttr \".h\" " + std::to_string(h) + ";\n"
           "\tsetAttr \".dar\" " + std::to_string(double(w) / h) + ";\n";
}

// ---------------------------------------------------------------- analytic shading

TEST(Renderer, LambertSphereUnderDirectionalLightMatchesClosedForm) {
    std::string text = header() + orthoCamera(2.5) +
                       "createNode transform -n \"ball\";\n"
                       "createNode mesh -n \"ballShape\" -p \"ball\";\n"
                       "createNode polySphere -n \"polySphere1\";\n"
                       "\tsetAttr \".r\" 1;\n"
                       "\tsetAttr \".sa\" 160;\n"
                       "\tsetAttr \".sh\" 80;\n"
                       "createNode transform -n \"sun\";\n"
                       "\tsetAttr \".r\" -type \"double3\" -35 25 0;\n"
                       "createNode directionalLight -n \"sunShape\" -p \"sun\";\n"
                       "\tsetAttr \".in\" 1.5;\n"
                       "connectAttr \"polySphere1.out\" \"ballShape.i\";\n"
                       "connectAttr \"ballShape.iog\" \":initialShadingGroup.dsm\" -na;\n" +
                       resolution(160, 160);
    Scene sc(text);
    render::RenderSettings s = sc.settings;
    s.edgeAntiAliasing = 0;
    s.shadingSamples = 16;
    s.maxShadingSamples = 16;
    Rendered r = sc.render(s);

    // Closed form: lambert1 (color 0.5, diffuse 0.8) under a directional light of intensity 1.5;
    // the direction toward the light is the light's local +Z in world space.
    scene::Evaluator ev(sc.graph, sc.frame);
    glm::dmat4 lightWorld = ev.worldMatrix(sc.graph.dagPaths(sc.graph.find("sunShape"))[0]);
    glm::dvec3 toLight = glm::normalize(glm::dvec3(lightWorld * glm::dvec4(0, 0, 1, 0)));
    const double albedo = 0.5 * 0.8 * 1.5;
    double errSum = 0.0, refSum = 0.0;
    int pixels = 0;
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x) {
            // Pixel footprint in camera/world space (camera at the origin in x, y).
            double cx = (x + 0.5) / 160.0 * 2.5 - 1.25, cy = 1.25 - (y + 0.5) / 160.0 * 2.5;
            if (cx * cx + cy * cy > 0.9 * 0.9) continue;  // interior pixels only
            double ref = 0.0;
            const int k = 8;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    double px = cx + ((i + 0.5) / k - 0.5) * 2.5 / 160.0;
                    double py = cy - ((j + 0.5) / k - 0.5) * 2.5 / 160.0;
                    glm::dvec3 n(px, py, std::sqrt(1.0 - px * px - py * py));
                    ref += albedo * std::max(0.0, glm::dot(n, toLight));
                }
            ref /= k * k;
            const float* p = r.image.pixel(x, y);
            for (int c = 0; c < 3; ++c) errSum += std::fabs(p[c] - ref);
            refSum += 3 * ref;
            ++pixels;
            EXPECT_FLOAT_EQ(p[3], 1.0f);
        }
    ASSERT_GT(pixels, 10000);
    double relativeMae = errSum / refSum;
    RecordProperty("relativeMeanAbsoluteError", std::to_string(relativeMae));
    std::printf("Lambert sphere: mean absolute error %.5f%% of the mean value over %d interior pixels\n",
                100.0 * relativeMae, pixels);
    EXPECT_LT(relativeMae, 0.005) << "mean absolute error relative to the mean value";
}

// ---------------------------------------------------------------- analytic coverage

// Exact area of a convex polygon clipped to the unit-square pixel at (px, py).
double clippedArea(std::vector<glm::dvec2> poly, double px, double py) {
    auto clip = [&](auto inside, auto cross) {
        std::vector<glm::dvec2> out;
        for (size_t i = 0; i < poly.size(); ++i) {
            glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
            if (inside(a)) out.push_back(a);
            if (inside(a) != inside(b)) out.push_back(cross(a, b));
        }
        poly = out;
    };
    auto lerpX = [](double x) {
        return [x](glm::dvec2 a, glm::dvec2 b) { double t = (x - a.x) / (b.x - a.x); return a + (b - a) * t; };
    };
    auto lerpY = [](double y) {
        return [y](glm::dvec2 a, glm::dvec2 b) { double t = (y - a.y) / (b.y - a.y); return a + (b - a) * t; };
    };
    clip([&](glm::dvec2 p) { return p.x >= px; }, lerpX(px));
    clip([&](glm::dvec2 p) { return p.x <= px + 1; }, lerpX(px + 1));
    clip([&](glm::dvec2 p) { return p.y >= py; }, lerpY(py));
    clip([&](glm::dvec2 p) { return p.y <= py + 1; }, lerpY(py + 1));
    double a = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
        a += p.x * q.y - q.x * p.y;
    }
    return std::fabs(a) * 0.5;
}

TEST(Renderer, BoxFilteredAlphaOfAPolygonIsItsExactArea) {
    // A unit square plane (one quad, two triangles of one surface), rotated about the view axis,
    // under an orthographic camera: in raster space it stays an exact square.
    for (double angle : {0.0, 17.0, 33.3, 45.0, 71.9}) {
        for (double size : {0.6, 7.3}) {
            std::string text = header() + orthoCamera(4.0) +
                               "createNode transform -n \"card\";\n"
                               "\tsetAttr \".t\" -type \"double3\" 0.123 -0.071 0;\n"
                               "\tsetAttr \".r\" -type \"double3\" 90 0 " + std::to_string(angle) + ";\n"
                               "\tsetAttr \".s\" -type \"double3\" " + std::to_string(size / 16.0) + " 1 " +
                               std::to_string(size / 16.0) + ";\n"
                               "createNode mesh -n \"cardShape\" -p \"card\";\n"
                               "createNode polyPlane -n \"polyPlane1\";\n"
                               "\tsetAttr \".sw\" 1;\n"
                               "\tsetAttr \".sh\" 1;\n"
                               "connectAttr \"polyPlane1.out\" \"cardShape.i\";\n"
                               "connectAttr \"cardShape.iog\" \":initialShadingGroup.dsm\" -na;\n" +
                               resolution(64, 64);
            Scene sc(text);
            for (int eaa : {3, 0}) {
                render::RenderSettings s = sc.settings;
                s.edgeAntiAliasing = eaa;
                s.useMultiPixelFilter = false;
                Rendered r = sc.render(s);
                // The square's corners in raster space: 64 px span 4 units → 16 px per unit.
                double half = size / 32.0, a = angle * M_PI / 180.0;  // size pixels = size/16 units
                std::vector<glm::dvec2> square;
                for (auto [u, v] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}) {
                    double wx = 0.123 + half * (u * std::cos(a) - v * std::sin(a));
                    double wy = -0.071 + half * (u * std::sin(a) + v * std::cos(a));
                    square.push_back({(wx + 2.0) * 16.0, (2.0 - wy) * 16.0});
                }
                double worst = 0.0;
                int wx = -1, wy = -1;
                for (int y = 0; y < 64; ++y)
                    for (int x = 0; x < 64; ++x) {
                        double e = std::fabs(r.image.pixel(x, y)[3] - clippedArea(square, x, y));
                        if (e > worst) worst = e, wx = x, wy = y;
                    }
                if (worst >= 1e-4)
                    ADD_FAILURE() << "pixel " << wx << "," << wy << ": alpha " << r.image.pixel(wx, wy)[3] << ", exact "
                                  << clippedArea(square, wx, wy);
                EXPECT_LT(worst, 1e-4) << "angle " << angle << " size " << size << " eaa " << eaa;
            }
        }
    }
}

// ---------------------------------------------------------------- determinism

// `settings` at 160×120 with adaptive shading at the Highest level, one to eight samples.
render::RenderSettings adaptiveAt160x120(render::RenderSettings s) {
    s.width = 160;
    s.height = 120;
    s.edgeAntiAliasing = 0;
    s.shadingSamples = 1;
    s.maxShadingSamples = 8;
    return s;
}

TEST(Renderer, SameImageWithOneOrTwoThreadsAndAnyTileSize) {
    Scene sc(std::string(scene::demoSceneText()), "softSpotlight.ma");
    for (int filter : {6, 2}) {
        render::RenderSettings s = sc.settings;
        s.width = 160;
        s.height = 120;
        s.edgeAntiAliasing = 0;
        s.shadingSamples = 1;
        s.maxShadingSamples = 8;
        s.useMultiPixelFilter = true;
        s.pixelFilterType = filter;
        s.numCpusToUse = 1;
        s.tileWidth = s.tileHeight = 64;
        Rendered a = sc.render(s);
        s.numCpusToUse = 2;
        s.tileWidth = 16;
        s.tileHeight = 16;
        Rendered b = sc.render(s);
        s.tileWidth = 37;
        s.tileHeight = 23;
        Rendered c = sc.render(s);
        ASSERT_EQ(a.image.rgba.size(), b.image.rgba.size());
        EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), b.image.rgba.data(), a.image.rgba.size() * sizeof(float)));
        EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), c.image.rgba.data(), a.image.rgba.size() * sizeof(float)));
        EXPECT_GT(a.stats.shadingSamplesAdaptive, 0u);
        EXPECT_EQ(a.stats.shadingSamplesAdaptive > 0, b.stats.shadingSamplesAdaptive > 0);
    }
}

// A multi-pixel filter costs small tiles no apron: the pixels whose window reaches past their
// tile are filtered at the end from what the tiles kept, the same bits as one tile over the frame.
TEST(Renderer, AMultiPixelFilterRendersNoApron) {
    Scene sc(std::string(scene::demoSceneText()), "softSpotlight.ma");
    for (int filter : {2, 4, 6}) {
        render::RenderSettings s = sc.settings;
        s.width = 160;
        s.height = 120;
        s.edgeAntiAliasing = 1;
        s.useMultiPixelFilter = true;
        s.pixelFilterType = filter;
        s.pixelFilterWidthX = s.pixelFilterWidthY = 3.0;
        s.numCpusToUse = 1;
        s.tileWidth = 160;
        s.tileHeight = 120;
        const Rendered whole = sc.render(s);
        s.numCpusToUse = 2;
        s.tileWidth = s.tileHeight = 16;
        const Rendered small = sc.render(s);
        ASSERT_EQ(whole.image.rgba.size(), small.image.rgba.size());
        EXPECT_EQ(0, std::memcmp(whole.image.rgba.data(), small.image.rgba.data(), whole.image.rgba.size() * sizeof(float)))
            << "filter " << filter;
        EXPECT_EQ(small.stats.apronPixels, 0u) << "filter " << filter;
        EXPECT_EQ(small.stats.pixels, 160u * 120u);
    }
}

// At the Highest level a tile renders only the margins the contrast test reads that lie in tiles
// not done yet: rendered row by row, only the right margin, and the image keeps every bit.
TEST(Renderer, TheContrastTestReadsDoneNeighboursInsteadOfAnApron) {
    Scene sc(std::string(scene::demoSceneText()), "softSpotlight.ma");
    render::RenderSettings s = adaptiveAt160x120(sc.settings);
    s.numCpusToUse = 1;
    s.tileWidth = 160;
    s.tileHeight = 120;
    const Rendered whole = sc.render(s);
    s.tileWidth = s.tileHeight = 16;
    const Rendered rows = sc.render(s);
    s.numCpusToUse = 2;
    const Rendered two = sc.render(s);
    ASSERT_EQ(whole.image.rgba.size(), rows.image.rgba.size());
    EXPECT_EQ(0, std::memcmp(whole.image.rgba.data(), rows.image.rgba.data(), whole.image.rgba.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(whole.image.rgba.data(), two.image.rgba.data(), whole.image.rgba.size() * sizeof(float)));
    EXPECT_GT(rows.stats.shadingSamplesAdaptive, 0u);
    // The whole margins of the 10 × 8 tiles (two columns left, one right, one row above, within
    // the image; the last row of tiles is 8 pixels high) against the right margins of the tiles
    // left of the last column, one pixel a row.
    uint64_t margins = 0;
    for (int ty = 0; ty < 8; ++ty)
        for (int tx = 0; tx < 10; ++tx) {
            const int x0 = std::max(0, 16 * tx - 2), x1 = std::min(160, 16 * tx + 17), y0 = std::max(0, 16 * ty - 1);
            const int y1 = std::min(120, 16 * ty + 16);
            margins += uint64_t(x1 - x0) * uint64_t(y1 - y0) - uint64_t(16 * (y1 - 16 * ty));
        }
    EXPECT_EQ(rows.stats.apronPixels, 9u * 120u) << "of " << margins;
    EXPECT_LT(two.stats.apronPixels, margins);
}

// ---------------------------------------------------------------- deferred primitives

// A lit sphere from a polySphere, a cube from a polyCube, a torus and a cylinder with n-gon caps,
// each in one shading group as a whole (`membership` "whole"), or through per-face groups listing
// every face ("faces"), or with a point tweak of zero on the sphere ("zeroTweak").
std::string primitiveScene(const std::string& membership) {
    std::string t = header() + orthoCamera(8.0) + resolution(96, 72) +
                    "createNode transform -n \"sun\";\n\tsetAttr \".r\" -type \"double3\" -30 40 0;\n"
                    "createNode directionalLight -n \"sunShape\" -p \"sun\";\n"
                    "createNode lambert -n \"grey\";\ncreateNode shadingEngine -n \"greySG\";\n"
                    "connectAttr \"grey.oc\" \"greySG.ss\";\nconnectAttr \"greySG.pa\" \":renderPartition.st\" -na;\n"
                    "createNode transform -n \"ball\";\n\tsetAttr \".t\" -type \"double3\" -1.2 0.3 0;\n"
                    "createNode mesh -n \"ballShape\" -p \"ball\";\n";
    if (membership == "faces")
        t += "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[0:383]\";\n";
    if (membership == "zeroTweak") t += "\tsetAttr \".pt[5]\" -type \"float3\" 0 0 0;\n";
    t += "createNode polySphere -n \"ballMaker\";\n\tsetAttr \".r\" 1.5;\n\tsetAttr \".sa\" 24;\n\tsetAttr \".sh\" 16;\n"
         "connectAttr \"ballMaker.out\" \"ballShape.i\";\n"
         "createNode transform -n \"box\";\n\tsetAttr \".t\" -type \"double3\" 1.8 -0.5 -1;\n"
         "\tsetAttr \".r\" -type \"double3\" 20 35 0;\n"
         "createNode mesh -n \"boxShape\" -p \"box\";\n";
    if (membership == "faces")
        t += "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[0:23]\";\n";
    t += "createNode polyCube -n \"boxMaker\";\n\tsetAttr \".w\" 2;\n\tsetAttr \".sw\" 2;\n\tsetAttr \".sh\" 2;\n"
         "\tsetAttr \".sd\" 2;\n\tsetAttr \".ax\" -type \"double3\" 1 1 0;\n"
         "connectAttr \"boxMaker.out\" \"boxShape.i\";\n";
    t += "createNode transform -n \"ring\";\n\tsetAttr \".t\" -type \"double3\" 0.5 2 -2;\n"
         "createNode mesh -n \"ringShape\" -p \"ring\";\n";
    if (membership == "faces")
        t += "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[0:95]\";\n";
    t += "createNode polyTorus -n \"ringMaker\";\n\tsetAttr \".r\" 1.2;\n\tsetAttr \".sr\" 0.3;\n"
         "\tsetAttr \".sa\" 12;\n\tsetAttr \".sh\" 8;\n\tsetAttr \".ax\" -type \"double3\" 0 0.3 1;\n"
         "connectAttr \"ringMaker.out\" \"ringShape.i\";\n"
         "createNode transform -n \"post\";\n\tsetAttr \".t\" -type \"double3\" -2.5 -1.5 -0.5;\n"
         "createNode mesh -n \"postShape\" -p \"post\";\n";
    if (membership == "faces")
        t += "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[0:21]\";\n";
    t += "createNode polyCylinder -n \"postMaker\";\n\tsetAttr \".r\" 0.5;\n\tsetAttr \".h\" 1.5;\n"
         "\tsetAttr \".sa\" 10;\n\tsetAttr \".sh\" 2;\n\tsetAttr \".sc\" 0;\n\tsetAttr \".ax\" -type \"double3\" 1 0 0.4;\n"
         "connectAttr \"postMaker.out\" \"postShape.i\";\n";
    const std::string plug = membership == "faces" ? ".iog.og[0]" : ".iog";
    for (const char* shape : {"ballShape", "boxShape", "ringShape", "postShape"})
        t += "connectAttr \"" + std::string(shape) + plug + "\" \"greySG.dsm\" -na;\n";
    return t;
}

// A shape straight from a primitive in one shading group gets its bounds and counts from the
// creator and makes its mesh only when a tile needs it; it renders every bit its evaluated mesh
// renders (per-face groups and tweaks take the evaluated path).
TEST(Renderer, PrimitivesMakeTheirMeshWhenATileNeedsItAndRenderTheSameImage) {
    const Scene deferred(primitiveScene("whole")), faces(primitiveScene("faces")), tweaked(primitiveScene("zeroTweak"));
    for (const Scene* sc : {&deferred, &faces, &tweaked}) {
        scene::Evaluator ev(sc->graph, sc->frame);
        const render::FrameScene fs = render::buildFrameScene(ev, sc->setup, sc->settings);
        ASSERT_EQ(fs.objects.size(), 4u) << (fs.notes.empty() ? "" : fs.notes.front());
        const bool shouldDefer = sc == &deferred || sc == &tweaked;  // a zero tweak moves nothing
        for (const render::RenderObject& o : fs.objects) {
            SCOPED_TRACE(o.name);
            // Without a cap an evaluated mesh is kept; a deferred one is made on demand.
            EXPECT_EQ(o.geometry->keepsSource(), !shouldDefer);
            const std::map<std::string, uint64_t> triangles = {{"|ball|ballShape", 2 * 24 * 15},
                                                               {"|box|boxShape", 2 * 24},
                                                               {"|ring|ringShape", 2 * 96},
                                                               {"|post|postShape", 2 * 20 + 2 * 8}};
            EXPECT_EQ(o.geometry->triangleCount(), triangles.at(o.name));
        }
        if (sc == &deferred) {
            const geom::Bounds3& b = fs.objects[0].geometry->bounds();
            EXPECT_NEAR(b.lo.x, -1.5, 1e-5);
            EXPECT_NEAR(b.hi.y, 1.5, 1e-5);
        }
    }
    render::RenderSettings s = deferred.settings;
    s.numCpusToUse = 2;
    s.tileWidth = s.tileHeight = 16;
    const Rendered a = deferred.render(s), b = faces.render(s), c = tweaked.render(s);
    EXPECT_EQ(a.stats.trianglesRasterized, b.stats.trianglesRasterized);
    ASSERT_EQ(a.image.rgba.size(), b.image.rgba.size());
    EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), b.image.rgba.data(), a.image.rgba.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.image.rgba.data(), c.image.rgba.data(), a.image.rgba.size() * sizeof(float)));
    float covered = 0.0f;
    for (size_t i = 3; i < a.image.rgba.size(); i += 4) covered += a.image.rgba[i];
    EXPECT_GT(covered, 500.0f) << "both shapes are in view";
}

// ---------------------------------------------------------------- occlusion

// A dense wall over the left of the view with a transparent card and a ball in front of it, and
// a row of balls behind it: some wholly hidden, one half behind its edge, two in the open.
std::string wallScene() {
    std::string text = test::maPreamble(10) + R"(createNode transform -n "sun";
	setAttr ".r" -type "double3" -40 30 0;
createNode directionalLight -n "sunShape" -p "sun";
)" + test::greyShadingGroup() + R"(createNode lambert -n "glass";
	setAttr ".it" -type "float3" 0.5 0.5 0.5;
createNode shadingEngine -n "glassSG";
connectAttr "glassSG.pa" ":renderPartition.st" -na;
connectAttr "glass.oc" "glassSG.ss";
createNode transform -n "wall";
	setAttr ".t" -type "double3" -1 0 0;
createNode mesh -n "wallShape" -p "wall";
createNode polyPlane -n "wallCreator";
	setAttr ".ax" -type "double3" 0 0 1;
	setAttr ".w" 6;
	setAttr ".h" 8;
	setAttr ".sw" 40;
	setAttr ".sh" 40;
connectAttr "wallCreator.out" "wallShape.i";
connectAttr "wallShape.iog" "greySG.dsm" -na;
createNode transform -n "card";
	setAttr ".t" -type "double3" -2 1 2;
createNode mesh -n "cardShape" -p "card";
createNode polyPlane -n "cardCreator";
	setAttr ".ax" -type "double3" 0 0 1;
	setAttr ".w" 2;
	setAttr ".h" 2;
connectAttr "cardCreator.out" "cardShape.i";
connectAttr "cardShape.iog" "glassSG.dsm" -na;
)";
    auto ball = [&](const std::string& id, double x, double y, double z) {
        text += "createNode transform -n \"ball" + id + "\";\n\tsetAttr \".t\" -type \"double3\" " + std::to_string(x) +
                " " + std::to_string(y) + " " + std::to_string(z) + ";\n";
        text += "createNode mesh -n \"ball" + id + "Shape\" -p \"ball" + id + "\";\n";
        text += "createNode polySphere -n \"ballCreator" + id + "\";\n\tsetAttr \".r\" 0.5;\n";
        text += "connectAttr \"ballCreator" + id + ".out\" \"ball" + id + "Shape.i\";\n";
        text += "connectAttr \"ball" + id + "Shape.iog\" \"greySG.dsm\" -na;\n";
    };
    ball("Front", -2.5, -1.5, 1.5);
    const double xs[] = {-3.5, -2.5, -1.5, -0.5, 0.5, 2.2, 3.5, 4.5};
    int n = 0;
    for (double x : xs)
        for (double y : {-1.2, 1.2}) ball(std::to_string(n++), x, y, -2.0);
    return text + resolution(160, 120);
}

TEST(Renderer, ObjectsHiddenInAWholeTileAreNeverTessellatedAndTheImageKeepsEveryBit) {
    Scene sc(wallScene(), "wall.ma");
    for (int tile : {0, 16, 23}) {
        render::RenderSettings s = sc.settings;
        s.edgeAntiAliasing = 0;
        s.useMultiPixelFilter = tile == 16;
        s.pixelFilterType = 2;
        s.maxShadingSamples = 8;
        s.numCpusToUse = tile == 16 ? 2 : 1;
        if (tile) s.tileWidth = s.tileHeight = tile;
        const Rendered all = sc.render(s, {}, false);
        const Rendered skipped = sc.render(s, {}, true);
        ASSERT_EQ(all.image.rgba.size(), skipped.image.rgba.size());
        EXPECT_EQ(0, std::memcmp(all.image.rgba.data(), skipped.image.rgba.data(), all.image.rgba.size() * sizeof(float)))
            << "tile " << tile;
        EXPECT_EQ(all.stats.skippedOccluded, 0u);
        EXPECT_GT(skipped.stats.skippedOccluded, 0u) << "tile " << tile;
        // The wall, the card, the front ball, the half-hidden ball and the four in the open are
        // made; the ten balls wholly behind the wall never are.
        EXPECT_EQ(all.stats.tessellationsMade, 19u);
        EXPECT_EQ(skipped.stats.tessellationsMade, 9u) << "tile " << tile;
        // On two threads the contrast margins a tile renders depend on which tiles around it are
        // done, so the objects its base region reaches may differ from one render to the next.
        if (s.numCpusToUse == 1) {
            EXPECT_EQ(skipped.stats.objectTileVisits + skipped.stats.skippedOccluded, all.stats.objectTileVisits);
        }
    }
}

// ---------------------------------------------------------------- adaptive shading

TEST(Renderer, AdaptiveShadingChangesOnlyTheHighContrastPixels) {
    Scene sc(std::string(scene::demoSceneText()), "softSpotlight.ma");
    render::RenderSettings s = adaptiveAt160x120(sc.settings);
    s.useMultiPixelFilter = false;
    Rendered on = sc.render(s);
    s.maxShadingSamples = 1;  // adaptive shading off
    Rendered off = sc.render(s);
    EXPECT_GT(on.stats.adaptivePixels, 0u);
    EXPECT_GT(on.stats.shadingSamplesAdaptive, on.stats.adaptivePixels - 1);
    EXPECT_EQ(off.stats.shadingSamplesAdaptive, 0u);
    EXPECT_EQ(on.stats.shadingSamplesBase, off.stats.shadingSamplesBase);
    size_t changed = 0, adaptive = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            size_t i = size_t(y) * s.width + x;
            adaptive += on.adaptive[i];
            bool differs = std::memcmp(on.image.pixel(x, y), off.image.pixel(x, y), 4 * sizeof(float)) != 0;
            changed += differs;
            if (differs) {
                EXPECT_EQ(on.adaptive[i], 1) << "pixel " << x << "," << y << " changed without extra samples";
            }
        }
    EXPECT_EQ(adaptive, on.stats.adaptivePixels);
    EXPECT_GT(changed, 0u);
}

TEST(Renderer, FlatSceneTakesNoAdaptiveSamples) {
    std::string text = header() + orthoCamera(1.0) +
                       "createNode transform -n \"wall\";\n"
                       "\tsetAttr \".r\" -type \"double3\" 90 0 0;\n"
                       "\tsetAttr \".s\" -type \"double3\" 10 10 10;\n"
                       "createNode mesh -n \"wallShape\" -p \"wall\";\n"
                       "createNode polyPlane -n \"polyPlane1\";\n"
                       "createNode surfaceShader -n \"flat\";\n"
                       "\tsetAttr \".oc\" -type \"float3\" 0.2 0.5 0.7;\n"
                       "createNode shadingEngine -n \"flatSG\";\n"
                       "connectAttr \"flatSG.pa\" \":renderPartition.st\" -na;\n"
                       "connectAttr \"flat.oc\" \"flatSG.ss\";\n"
                       "connectAttr \"polyPlane1.out\" \"wallShape.i\";\n"
                       "connectAttr \"wallShape.iog\" \"flatSG.dsm\" -na;\n" +
                       resolution(32, 32);
    Scene sc(text);
    render::RenderSettings s = sc.settings;
    s.edgeAntiAliasing = 0;
    s.shadingSamples = 1;
    s.maxShadingSamples = 8;
    Rendered r = sc.render(s);
    EXPECT_EQ(r.stats.shadingSamplesAdaptive, 0u);
    EXPECT_EQ(r.stats.adaptivePixels, 0u);
    EXPECT_NEAR(r.image.pixel(16, 16)[0], 0.2f, 1e-6);
    EXPECT_NEAR(r.image.pixel(16, 16)[1], 0.5f, 1e-6);
    EXPECT_NEAR(r.image.pixel(16, 16)[2], 0.7f, 1e-6);
    EXPECT_FLOAT_EQ(r.image.pixel(0, 0)[3], 1.0f);
}

// ---------------------------------------------------------------- culling, clipping, sides

std::string cardScene(const std::string& transform, const std::string& shapeAttrs, const std::string& camera) {
    return header() + camera +
           "createNode transform -n \"card\";\n" + transform +
           "createNode mesh -n \"cardShape\" -p \"card\";\n" + shapeAttrs +
           "createNode polyPlane -n \"polyPlane1\";\n"
           "\tsetAttr \".w\" 4;\n"
           "\tsetAttr \".h\" 4;\n"
           "createNode surfaceShader -n \"white\";\n"
           "\tsetAttr \".oc\" -type \"float3\" 1 1 1;\n"
           "createNode shadingEngine -n \"whiteSG\";\n"
           "connectAttr \"whiteSG.pa\" \":renderPartition.st\" -na;\n"
           "connectAttr \"white.oc\" \"whiteSG.ss\";\n"
           "connectAttr \"polyPlane1.out\" \"cardShape.i\";\n"
           "connectAttr \"cardShape.iog\" \"whiteSG.dsm\" -na;\n" +
           resolution(32, 32);
}

TEST(Renderer, SingleSidedBackFacesAreNotRendered) {
    // polyPlane faces +Y; rotated −90° about X it faces −Z, away from the camera at +Z.
    std::string away = "\tsetAttr \".r\" -type \"double3\" -90 0 0;\n";
    Scene oneSided(cardScene(away, "\tsetAttr \".ds\" no;\n", orthoCamera(2.0)));
    Rendered r1 = oneSided.render(oneSided.settings);
    EXPECT_FLOAT_EQ(r1.image.pixel(16, 16)[3], 0.0f);
    EXPECT_GT(r1.stats.trianglesBackfacing, 0u);
    Scene twoSided(cardScene(away, "", orthoCamera(2.0)));
    Rendered r2 = twoSided.render(twoSided.settings);
    EXPECT_FLOAT_EQ(r2.image.pixel(16, 16)[3], 1.0f);
}

TEST(Renderer, NearPlaneClipsAndFarPlaneCullsPerObject) {
    std::string persp = "createNode transform -n \"cam\";\n"
                        "\tsetAttr \".t\" -type \"double3\" 0 0.5 0;\n"
                        "createNode camera -n \"camShape\" -p \"cam\";\n"
                        "\tsetAttr \".rnd\" yes;\n"
                        "\tsetAttr \".ncp\" 0.1;\n"
                        "\tsetAttr \".fcp\" 100;\n";
    // A floor under the camera, running from behind it to far ahead: it crosses the near plane.
    Scene floor(cardScene("\tsetAttr \".s\" -type \"double3\" 10 1 10;\n", "", persp));
    Rendered r = floor.render(floor.settings);
    EXPECT_GT(r.stats.trianglesNearClipped, 0u);
    for (float v : r.image.rgba) ASSERT_TRUE(std::isfinite(v));
    EXPECT_FLOAT_EQ(r.image.pixel(16, 31)[3], 1.0f);  // the floor fills the bottom row
    EXPECT_FLOAT_EQ(r.image.pixel(16, 0)[3], 0.0f);   // the sky stays empty

    // The same card 200 units away is past the far plane: culled as a whole object.
    Scene far(cardScene("\tsetAttr \".t\" -type \"double3\" 0 0 -200;\n\tsetAttr \".r\" -type \"double3\" 90 0 0;\n", "",
                        persp));
    Rendered rf = far.render(far.settings);
    EXPECT_EQ(rf.stats.objectsCulledFar, 1u);
    EXPECT_EQ(rf.stats.trianglesRasterized, 0u);
    for (size_t i = 3; i < rf.image.rgba.size(); i += 4) ASSERT_EQ(rf.image.rgba[i], 0.0f);

    // Off to the side: culled by its screen-space bounds.
    Scene aside(cardScene("\tsetAttr \".t\" -type \"double3\" 500 0 -20;\n\tsetAttr \".r\" -type \"double3\" 90 0 0;\n", "",
                          persp));
    Rendered ra = aside.render(aside.settings);
    EXPECT_EQ(ra.stats.objectsCulledFrustum, 1u);
}

TEST(Renderer, TransparentSurfaceLetsTheOneBehindThrough) {
    std::string text = header() + orthoCamera(2.0) +
                       "createNode transform -n \"front\";\n"
                       "\tsetAttr \".t\" -type \"double3\" 0 0 1;\n"
                       "\tsetAttr \".r\" -type \"double3\" 90 0 0;\n"
                       "createNode mesh -n \"frontShape\" -p \"front\";\n"
                       "createNode transform -n \"back\";\n"
                       "\tsetAttr \".r\" -type \"double3\" 90 0 0;\n"
                       "createNode mesh -n \"backShape\" -p \"back\";\n"
                       "createNode polyPlane -n \"polyPlane1\";\n"
                       "\tsetAttr \".w\" 4;\n"
                       "\tsetAttr \".h\" 4;\n"
                       "createNode surfaceShader -n \"glass\";\n"
                       "\tsetAttr \".oc\" -type \"float3\" 0.5 0 0;\n"
                       "\tsetAttr \".ot\" -type \"float3\" 0.5 0.5 0.5;\n"
                       "createNode shadingEngine -n \"glassSG\";\n"
                       "connectAttr \"glassSG.pa\" \":renderPartition.st\" -na;\n"
                       "createNode surfaceShader -n \"blue\";\n"
                       "\tsetAttr \".oc\" -type \"float3\" 0 0 1;\n"
                       "createNode shadingEngine -n \"blueSG\";\n"
                       "connectAttr \"blueSG.pa\" \":renderPartition.st\" -na;\n"
                       "connectAttr \"glass.oc\" \"glassSG.ss\";\n"
                       "connectAttr \"blue.oc\" \"blueSG.ss\";\n"
                       "connectAttr \"polyPlane1.out\" \"frontShape.i\";\n"
                       "connectAttr \"polyPlane1.out\" \"backShape.i\";\n"
                       "connectAttr \"frontShape.iog\" \"glassSG.dsm\" -na;\n"
                       "connectAttr \"backShape.iog\" \"blueSG.dsm\" -na;\n" +
                       resolution(16, 16);
    Scene sc(text);
    Rendered r = sc.render(sc.settings);
    const float* p = r.image.pixel(8, 8);
    EXPECT_NEAR(p[0], 0.5f, 1e-5);  // the glass's own colour
    EXPECT_NEAR(p[1], 0.0f, 1e-5);
    EXPECT_NEAR(p[2], 0.5f, 1e-5);  // blue seen through 50% transparency
    EXPECT_NEAR(p[3], 1.0f, 1e-5);
}

TEST(Renderer, DefaultLightWhenTheSceneHasNone) {
    std::string text = header() + orthoCamera(2.0) +
                       "createNode transform -n \"wall\";\n"
                       "\tsetAttr \".r\" -type \"double3\" 90 0 0;\n"
                       "createNode mesh -n \"wallShape\" -p \"wall\";\n"
                       "createNode polyPlane -n \"polyPlane1\";\n"
                       "\tsetAttr \".w\" 4;\n"
                       "\tsetAttr \".h\" 4;\n"
                       "connectAttr \"polyPlane1.out\" \"wallShape.i\";\n"
                       "connectAttr \"wallShape.iog\" \":initialShadingGroup.dsm\" -na;\n" +
                       resolution(16, 16);
    Scene sc(text);
    render::RenderSettings s = sc.settings;
    Rendered lit = sc.render(s);
    // lambert1 facing the default light head-on: 0.5 · 0.8 · 1.
    EXPECT_NEAR(lit.image.pixel(8, 8)[0], 0.4f, 1e-4);
    s.enableDefaultLight = false;
    Rendered dark = sc.render(s);
    EXPECT_NEAR(dark.image.pixel(8, 8)[0], 0.0f, 1e-6);
    EXPECT_NEAR(dark.image.pixel(8, 8)[3], 1.0f, 1e-6);
}

TEST(Renderer, RenderRegionLeavesTheRestEmptyAndCompositeDropsTheBackground) {
    std::string text = cardScene("\tsetAttr \".r\" -type \"double3\" 90 0 0;\n\tsetAttr \".s\" -type \"double3\" 0.1 1 0.1;\n",
                                 "", orthoCamera(2.0) + "\tsetAttr \".col\" -type \"float3\" 0 1 0;\n");
    Scene sc(text);
    render::RenderSettings s = sc.settings;
    Rendered full = sc.render(s);
    EXPECT_NEAR(full.image.pixel(0, 0)[1], 1.0f, 1e-6);  // the camera's background colour
    EXPECT_NEAR(full.image.pixel(0, 0)[3], 0.0f, 1e-6);
    s.composite = true;
    Rendered comp = sc.render(s);
    EXPECT_NEAR(comp.image.pixel(0, 0)[1], 0.0f, 1e-6);
    s.composite = false;
    s.useRenderRegion = true;
    s.left = 4, s.rght = 11, s.bot = 20, s.top = 27;  // rows counted from the bottom
    Rendered region = sc.render(s);
    EXPECT_EQ(region.stats.pixels, 64u);
    EXPECT_NEAR(region.image.pixel(4, 4)[1], 1.0f, 1e-6);   // inside: background
    EXPECT_NEAR(region.image.pixel(3, 4)[1], 0.0f, 1e-6);   // outside: untouched
    EXPECT_NEAR(region.image.pixel(4, 12)[1], 0.0f, 1e-6);
}

// ---------------------------------------------------------------- tile plan

TEST(TilePlan, CoversTheRegionExactlyOnce) {
    for (auto [w, h] : {std::pair{64, 64}, {16, 16}, {37, 23}, {1, 1}, {0, -3}}) {
        render::PixelRect region{3, 5, 203, 130};
        std::vector<render::PixelRect> tiles = render::planTiles(region, w, h);
        std::vector<int> hits(size_t(region.width()) * region.height(), 0);
        for (const render::PixelRect& t : tiles) {
            EXPECT_LE(t.width(), std::max(w, 1));
            EXPECT_LE(t.height(), std::max(h, 1));
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) ++hits[size_t(y - region.y0) * region.width() + (x - region.x0)];
        }
        for (int v : hits) ASSERT_EQ(v, 1);
    }
    EXPECT_TRUE(render::planTiles({0, 0, 0, 10}, 64, 64).empty());
}

// ---------------------------------------------------------------- the public scenes

TEST(Renderer, EveryPublicSceneWithACameraAndPolygonsRenders) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    size_t rendered = 0;
    for (const auto& path : pushpin::test::maCorpusFiles()) {
        scene::Graph graph = scene::MaReader::readFile(path);
        double frame = scene::sceneCurrentFrame(graph);
        scene::Evaluator ev(graph, frame);
        scene::RenderSetup setup = scene::extractRenderSetup(graph);
        std::vector<std::string> notes;
        render::RenderSettings s = render::readRenderSettings(ev, setup, notes);
        s.width = 64;
        s.height = 48;
        s.deviceAspectRatio = 64.0 / 48.0;
        s.edgeAntiAliasing = 0;
        s.shadingSamples = 1;
        s.maxShadingSamples = 4;
        render::FrameScene fs = render::buildFrameScene(ev, setup, s);
        bool polygons = false;
        for (const render::RenderObject& o : fs.objects)
            polygons |= o.geometry->triangleCount() > 0 && ev.graph().node(o.shape).type == "mesh";
        if (!polygons) continue;
        for (const scene::CameraInfo& c : setup.cameras) {
            if (!c.renderable) continue;
            render::RenderCamera camera = render::makeRenderCamera(ev, c.path, s.width, s.height, s.deviceAspectRatio);
            render::RenderStats stats;
            render::Framebuffer image = render::renderFrame(fs, camera, s, stats);
            for (float v : image.rgba) ASSERT_TRUE(std::isfinite(v)) << path;
            ++rendered;
        }
    }
    EXPECT_GT(rendered, 10u);
}

}  // namespace
