// Numbers at the door (core/render/camera.h, frame_scene.h): hostile values in cameras, object and
// light transforms and vertex positions are refused where they enter — makeRenderCamera throws
// naming the camera and the value, buildFrameScene skips the object or light with a note — and
// whatever is accepted renders to finite pixels. Scenes are .ma text read in memory; values the
// .ma reader refuses (NaN) are set on the graph.
#include "core/render/camera.h"
#include "core/render/frame_scene.h"
#include "core/render/renderer.h"

#include "cache/error.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

constexpr const char* kHeader = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
select -ne :defaultResolution;
	setAttr ".w" 40;
	setAttr ".h" 30;
	setAttr ".dar" 1.3333333333333333;
)";

// A perspective camera 10 units up +Z looking at the origin, with extra shape / transform lines.
std::string camera(const std::string& shapeLines = "", const std::string& transformLines = "") {
    return "createNode transform -n \"persp\";\n\tsetAttr \".t\" -type \"double3\" 0 0 10;\n" + transformLines +
           "createNode camera -n \"perspShape\" -p \"persp\";\n\tsetAttr \".rnd\" yes;\n" + shapeLines;
}

// A unit polyCube "box" with a lambert, and extra transform lines.
std::string box(const std::string& transformLines = "") {
    return "createNode transform -n \"box\";\n" + transformLines +
           "createNode mesh -n \"boxShape\" -p \"box\";\n"
           "createNode polyCube -n \"boxCreator\";\n"
           "connectAttr \"boxCreator.out\" \"boxShape.i\";\n"
           "createNode lambert -n \"grey\";\n"
           "createNode shadingEngine -n \"greySG\";\n"
           "connectAttr \"greySG.pa\" \":renderPartition.st\" -na;\n"
           "connectAttr \"grey.oc\" \"greySG.ss\";\n"
           "connectAttr \"boxShape.iog\" \"greySG.dsm\" -na;\n";
}

// A point light "bulb" with extra transform and shape lines.
std::string bulb(const std::string& transformLines, const std::string& shapeLines = "") {
    return "createNode transform -n \"bulb\";\n" + transformLines + "createNode pointLight -n \"bulbShape\" -p \"bulb\";\n" +
           shapeLines;
}

// A scene loaded with everything a render needs, kept alive together.
struct Loaded {
    std::unique_ptr<scene::Graph> graph;
    scene::RenderSetup setup;
    RenderSettings settings;

    explicit Loaded(const std::string& text)
        : graph(std::make_unique<scene::Graph>(scene::MaReader::readString(std::string(kHeader) + text, "hostile.ma"))) {
        refresh();
    }
    void refresh() {
        setup = scene::extractRenderSetup(*graph);
        scene::Evaluator ev(*graph, 1.0);
        std::vector<std::string> notes;
        settings = readRenderSettings(ev, setup, notes);
    }
    std::vector<scene::NodeId> cameraPath() const {
        return graph->dagPaths(graph->find("perspShape")).at(0);
    }
    FrameScene frame() const {
        scene::Evaluator ev(*graph, 1.0);
        return buildFrameScene(ev, setup, settings);
    }
    RenderCamera renderCamera() const {
        scene::Evaluator ev(*graph, 1.0);
        return makeRenderCamera(ev, cameraPath(), settings.width, settings.height, settings.deviceAspectRatio);
    }
    // Builds, projects and renders; every colour and alpha value must be finite.
    Framebuffer render() const {
        scene::Evaluator ev(*graph, 1.0);
        const FrameScene fs = buildFrameScene(ev, setup, settings);
        const RenderCamera cam = makeRenderCamera(ev, cameraPath(), settings.width, settings.height,
                                                  settings.deviceAspectRatio);
        RenderStats stats;
        return renderFrame(fs, cam, settings, stats);
    }
};

bool hasNote(const FrameScene& f, const std::string& a, const std::string& b) {
    return std::any_of(f.notes.begin(), f.notes.end(), [&](const std::string& n) {
        return n.find(a) != std::string::npos && n.find(b) != std::string::npos;
    });
}

std::string allNotes(const FrameScene& f) {
    std::string s;
    for (const std::string& n : f.notes) s += n + "\n";
    return s;
}

// Index of the first non-finite colour or alpha value, or -1.
long firstNonFinite(const Framebuffer& image) {
    for (size_t i = 0; i < image.rgba.size(); ++i)
        if (!std::isfinite(image.rgba[i])) return long(i);
    return -1;
}

