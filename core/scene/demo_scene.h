// core/scene/demo_scene.h: the built-in demo scene, a Maya ASCII text compiled into the binary:
// the soft-spotlight lesson — a floor, a figure built from primitives, a spotlight with penumbra,
// dropoff and quadratic decay, and an ambient fill at 0.25.
#pragma once

#include <string_view>

namespace pushpin::scene {

// The demo scene's .ma text (static storage). Readable by MaReader like any file.
std::string_view demoSceneText();
// The name the demo scene goes by in messages and output file names.
constexpr std::string_view kDemoSceneName = "softSpotlight.ma";

}  // namespace pushpin::scene
