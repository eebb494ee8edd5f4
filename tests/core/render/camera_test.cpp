// Tests for core/render/camera.h: the film-back projection against the closed-form formulas of
// reference/nodes.md §2, every film fit mode, offsets, orthographic cameras, the inverse maps,
// and the errors for attributes that make no image.
#include "core/render/camera.h"

#include "cache/error.h"
#include "core/scene/ma_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace pushpin::render {
namespace {

constexpr double kMm = 25.4;

// A scene with one camera `cam1` (shape `cam1Shape`) whose shape gets `shapeAttrs` (setAttr lines
// without the node) and whose transform gets `transformAttrs`.
scene::Graph cameraScene(const std::string& shapeAttrs, const std::string& transformAttrs = "") {
    const std::string text = "createNode transform -n \"cam1\";\n" + transformAttrs +
                             "createNode camera -n \"cam1Shape\" -p \"cam1\";\n" + shapeAttrs;
    return scene::MaReader::readString(text, "test.ma");
}

RenderCamera build(const scene::Graph& g, int w, int h, double dar, double frame = 1.0) {
    scene::Evaluator ev(g, frame);
    const scene::NodeId shape = g.find("cam1Shape");
    EXPECT_NE(shape, scene::kNoNode);
    return makeRenderCamera(ev, g.dagPaths(shape).at(0), w, h, dar);
}

// 35 mm lens on a 36 × 24 mm back.
const std::string k35mm = "setAttr \".fl\" 35;\nsetAttr \".cap\" -type \"double2\" 1.4173228346456692 0.94488188976377951;\n";

// Expected raster position of a camera-space point for a window of half-extents (hw, hh) centred
// at (cx, cy) on the z = −1 plane.
glm::dvec2 expectedRaster(const glm::dvec3& p, double hw, double hh, double cx, double cy, int w, int h) {
    const double sx = p.x / -p.z, sy = p.y / -p.z;
    return {(sx - (cx - hw)) / (2 * hw) * w, ((cy + hh) - sy) / (2 * hh) * h};
}

TEST(RenderCamera, HorizontalFitProjectsByTheFocalLengthFormula) {
    const scene::Graph g = cameraScene(k35mm);
    const RenderCamera cam = build(g, 640, 480, 4.0 / 3.0);
    EXPECT_EQ(cam.name, "cam1");
    EXPECT_FALSE(cam.orthographic);
    const double hw = 18.0 / 35.0, hh = hw * 0.75;
    EXPECT_NEAR(cam.windowRight, hw, 1e-12);
    EXPECT_NEAR(cam.windowTop, hh, 1e-12);
    // fovH = 2·atan(hfa·25.4 / (2·fl))
    EXPECT_NEAR(2 * std::atan(cam.windowRight), 2 * std::atan(36.0 / 70.0), 1e-12);
    const glm::dvec3 points[] = {{0, 0, -5}, {1, 0.5, -10}, {-2, -1, -3}, {18, 13.5, -35}};
    for (const glm::dvec3& p : points) {
        const glm::dvec2 r = cam.rasterFromCamera(p);
        const glm::dvec2 e = expectedRaster(p, hw, hh, 0, 0, 640, 480);
        EXPECT_NEAR(r.x, e.x, 1e-9);
        EXPECT_NEAR(r.y, e.y, 1e-9);
    }
    // The centre of the image and the top-right corner of the film gate.
    EXPECT_NEAR(cam.rasterFromCamera({0, 0, -1}).x, 320.0, 1e-9);
    EXPECT_NEAR(cam.rasterFromCamera({0, 0, -1}).y, 240.0, 1e-9);
    EXPECT_NEAR(cam.rasterFromCamera({18, 13.5, -35}).x, 640.0, 1e-9);
    EXPECT_NEAR(cam.rasterFromCamera({18, 13.5, -35}).y, 0.0, 1e-9);
}

TEST(RenderCamera, DefaultsAreMayasPerspCamera) {
    const scene::Graph g = cameraScene("");
    const RenderCamera cam = build(g, 640, 480, 4.0 / 3.0);
    EXPECT_NEAR(cam.windowRight, 1.41732 * kMm / 35.0 / 2.0, 1e-12);
    EXPECT_DOUBLE_EQ(cam.nearClipPlane, 0.1);
    EXPECT_DOUBLE_EQ(cam.farClipPlane, 10000.0);
    EXPECT_EQ(cam.backgroundColor, glm::dvec3(0.0));
}

// 16:9 output on the 3:2 film back: the film is narrower than the device.
TEST(RenderCamera, FilmFitModesOnAWiderDevice) {
    const double dar = 16.0 / 9.0;
    const double fw = 36.0 / 35.0, fh = 24.0 / 35.0;  // film gate on the z = −1 plane
    struct Case {
        int fit;
        double width, height;
    } cases[] = {
        {0, fw, fw / dar},       // Fill: resolution gate inside the film gate → match width
        {1, fw, fw / dar},       // Horizontal
        {2, fh * dar, fh},       // Vertical
        {3, fh * dar, fh},       // Overscan: film gate inside → match height
    };
    for (const Case& c : cases) {
        const scene::Graph g = cameraScene(k35mm + "setAttr \".ff\" " + std::to_string(c.fit) + ";\n");
        const RenderCamera cam = build(g, 1920, 1080, dar);
        EXPECT_NEAR(cam.windowRight - cam.windowLeft, c.width, 1e-12) << "filmFit " << c.fit;
        EXPECT_NEAR(cam.windowTop - cam.windowBottom, c.height, 1e-12) << "filmFit " << c.fit;
        if (c.fit == 0) {
            EXPECT_LE(cam.windowTop - cam.windowBottom, fh + 1e-12);
        }
        if (c.fit == 3) {
            EXPECT_GE(cam.windowRight - cam.windowLeft, fw - 1e-12);
        }
    }
}

// 1:1 output on the 3:2 film back: the film is wider than the device.
TEST(RenderCamera, FilmFitModesOnANarrowerDevice) {
    const double fw = 36.0 / 35.0, fh = 24.0 / 35.0;
    const double expectedWidth[] = {fh, fw, fh, fw};  // Fill → Vertical, Overscan → Horizontal
    for (int fit = 0; fit < 4; ++fit) {
        const scene::Graph g = cameraScene(k35mm + "setAttr \".ff\" " + std::to_string(fit) + ";\n");
        const RenderCamera cam = build(g, 500, 500, 1.0);
        EXPECT_NEAR(cam.windowRight - cam.windowLeft, expectedWidth[fit], 1e-12) << "filmFit " << fit;
        EXPECT_NEAR(cam.windowTop - cam.windowBottom, expectedWidth[fit], 1e-12) << "filmFit " << fit;
    }
}

TEST(RenderCamera, FilmOffsetShiftsTheWindow) {
    const scene::Graph g = cameraScene(k35mm + "setAttr \".fio\" -type \"double2\" 0.1 -0.2;\n");
    const RenderCamera cam = build(g, 640, 480, 4.0 / 3.0);
    const double cx = 0.1 * kMm / 35.0, cy = -0.2 * kMm / 35.0;
    const double hw = 18.0 / 35.0, hh = hw * 0.75;
    EXPECT_NEAR(0.5 * (cam.windowLeft + cam.windowRight), cx, 1e-12);
    EXPECT_NEAR(0.5 * (cam.windowBottom + cam.windowTop), cy, 1e-12);
    const glm::dvec3 p{0.3, 0.2, -4};
    const glm::dvec2 r = cam.rasterFromCamera(p);
    const glm::dvec2 e = expectedRaster(p, hw, hh, cx, cy, 640, 480);
    EXPECT_NEAR(r.x, e.x, 1e-9);
    EXPECT_NEAR(r.y, e.y, 1e-9);
    // A point on the offset axis lands in the image centre.
    EXPECT_NEAR(cam.rasterFromCamera({cx * 7, cy * 7, -7}).x, 320.0, 1e-9);
    EXPECT_NEAR(cam.rasterFromCamera({cx * 7, cy * 7, -7}).y, 240.0, 1e-9);
}

TEST(RenderCamera, OverscanAndScalesResizeTheWindow) {
    const double hw = 18.0 / 35.0;
    {
        const RenderCamera cam = build(cameraScene(k35mm + "setAttr \".ovr\" 1.5;\n"), 640, 480, 4.0 / 3.0);
        EXPECT_NEAR(cam.windowRight, hw * 1.5, 1e-12);
    }
    {
        const RenderCamera cam =
            build(cameraScene(k35mm + "setAttr \".psc\" 2;\nsetAttr \".ptsc\" 0.5;\n"), 640, 480, 4.0 / 3.0);
        EXPECT_NEAR(cam.windowRight, hw, 1e-12);
    }
    {
        const RenderCamera cam = build(cameraScene(k35mm + "setAttr \".ptsc\" 2;\n"), 640, 480, 4.0 / 3.0);
        EXPECT_NEAR(cam.windowRight, hw / 2, 1e-12);
    }
    {
        // Lens squeeze widens the horizontal aperture.
        const RenderCamera cam = build(cameraScene(k35mm + "setAttr \".lsr\" 2;\n"), 640, 480, 4.0 / 3.0);
        EXPECT_NEAR(cam.windowRight, 2 * hw, 1e-12);
    }
}

TEST(RenderCamera, OrthographicWindowFollowsOrthographicWidth) {
    const scene::Graph g = cameraScene(k35mm + "setAttr \".o\" yes;\nsetAttr \".ow\" 30;\n");
    const RenderCamera cam = build(g, 640, 480, 4.0 / 3.0);
    EXPECT_TRUE(cam.orthographic);
    EXPECT_NEAR(cam.windowLeft, -15.0, 1e-12);
    EXPECT_NEAR(cam.windowRight, 15.0, 1e-12);
    EXPECT_NEAR(cam.windowTop, 11.25, 1e-12);
    // Orthographic: depth does not change the raster position.
    const glm::dvec2 a = cam.rasterFromCamera({7.5, -5.625, -1});
    const glm::dvec2 b = cam.rasterFromCamera({7.5, -5.625, -100});
    EXPECT_NEAR(a.x, 480.0, 1e-9);
    EXPECT_NEAR(a.y, 360.0, 1e-9);
    EXPECT_NEAR(b.x, a.x, 1e-9);
    EXPECT_NEAR(b.y, a.y, 1e-9);

    // Vertical fit of an ortho camera uses the film gate's aspect: height = ow · vfa / hfa = 20.
    const scene::Graph gv = cameraScene(k35mm + "setAttr \".o\" yes;\nsetAttr \".ow\" 30;\nsetAttr \".ff\" 2;\n");
    const RenderCamera v = build(gv, 640, 480, 4.0 / 3.0);
    EXPECT_NEAR(v.windowTop - v.windowBottom, 20.0, 1e-12);
    EXPECT_NEAR(v.windowRight - v.windowLeft, 20.0 * 4.0 / 3.0, 1e-12);
}

TEST(RenderCamera, RayThroughInvertsRasterFromCamera) {
    for (const char* extra : {"", "setAttr \".o\" yes;\nsetAttr \".ow\" 12;\n", "setAttr \".fio\" -type \"double2\" 0.2 0.1;\n"}) {
        const RenderCamera cam = build(cameraScene(k35mm + extra), 320, 200, 1.6);
        for (double rx : {0.0, 13.25, 160.0, 319.5}) {
            for (double ry : {0.0, 99.0, 187.75}) {
                glm::dvec3 o, d;
                cam.rayThrough(rx, ry, o, d);
                EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
                EXPECT_LT(d.z, 0.0);
                const glm::dvec3 p = o + d * 17.0;
                const glm::dvec2 r = cam.rasterFromCamera(p);
                EXPECT_NEAR(r.x, rx, 1e-9) << extra;
                EXPECT_NEAR(r.y, ry, 1e-9) << extra;
            }
        }
    }
}

TEST(RenderCamera, DepthKeyRoundTrips) {
    const RenderCamera persp = build(cameraScene(k35mm), 64, 48, 4.0 / 3.0);
    const RenderCamera ortho = build(cameraScene(k35mm + "setAttr \".o\" yes;\n"), 64, 48, 4.0 / 3.0);
    for (double d : {0.1, 1.0, 3.5, 1234.5}) {
        const glm::dvec3 p{0.3, -0.2, -d};
        EXPECT_NEAR(persp.depthKey(p), -1.0 / d, 1e-15);
        EXPECT_NEAR(persp.distanceFromDepthKey(persp.depthKey(p)), d, 1e-9 * d);
        EXPECT_DOUBLE_EQ(ortho.depthKey(p), d);
        EXPECT_DOUBLE_EQ(ortho.distanceFromDepthKey(ortho.depthKey(p)), d);
    }
    // Nearer is smaller for both.
    EXPECT_LT(persp.depthKey({0, 0, -1}), persp.depthKey({0, 0, -2}));
    EXPECT_LT(ortho.depthKey({0, 0, -1}), ortho.depthKey({0, 0, -2}));
}

TEST(RenderCamera, WorldMatrixComesFromTheParentTransform) {
    const scene::Graph g = cameraScene(k35mm, "setAttr \".t\" -type \"double3\" 1 2 3;\nsetAttr \".ry\" 90;\n");
    const RenderCamera cam = build(g, 64, 48, 4.0 / 3.0);
    const glm::dvec4 eye = cam.worldFromCamera * glm::dvec4(0, 0, 0, 1);
    EXPECT_NEAR(eye.x, 1.0, 1e-12);
    EXPECT_NEAR(eye.y, 2.0, 1e-12);
    EXPECT_NEAR(eye.z, 3.0, 1e-12);
    // Rotated 90° about Y, the camera looks down world −X.
    const glm::dvec4 ahead = cam.worldFromCamera * glm::dvec4(0, 0, -1, 0);
    EXPECT_NEAR(ahead.x, -1.0, 1e-12);
    EXPECT_NEAR(ahead.z, 0.0, 1e-12);
    const glm::dmat4 id = cam.cameraFromWorld * cam.worldFromCamera;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(id[c][r], c == r ? 1.0 : 0.0, 1e-12);
}

TEST(RenderCamera, BackgroundColorAndClipPlanesAreRead) {
    const scene::Graph g = cameraScene(k35mm + "setAttr \".col\" -type \"float3\" 0.25 0.5 0.75;\n"
                                               "setAttr \".ncp\" 0.5;\nsetAttr \".fcp\" 200;\n");
    const RenderCamera cam = build(g, 64, 48, 4.0 / 3.0);
    EXPECT_NEAR(cam.backgroundColor.x, 0.25, 1e-7);
    EXPECT_NEAR(cam.backgroundColor.y, 0.5, 1e-7);
    EXPECT_NEAR(cam.backgroundColor.z, 0.75, 1e-7);
    EXPECT_DOUBLE_EQ(cam.nearClipPlane, 0.5);
    EXPECT_DOUBLE_EQ(cam.farClipPlane, 200.0);
}

// Expects makeRenderCamera to throw an Error whose message names the camera and `attr`.
void expectBad(const std::string& shapeAttrs, const std::string& attr, const std::string& transformAttrs = "") {
    const scene::Graph g = cameraScene(shapeAttrs, transformAttrs);
    try {
        (void)build(g, 64, 48, 4.0 / 3.0);
        ADD_FAILURE() << "no error for " << shapeAttrs << transformAttrs;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("cam1"), std::string::npos) << what;
        EXPECT_NE(what.find(attr), std::string::npos) << what;
    }
}

