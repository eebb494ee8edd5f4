// Maya's camera model (reference/nodes.md §2). The film back is reduced to one screen window on
// the z = −1 plane (perspective) or in camera units (orthographic); everything the renderer asks
// of the camera (projection, depth keys, primary rays) is a linear map of that window.
#include "core/render/camera.h"

#include "core/geom/finite.h"
#include "core/util/format.h"


#include "cache/error.h"

#include <glm/matrix.hpp>

#include <cmath>
#include <sstream>

namespace pushpin::render {

namespace {

constexpr double kMmPerInch = 25.4;

// filmFit values (nodes.md §2).
constexpr int kFill = 0, kHorizontal = 1, kVertical = 2, kOverscan = 3;

struct CameraReader {
    scene::Evaluator& ev;
    scene::NodeId shape;
    std::string cameraLabel;  // the camera's DAG path, excerpted

    [[noreturn]] void fail(const std::string& attr, const std::string& why) const {
        throw Error("camera '" + cameraLabel + "': " + attr + " " + why);
    }
    // A value the model can use: finite and within [lo, hi]; `range` says so in the message.
    double ranged(const char* attr, double fallback, double lo, double hi, const char* range) const {
        const double v = ev.getDouble(shape, attr, fallback);
        if (!std::isfinite(v) || v < lo || v > hi)
            fail(attr, util::formatNumber(v, 10) + " is out of range (" + range + ")");
        return v;
    }
};

// Door ranges of the camera attributes. They are pushpin's, far wider than any real lens or
// film back, and chosen so that the screen window built from them (camera.h) spans between
// about 1e-24 and 1e17 on the z = −1 plane: projecting any camera-space point within
// 2·kMaxSceneCoordinate then gives raster positions below 1e60 pixels, which the binning,
// rasterizer and depth planes handle in double without overflow.
constexpr double kMinFocalLengthMm = 1e-3, kMaxFocalLengthMm = 1e7;
constexpr double kMinApertureInches = 1e-6, kMaxApertureInches = 1e4;
constexpr double kMaxFilmOffsetInches = 1e4;
constexpr double kMinFactor = 1e-3, kMaxFactor = 1e3;  // lensSqueezeRatio, overscan, pre/postScale
constexpr double kMinOrthographicWidth = 1e-6;
constexpr double kMinNearClipPlane = 1e-6;  // perspective: depth keys are −1/distance
// A camera transform that shrinks or grows space by more than this makes camera-space
// coordinates leave the bounds kMaxSceneCoordinate guarantees for world space.
constexpr double kMinAxisScale = 1e-6, kMaxAxisScale = 1e6;

}  // namespace

glm::dvec2 RenderCamera::rasterFromCamera(const glm::dvec3& p) const {
    double sx = p.x, sy = p.y;
    if (!orthographic) {
        const double invDepth = 1.0 / -p.z;
        sx *= invDepth;
        sy *= invDepth;
    }
    // Raster y runs down from the top edge of the window (fragment.h).
    return {(sx - windowLeft) / (windowRight - windowLeft) * width,
            (windowTop - sy) / (windowTop - windowBottom) * height};
}

double RenderCamera::depthKey(const glm::dvec3& p) const {
    const double distance = -p.z;
    return orthographic ? distance : -1.0 / distance;
}

double RenderCamera::distanceFromDepthKey(double key) const { return orthographic ? key : -1.0 / key; }

void RenderCamera::rayThrough(double rasterX, double rasterY, glm::dvec3& origin, glm::dvec3& direction) const {
    const double sx = windowLeft + rasterX / width * (windowRight - windowLeft);
    const double sy = windowTop - rasterY / height * (windowTop - windowBottom);
    if (orthographic) {
        origin = {sx, sy, 0.0};
        direction = {0.0, 0.0, -1.0};
    } else {
        origin = {0.0, 0.0, 0.0};
        direction = glm::normalize(glm::dvec3(sx, sy, -1.0));
    }
}

RenderCamera makeRenderCamera(scene::Evaluator& ev, const std::vector<scene::NodeId>& dagPath, int width,
                              int height, double deviceAspectRatio) {
    if (dagPath.empty()) throw Error("camera: empty DAG path");
    const scene::Graph& g = ev.graph();
    RenderCamera cam;
    cam.shape = dagPath.back();
    if (cam.shape >= g.size()) throw Error("camera: DAG path ends at an unknown node");
    cam.name = dagPath.size() >= 2 ? g.node(dagPath[dagPath.size() - 2]).name : g.node(cam.shape).name;
    CameraReader rd{ev, cam.shape, util::excerpt(g.dagPathName(dagPath))};

    if (width < 1 || height < 1)
        throw Error("camera '" + rd.cameraLabel + "': image size " + std::to_string(width) + "x" +
                    std::to_string(height) + " has no pixels");
    if (!std::isfinite(deviceAspectRatio) || !(deviceAspectRatio > 0.0))
        throw Error("camera '" + rd.cameraLabel + "': device aspect ratio " + util::formatNumber(deviceAspectRatio) +
                    " must be a positive number");
    cam.width = width;
    cam.height = height;
    cam.deviceAspectRatio = deviceAspectRatio;

    cam.orthographic = ev.getBool(cam.shape, "orthographic", false);
    const double focalLength = rd.ranged("focalLength", 35.0, kMinFocalLengthMm, kMaxFocalLengthMm, "0.001..1e7 mm");
    const double hfa = rd.ranged("horizontalFilmAperture", 1.41732, kMinApertureInches, kMaxApertureInches,
                                 "1e-6..1e4 inches");
    const double vfa = rd.ranged("verticalFilmAperture", 0.94488, kMinApertureInches, kMaxApertureInches,
                                 "1e-6..1e4 inches");
    const double squeeze = rd.ranged("lensSqueezeRatio", 1.0, kMinFactor, kMaxFactor, "0.001..1000");
    const double hfo = rd.ranged("horizontalFilmOffset", 0.0, -kMaxFilmOffsetInches, kMaxFilmOffsetInches,
                                 "-1e4..1e4 inches");
    const double vfo = rd.ranged("verticalFilmOffset", 0.0, -kMaxFilmOffsetInches, kMaxFilmOffsetInches,
                                 "-1e4..1e4 inches");
    const double overscan = rd.ranged("overscan", 1.0, kMinFactor, kMaxFactor, "0.001..1000");
    const double preScale = rd.ranged("preScale", 1.0, kMinFactor, kMaxFactor, "0.001..1000");
    const double postScale = rd.ranged("postScale", 1.0, kMinFactor, kMaxFactor, "0.001..1000");
    const double orthoWidth = cam.orthographic ? rd.ranged("orthographicWidth", 10.0, kMinOrthographicWidth,
                                                           kMaxSceneCoordinate, "1e-6..1e18 scene units")
                                               : 0.0;
    const double filmFitValue = ev.getDouble(cam.shape, "filmFit", kHorizontal);
    if (!(filmFitValue >= kFill && filmFitValue <= kOverscan) || filmFitValue != std::floor(filmFitValue))
        rd.fail("filmFit", "is " + util::formatNumber(filmFitValue) + " (must be 0 Fill, 1 Horizontal, 2 Vertical or 3 Overscan)");
    const int filmFit = static_cast<int>(filmFitValue);
    if (cam.orthographic)
        cam.nearClipPlane = rd.ranged("nearClipPlane", 0.1, -kMaxSceneCoordinate, kMaxSceneCoordinate,
                                      "-1e18..1e18 scene units");
    else
        cam.nearClipPlane = rd.ranged("nearClipPlane", 0.1, kMinNearClipPlane, kMaxSceneCoordinate,
                                      "1e-6..1e18 scene units for a perspective camera");
    cam.farClipPlane = rd.ranged("farClipPlane", 10000.0, -kMaxSceneCoordinate, kMaxSceneCoordinate,
                                 "-1e18..1e18 scene units");
    if (!(cam.nearClipPlane < cam.farClipPlane))
        rd.fail("nearClipPlane", "(" + util::formatNumber(cam.nearClipPlane) + ") is not less than farClipPlane (" +
                                     util::formatNumber(cam.farClipPlane) + ")");
    cam.backgroundColor = ev.getDouble3(cam.shape, "backgroundColor", glm::dvec3(0.0));
    if (!std::isfinite(cam.backgroundColor.x) || !std::isfinite(cam.backgroundColor.y) ||
        !std::isfinite(cam.backgroundColor.z))
        rd.fail("backgroundColor", "is not finite");

    // The film gate in window units: tangents on the z = −1 plane for perspective cameras
    // (an aperture of a millimetres at focal length f spans a / f), camera units for orthographic
    // ones (orthographicWidth spans the squeezed horizontal aperture; the vertical follows the
    // apertures' aspect). `unitsPerInch` converts film offsets the same way.
    const double filmWidthInches = hfa * squeeze;
    const double unitsPerInch = cam.orthographic ? orthoWidth / filmWidthInches : kMmPerInch / focalLength;
    const double filmWidth = filmWidthInches * unitsPerInch;
    const double filmHeight = vfa * unitsPerInch;
    const double filmAspect = filmWidth / filmHeight;

    // Film fit (nodes.md §2): Fill puts the resolution gate inside the film gate, Overscan the
    // film gate inside the resolution gate; Horizontal/Vertical match one dimension. Both equal
    // Horizontal or Vertical depending on which aspect is wider.
    int fit = filmFit;
    if (fit == kFill) fit = deviceAspectRatio > filmAspect ? kHorizontal : kVertical;
    if (fit == kOverscan) fit = deviceAspectRatio > filmAspect ? kVertical : kHorizontal;
    double windowWidth, windowHeight;
    if (fit == kHorizontal) {
        windowWidth = filmWidth;
        windowHeight = filmWidth / deviceAspectRatio;
    } else {
        windowHeight = filmHeight;
        windowWidth = filmHeight * deviceAspectRatio;
    }

    // overscan widens the window about its centre (shows more, changes no perspective).
    // preScale and postScale are read as 2D scales of the projected image, applied after the
    // film offset: a value of 2 doubles the image, i.e. halves the window about the offset
    // centre. Without film translate and roll (not modelled) their order does not matter.
    const double scale = overscan / (preScale * postScale);
    const double halfW = 0.5 * windowWidth * scale;
    const double halfH = 0.5 * windowHeight * scale;
    const double centerX = hfo * unitsPerInch;
    const double centerY = vfo * unitsPerInch;
    cam.windowLeft = centerX - halfW;
    cam.windowRight = centerX + halfW;
    cam.windowBottom = centerY - halfH;
    cam.windowTop = centerY + halfH;
    // The ranges above keep every term finite; a film offset that dwarfs the window could still
    // round both edges to one value, which would divide by zero in rasterFromCamera.
    if (!std::isfinite(halfW) || !std::isfinite(halfH) || !(halfW > 0.0) || !(halfH > 0.0) ||
        !std::isfinite(cam.windowLeft) || !std::isfinite(cam.windowRight) || !std::isfinite(cam.windowBottom) ||
        !std::isfinite(cam.windowTop) || !(cam.windowRight > cam.windowLeft) || !(cam.windowTop > cam.windowBottom))
        rd.fail("film back", "gives no usable screen window (the film offset is too large for the aperture)");

    cam.worldFromCamera = ev.worldMatrix(dagPath);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            const double v = cam.worldFromCamera[c][r];
            if (!std::isfinite(v))
                throw Error("camera '" + rd.cameraLabel + "': world matrix is not finite (NaN or Inf on the path)");
            if (std::abs(v) > kMaxSceneCoordinate)
                throw Error("camera '" + rd.cameraLabel + "': world matrix entry " + util::formatNumber(v, 10) +
                            " is out of range (|value| <= 1e18 scene units; a translate or scale on the path is too large)");
        }
    double columnScale = 1.0;
    for (int c = 0; c < 3; ++c) {
        const double axis = glm::length(glm::dvec3(cam.worldFromCamera[c]));
        columnScale *= axis;
        if (axis != 0.0 && (axis < kMinAxisScale || axis > kMaxAxisScale))
            throw Error("camera '" + rd.cameraLabel + "': world matrix scales the camera by " + util::formatNumber(axis, 10) +
                        " (must be 1e-6..1e6)");
    }
    // Singular when the 3×3 part has lost a dimension relative to the lengths of its axes.
    const double det = glm::determinant(cam.worldFromCamera);
    if (!std::isfinite(det) || !(std::abs(det) > 1e-12 * columnScale))
        throw Error("camera '" + rd.cameraLabel + "': world matrix is singular (scale 0 on the path)");
    cam.cameraFromWorld = glm::inverse(cam.worldFromCamera);
    return cam;
}

std::string worldMatrixProblem(const glm::dmat4& m) {
    if (!geom::isFinite(m)) return "non-finite world matrix";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (std::abs(m[c][r]) > kMaxSceneCoordinate)
                return "world matrix entry " + util::formatNumber(m[c][r], 6) +
                       " is beyond 1e18 scene units (a translate or scale on the path is too large)";
    return {};
}

}  // namespace pushpin::render