// The message of the pushpin::Error makeRenderCamera throws, or "" when it accepts the camera.
std::string cameraError(const Loaded& scene) {
    try {
        (void)scene.renderCamera();
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

// ---------------------------------------------------------------- cameras

TEST(HostileNumbers, CameraValuesOutOfRangeThrowNamingTheCameraAndTheValue) {
    struct Case {
        std::string lines;
        std::string expected;  // attribute and value as the message shows them
    };
    const Case cases[] = {
        {"\tsetAttr \".fl\" 1e308;\n", "focalLength 1e+308 is out of range"},
        {"\tsetAttr \".fl\" 1e-308;\n", "focalLength 1e-308 is out of range"},
        {"\tsetAttr \".fl\" -1;\n", "focalLength -1 is out of range"},
        {"\tsetAttr \".ncp\" 0;\n", "nearClipPlane 0 is out of range"},
        {"\tsetAttr \".ncp\" -1;\n", "nearClipPlane -1 is out of range"},
        {"\tsetAttr \".ncp\" 200;\n\tsetAttr \".fcp\" 100;\n", "nearClipPlane (200) is not less than farClipPlane (100)"},
        {"\tsetAttr \".fcp\" 1e300;\n", "farClipPlane 1e+300 is out of range"},
        {"\tsetAttr \".o\" yes;\n\tsetAttr \".ow\" 0;\n", "orthographicWidth 0 is out of range"},
        {"\tsetAttr \".o\" yes;\n\tsetAttr \".ow\" 1e308;\n", "orthographicWidth 1e+308 is out of range"},
        {"\tsetAttr \".cap\" -type \"double2\" 1e308 0.9;\n", "horizontalFilmAperture 1e+308 is out of range"},
        {"\tsetAttr \".cap\" -type \"double2\" 1.4 1e-308;\n", "verticalFilmAperture 1e-308 is out of range"},
        {"\tsetAttr \".hfo\" 1e308;\n", "horizontalFilmOffset 1e+308 is out of range"},
        {"\tsetAttr \".vfo\" -1e308;\n", "verticalFilmOffset -1e+308 is out of range"},
        {"\tsetAttr \".lsr\" 1e308;\n", "lensSqueezeRatio 1e+308 is out of range"},
        {"\tsetAttr \".ovr\" 1e308;\n", "overscan 1e+308 is out of range"},
        {"\tsetAttr \".psc\" 1e-308;\n", "preScale 1e-308 is out of range"},
        {"\tsetAttr \".ptsc\" 1e308;\n", "postScale 1e+308 is out of range"},
    };
    for (const Case& c : cases) {
        const std::string message = cameraError(Loaded(camera(c.lines) + box()));
        EXPECT_NE(message.find("camera '|persp|perspShape': "), std::string::npos) << c.lines << message;
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.lines << message;
    }
}

TEST(HostileNumbers, NaNCameraValuesThrow) {
    for (const char* attr : {"focalLength", "nearClipPlane", "farClipPlane", "overscan", "horizontalFilmOffset"}) {
        Loaded scene(camera() + box());
        scene.graph->setValue(scene.graph->find("perspShape"), *scene::parsePlugPath(attr),
                              scene::Numbers{scene::Numbers::Kind::Plain, 1, {std::numeric_limits<double>::quiet_NaN()}});
        const std::string message = cameraError(scene);
        EXPECT_NE(message.find(std::string(attr) + " nan is out of range"), std::string::npos) << message;
    }
}

TEST(HostileNumbers, CameraTransformOutOfRangeThrows) {
    const std::pair<std::string, std::string> cases[] = {
        {"\tsetAttr \".t\" -type \"double3\" 1e308 0 10;\n", "world matrix entry 1e+308 is out of range"},
        {"\tsetAttr \".t\" -type \"double3\" 0 -1e308 10;\n", "world matrix entry -1e+308 is out of range"},
        {"\tsetAttr \".s\" -type \"double3\" 1e308 1e308 1e308;\n", "world matrix entry 1e+308 is out of range"},
        {"\tsetAttr \".s\" -type \"double3\" 0 0 0;\n", "singular"},
        {"\tsetAttr \".s\" -type \"double3\" 1e-9 1e-9 1e-9;\n", "scales the camera by"},
    };
    for (const auto& [lines, expected] : cases) {
        const std::string message = cameraError(Loaded(camera("", lines) + box()));
        EXPECT_NE(message.find("camera '|persp|perspShape': "), std::string::npos) << lines << message;
        EXPECT_NE(message.find(expected), std::string::npos) << lines << message;
    }
}

TEST(HostileNumbers, CamerasAtTheEdgesOfTheirRangesRenderFinitePixels) {
    // Accepted extremes: the projection of the box lands far off screen or covers a speck, which
    // binning and rasterisation must survive without overflow.
    const std::string cases[] = {
        "\tsetAttr \".fl\" 1e7;\n",
        "\tsetAttr \".fl\" 0.001;\n",
        "\tsetAttr \".ncp\" 1e-6;\n\tsetAttr \".fcp\" 1e18;\n",
        "\tsetAttr \".hfo\" 1e4;\n",
        "\tsetAttr \".o\" yes;\n\tsetAttr \".ow\" 1e-6;\n",
        "\tsetAttr \".o\" yes;\n\tsetAttr \".ow\" 1e18;\n\tsetAttr \".ncp\" -1e18;\n",
        "\tsetAttr \".ovr\" 1000;\n\tsetAttr \".psc\" 0.001;\n",
    };
    for (const std::string& lines : cases) {
        Loaded scene(camera(lines) + box() + bulb("\tsetAttr \".t\" -type \"double3\" 3 4 5;\n"));
        Framebuffer image;
        ASSERT_NO_THROW(image = scene.render()) << lines;
        EXPECT_EQ(firstNonFinite(image), -1) << lines;
    }
    // A square 1e6 units wide under a 1e-6 wide orthographic view: its raster corners sit about
    // 2e13 pixels out, past any int, and it still fills the frame.
    Loaded wide(camera("\tsetAttr \".o\" yes;\n\tsetAttr \".ow\" 1e-6;\n") +
                box("\tsetAttr \".s\" -type \"double3\" 1e6 1e6 1;\n"));
    const Framebuffer wideImage = wide.render();
    EXPECT_EQ(firstNonFinite(wideImage), -1);
    EXPECT_EQ(wideImage.pixel(0, 0)[3], 1.0f);
    EXPECT_EQ(wideImage.pixel(39, 29)[3], 1.0f);
    // The long lens on a box right in front of it: the box fills the frame.
    Loaded tele(camera("\tsetAttr \".fl\" 1e7;\n") + box());
    const Framebuffer image = tele.render();
    EXPECT_EQ(image.pixel(20, 15)[3], 1.0f);
}

// ---------------------------------------------------------------- objects

TEST(HostileNumbers, ObjectsOutOfRangeAreSkippedWithANote) {
    const std::pair<std::string, std::string> cases[] = {
        {"\tsetAttr \".t\" -type \"double3\" 1e308 0 0;\n", "world matrix entry 1e+308 is beyond 1e18"},
        {"\tsetAttr \".t\" -type \"double3\" 0 -1e308 0;\n", "world matrix entry -1e+308 is beyond 1e18"},
        {"\tsetAttr \".s\" -type \"double3\" 1e308 1 1;\n", "world matrix entry 1e+308 is beyond 1e18"},
        {"\tsetAttr \".t\" -type \"double3\" 0 0 -1e19;\n", "world matrix entry -1e+19 is beyond 1e18"},
        // Finite entries that still carry the bounds past the limit.
        {"\tsetAttr \".s\" -type \"double3\" 1e15 1e15 1e15;\n\tsetAttr \".t\" -type \"double3\" 1e18 0 0;\n",
         "world-space bounds reach"},
    };
    for (const auto& [lines, expected] : cases) {
        Loaded scene(camera() + box(lines));
        const FrameScene f = scene.frame();
        EXPECT_TRUE(f.objects.empty()) << lines;
        EXPECT_EQ(f.skippedShapes, 1u) << lines;
        EXPECT_TRUE(hasNote(f, "|box|boxShape: ", expected)) << lines << allNotes(f);
        Framebuffer image;
        ASSERT_NO_THROW(image = scene.render()) << lines;
        EXPECT_EQ(firstNonFinite(image), -1) << lines;
    }
}

TEST(HostileNumbers, ZeroScaleObjectRendersFinitePixels) {
    // Scale 0 on every axis collapses the box to a point; on one axis it is a flat square facing
    // the camera. Neither has an inverse matrix; both render without NaN.
    for (const char* scale : {"0 0 0", "1 1 0"}) {
        Loaded scene(camera() + box("\tsetAttr \".s\" -type \"double3\" " + std::string(scale) + ";\n") +
                     bulb("\tsetAttr \".t\" -type \"double3\" 0 0 5;\n"));
        const FrameScene f = scene.frame();
        EXPECT_EQ(f.objects.size(), 1u) << scale << allNotes(f);
        const Framebuffer image = scene.render();
        EXPECT_EQ(firstNonFinite(image), -1) << scale;
        if (std::string(scale) == "1 1 0") {
            EXPECT_EQ(image.pixel(20, 15)[3], 1.0f);
        }
    }
}

TEST(HostileNumbers, VerticesOutOfRangeSkipTheShapeWithANote) {
    // A stored triangle reaching far out: 1e308 is past float (the mesh is invalid); 1e19 is a
    // float whose bounds leave the scene range.
    const std::pair<std::string, std::string> cases[] = {{"0 0 0  1 0 0  0 1e308 0", "not finite"},
                                                         {"0 0 0  1e19 0 0  0 1e19 0", "world-space bounds reach 1e+19"}};
    for (const auto& [vertices, expected] : cases) {
        const std::string text = camera() + "createNode transform -n \"tri\";\n"
                                            "createNode mesh -n \"triShape\" -p \"tri\";\n"
                                            "\tsetAttr -s 3 \".vt[0:2]\"  " + vertices + ";\n"
                                            "\tsetAttr -s 3 \".ed[0:2]\"  0 1 0  1 2 0  2 0 0;\n"
                                            "\tsetAttr -s 1 \".fc[0]\" -type \"polyFaces\" f 3 0 1 2;\n"
                                            "createNode lambert -n \"grey\";\n"
                                            "createNode shadingEngine -n \"greySG\";\n"
                                            "connectAttr \"greySG.pa\" \":renderPartition.st\" -na;\n"
                                            "connectAttr \"grey.oc\" \"greySG.ss\";\n"
                                            "connectAttr \"triShape.iog\" \"greySG.dsm\" -na;\n";
        Loaded scene(text);
        const FrameScene f = scene.frame();
        EXPECT_TRUE(f.objects.empty()) << vertices;
        EXPECT_EQ(f.skippedShapes, 1u) << vertices;
        EXPECT_TRUE(hasNote(f, "|tri|triShape: ", expected)) << vertices << "\n" << allNotes(f);
        const Framebuffer image = scene.render();
        EXPECT_EQ(firstNonFinite(image), -1) << vertices;
    }
}

// ---------------------------------------------------------------- lights

TEST(HostileNumbers, LightsOutOfRangeAreSkippedWithANote) {
    const std::pair<std::string, std::string> cases[] = {
        {"\tsetAttr \".t\" -type \"double3\" 1e308 0 0;\n", "world matrix entry 1e+308 is beyond 1e18"},
        {"\tsetAttr \".t\" -type \"double3\" 0 0 -1e308;\n", "world matrix entry -1e+308 is beyond 1e18"},
        {"\tsetAttr \".s\" -type \"double3\" 0 0 0;\n", "scale 0"},
    };
    for (const auto& [lines, expected] : cases) {
        Loaded scene(camera() + box() + bulb(lines));
        const FrameScene f = scene.frame();
        EXPECT_TRUE(f.lights.empty()) << lines;
        EXPECT_TRUE(hasNote(f, "|bulb|bulbShape: ", expected)) << lines << allNotes(f);
        EXPECT_EQ(firstNonFinite(scene.render()), -1) << lines;
    }
}

TEST(HostileNumbers, LightValuesOutOfRangeAreReplacedWithANote) {
    Loaded scene(camera() + box() + bulb("\tsetAttr \".t\" -type \"double3\" 0 0 5;\n", "\tsetAttr \".in\" 1e308;\n"));
    const FrameScene f = scene.frame();
    ASSERT_EQ(f.lights.size(), 1u) << allNotes(f);
    EXPECT_EQ(f.lights[0].color, glm::vec3(1.0f));
    EXPECT_TRUE(hasNote(f, "|bulb|bulbShape: ", "intensity 1e+308 is beyond 1e30")) << allNotes(f);
    EXPECT_EQ(firstNonFinite(scene.render()), -1);

    // A colour × intensity product past float's range skips the light.
    Loaded bright(camera() + box() +
                  bulb("", "\tsetAttr \".cl\" -type \"float3\" 1e20 1 1;\n\tsetAttr \".in\" 1e20;\n"));
    const FrameScene fb = bright.frame();
    EXPECT_TRUE(fb.lights.empty());
    EXPECT_TRUE(hasNote(fb, "|bulb|bulbShape: ", "color × intensity is beyond 1e30")) << allNotes(fb);
}

}  // namespace
}  // namespace pushpin::render
