// Maya's camera model (reference/nodes.md §2). The film back is reduced to one screen window on
// the z = −1 plane (perspective) or in camera units (orthographic); everything the renderer asks
// of the camera (projection, depth keys, primary rays) is a linear map of that window.
#include "core/render/camera.h"

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
    std::string cameraName;

    [[noreturn]] void fail(const std::string& attr, const std::string& why) const {
        throw Error("camera '" + cameraName + "': " + attr + " " + why);
    }
    double finite(const char* attr, double fallback) const {
        const double v = ev.getDouble(shape, attr, fallback);
        if (!std::isfinite(v)) fail(attr, "is " + util::formatNumber(v) + " (must be a finite number)");
        return v;
    }
    double positive(const char* attr, double fallback) const {
        const double v = finite(attr, fallback);
        if (!(v > 0.0)) fail(attr, "is " + util::formatNumber(v) + " (must be > 0)");
        return v;
    }
};

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
    CameraReader rd{ev, cam.shape, cam.name};

    if (width < 1 || height < 1)
        throw Error("camera '" + cam.name + "': image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " has no pixels");
    if (!std::isfinite(deviceAspectRatio) || !(deviceAspectRatio > 0.0))
        throw Error("camera '" + cam.name + "': device aspect ratio " + util::formatNumber(deviceAspectRatio) +
                    " must be a positive number");
    cam.width = width;
    cam.height = height;
    cam.deviceAspectRatio = deviceAspectRatio;

    cam.orthographic = ev.getBool(cam.shape, "orthographic", false);
    const double focalLength = rd.positive("focalLength", 35.0);
    const double hfa = rd.positive("horizontalFilmAperture", 1.41732);
    const double vfa = rd.positive("verticalFilmAperture", 0.94488);
    const double squeeze = rd.positive("lensSqueezeRatio", 1.0);
    const double hfo = rd.finite("horizontalFilmOffset", 0.0);
    const double vfo = rd.finite("verticalFilmOffset", 0.0);
    const double overscan = rd.positive("overscan", 1.0);
    const double preScale = rd.positive("preScale", 1.0);
    const double postScale = rd.positive("postScale", 1.0);
    const double orthoWidth = cam.orthographic ? rd.positive("orthographicWidth", 10.0) : 0.0;
    const double filmFitValue = ev.getDouble(cam.shape, "filmFit", kHorizontal);
    if (!(filmFitValue >= kFill && filmFitValue <= kOverscan) || filmFitValue != std::floor(filmFitValue))
        rd.fail("filmFit", "is " + util::formatNumber(filmFitValue) + " (must be 0 Fill, 1 Horizontal, 2 Vertical or 3 Overscan)");
    const int filmFit = static_cast<int>(filmFitValue);
    cam.nearClipPlane = rd.finite("nearClipPlane", 0.1);
    cam.farClipPlane = rd.finite("farClipPlane", 10000.0);
    if (!cam.orthographic && !(cam.nearClipPlane > 0.0))
        rd.fail("nearClipPlane", "is " + util::formatNumber(cam.nearClipPlane) + " (must be > 0 for a perspective camera)");
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
    if (!std::isfinite(halfW) || !std::isfinite(halfH) || !(halfW > 0.0) || !(halfH > 0.0) ||
        !std::isfinite(cam.windowLeft) || !std::isfinite(cam.windowRight) || !std::isfinite(cam.windowBottom) ||
        !std::isfinite(cam.windowTop))
        rd.fail("film back", "gives no usable screen window");

    cam.worldFromCamera = ev.worldMatrix(dagPath);
    bool finiteMatrix = true;
    double columnScale = 1.0;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) finiteMatrix = finiteMatrix && std::isfinite(cam.worldFromCamera[c][r]);
        if (c < 3) columnScale *= glm::length(glm::dvec3(cam.worldFromCamera[c]));
    }
    // Singular when the 3×3 part has lost a dimension relative to the lengths of its axes.
    const double det = glm::determinant(cam.worldFromCamera);
    if (!finiteMatrix || !std::isfinite(det) || !(std::abs(det) > 1e-12 * columnScale))
        throw Error("camera '" + cam.name + "': world matrix is singular or not finite (scale 0 or NaN on the path)");
    cam.cameraFromWorld = glm::inverse(cam.worldFromCamera);
    return cam;
}

}  // namespace pushpin::render
