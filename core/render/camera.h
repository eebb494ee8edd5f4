// core/render/camera.h: Maya's camera model for rendering (reference/nodes.md §2): film back
// (focal length, horizontal/vertical film aperture in inches, lens squeeze, film fit Fill /
// Horizontal / Vertical / Overscan, film offsets, overscan, pre/post scale), orthographic cameras,
// near and far clip planes, the device aspect ratio of the output, and the background colour.
// Plain value after construction; thread-safe for concurrent const use.
//
// Camera space: +X right, +Y up, looking down −Z. Raster space: see fragment.h.
// The screen window is the rectangle [windowLeft, windowRight] × [windowBottom, windowTop] on the
// plane z = −1 (perspective: tangents of the view angles) or in camera units (orthographic) that
// maps onto the full image (0..width, 0..height).
//
// Numbers at the door: every camera attribute the model reads has a range (camera.cpp lists them,
// with the reason for each) and the camera's world matrix must stay within kMaxSceneCoordinate;
// makeRenderCamera refuses anything else with pushpin::Error, so the projection of any scene
// point the frame scene accepts (also bounded by kMaxSceneCoordinate) is a finite double.
// Memory: a RenderCamera is a few hundred bytes and charges nothing to the MemoryBudget.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/graph.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace pushpin::render {

// The largest magnitude of a world-space coordinate, a world-matrix entry or a camera distance
// the renderer accepts, in scene units (cm). Shading works in float: with every coordinate
// within 1e18, differences of two points stay within 2e18 and their squared lengths (distance
// falloff, normal lengths) within 1.2e37, inside float's 3.4e38. Objects, lights and cameras
// beyond it are refused at the door (buildFrameScene skips them with a note; makeRenderCamera
// throws) instead of overflowing later.
constexpr double kMaxSceneCoordinate = 1e18;

// Why a world matrix cannot place anything the renderer can project, or empty when it can: an
// entry that is not finite or beyond kMaxSceneCoordinate. Objects and lights with such a matrix
// are skipped with this reason in a note.
std::string worldMatrixProblem(const glm::dmat4& m);

struct RenderCamera {
    std::string name;           // the camera transform's name ("persp")
    scene::NodeId shape = scene::kNoNode;
    glm::dmat4 worldFromCamera{1.0};
    glm::dmat4 cameraFromWorld{1.0};
    int width = 640, height = 480;  // output pixels
    double deviceAspectRatio = 4.0 / 3.0;
    bool orthographic = false;
    double windowLeft = -1, windowRight = 1, windowBottom = -0.75, windowTop = 0.75;
    double nearClipPlane = 0.1, farClipPlane = 10000.0;  // distances along −Z, scene units (cm)
    glm::dvec3 backgroundColor{0.0};

    // Raster position of a camera-space point. Perspective: the point must be in front of the
    // camera (z < 0); callers clip against the near plane first.
    glm::dvec2 rasterFromCamera(const glm::dvec3& p) const;
    // The depth key (fragment.h) of a camera-space point: −1/distance (perspective) or distance
    // (orthographic), distance = −p.z.
    double depthKey(const glm::dvec3& p) const;
    // Distance along the view axis (−Z) from a depth key.
    double distanceFromDepthKey(double key) const;
    // The camera-space ray through a raster position: origin (the eye, or the point on the z = 0
    // plane for orthographic cameras) and unit direction.
    void rayThrough(double rasterX, double rasterY, glm::dvec3& origin, glm::dvec3& direction) const;
};

// Builds the render camera of one camera-shape instance (`dagPath` ends at the shape) at the
// evaluator's frame for an image of width × height pixels and the given device aspect ratio.
// Throws pushpin::Error naming the camera (its DAG path) and the attribute and value when the
// camera makes no image: a value that is NaN/Inf or outside its range (focalLength 0.001..1e7 mm,
// film apertures 1e-6..1e4 in, film offsets within ±1e4 in, lensSqueezeRatio, overscan,
// preScale and postScale 0.001..1000, orthographicWidth 1e-6..1e18, clip planes within
// ±1e18 with near < far and, for perspective cameras, near >= 1e-6), a filmFit that is no
// mode, a world matrix with an entry beyond kMaxSceneCoordinate or a singular 3×3 part.
// Example: "camera '|persp|perspShape': focalLength 1e+308 is out of range (0.001..1e+07 mm)".
RenderCamera makeRenderCamera(scene::Evaluator& ev, const std::vector<scene::NodeId>& dagPath, int width,
                              int height, double deviceAspectRatio);

}  // namespace pushpin::render
