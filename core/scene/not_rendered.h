// core/scene/not_rendered.h: the features a scene turns on that pushpin does not render yet
// (depth-map shadows, ray tracing, motion blur, glow, fog, displacement, particles, image planes,
// plug-in shading, extra render layers), each with the nodes that ask for it. A render prints
// them once and lists them under "notRendered" in --stats; --info lists them too.
// Pure reads at the Evaluator's frame; one Evaluator per thread.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/render_setup.h"

#include <cstddef>
#include <string>
#include <vector>

namespace pushpin::scene {

struct NotRendered {
    std::string feature;              // "depth-map shadows", "motion blur", …
    std::vector<std::string> nodes;   // the nodes that turn it on, at most kMaxNotRenderedNodes
    size_t count = 0;                 // how many nodes in all
};

inline constexpr size_t kMaxNotRenderedNodes = 50;

// In a stable order: by feature as listed in the header comment, nodes in scene order.
std::vector<NotRendered> notRenderedFeatures(Evaluator& ev, const RenderSetup& setup);

// "depth-map shadows (spotLightShape1, …)": one line for a note.
std::string describeNotRendered(const NotRendered& n);

}  // namespace pushpin::scene