TEST(RenderCamera, BadAttributesThrowNamingCameraAndAttribute) {
    expectBad("setAttr \".fl\" 0;\n", "focalLength");
    expectBad("setAttr \".fl\" -5;\n", "focalLength");
    expectBad("setAttr \".hfa\" 0;\n", "horizontalFilmAperture");
    expectBad("setAttr \".vfa\" -1;\n", "verticalFilmAperture");
    expectBad("setAttr \".ncp\" 100;\nsetAttr \".fcp\" 10;\n", "farClipPlane");
    expectBad("setAttr \".ncp\" 0;\n", "nearClipPlane");
    expectBad("setAttr \".ncp\" -1;\n", "nearClipPlane");
    expectBad("setAttr \".ovr\" 0;\n", "overscan");
    expectBad("setAttr \".o\" yes;\nsetAttr \".ow\" 0;\n", "orthographicWidth");
    expectBad("setAttr \".ff\" 7;\n", "filmFit");
    expectBad("setAttr \".ff\" -1;\n", "filmFit");
    expectBad("", "singular", "setAttr \".s\" -type \"double3\" 1 0 1;\n");
}

TEST(RenderCamera, NonFiniteAttributesThrow) {
    scene::Graph g = cameraScene(k35mm);
    const scene::NodeId shape = g.find("cam1Shape");
    const double bad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()};
    for (const char* attr : {"focalLength", "horizontalFilmOffset", "nearClipPlane", "farClipPlane"}) {
        for (double v : bad) {
            scene::Graph copy = g;
            copy.setValue(shape, *scene::parsePlugPath(attr), scene::Numbers{scene::Numbers::Kind::Plain, 1, {v}});
            try {
                (void)build(copy, 64, 48, 4.0 / 3.0);
                ADD_FAILURE() << attr << " = " << v << " accepted";
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find(attr), std::string::npos) << e.what();
            }
        }
    }
    // A NaN in the transform makes the world matrix unusable.
    scene::Graph nanMatrix = g;
    nanMatrix.setValue(g.find("cam1"), *scene::parsePlugPath("tx"),
                       scene::Numbers{scene::Numbers::Kind::Plain, 1, {std::numeric_limits<double>::quiet_NaN()}});
    EXPECT_THROW((void)build(nanMatrix, 64, 48, 4.0 / 3.0), Error);
}

TEST(RenderCamera, BadImageShapeThrows) {
    const scene::Graph g = cameraScene(k35mm);
    EXPECT_THROW((void)build(g, 0, 48, 4.0 / 3.0), Error);
    EXPECT_THROW((void)build(g, 64, 48, 0.0), Error);
    EXPECT_THROW((void)build(g, 64, 48, std::numeric_limits<double>::quiet_NaN()), Error);
    scene::Evaluator ev(g, 1.0);
    EXPECT_THROW((void)makeRenderCamera(ev, {}, 64, 48, 1.0), Error);
}

}  // namespace
}  // namespace pushpin::render
