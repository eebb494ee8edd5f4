// core/scene/detail/multi_elements.h: reading the elements of multi attributes during geometry
// evaluation (mesh history, deformers): stored numeric runs, element indices of connection plugs,
// and per-element vectors with their driven elements evaluated.
// Thread safety: as the Graph and the Evaluator passed in. Memory: results are owned by the caller.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/graph.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace pushpin::scene::detail {

// Elements beyond this index are refused: a hostile `.vt[2000000000]` must not allocate 24 GB.
constexpr uint64_t kMaxElements = uint64_t(1) << 27;

// "type (name)": how evaluation messages name a node.
std::string nodeLabel(const Node& n);

// Calls fn(index, values, width) for every stored numeric element of a multi attribute below
// kMaxElements, in index order.
template <class F>
void forEachNumeric(const AttrData& a, F&& fn) {
    for (const auto& [first, run] : a.multi.runs()) {
        const Numbers* nums = std::get_if<Numbers>(&run.value);
        if (!nums || run.width <= 0) continue;
        const size_t width = size_t(run.width);
        if (nums->values.empty() && width > kMaxCompactWidth) continue;  // never stored so
        double element[kMaxCompactWidth];
        for (uint32_t k = 0; k < run.count; ++k) {
            if ((size_t(k) + 1) * width > nums->size()) break;
            if (uint64_t(first) + k >= kMaxElements) return;
            if (!nums->values.empty()) {
                fn(uint64_t(first) + k, nums->values.data() + size_t(k) * width, run.width);
            } else {
                nums->copyTo(size_t(k) * width, width, element);
                fn(uint64_t(first) + k, static_cast<const double*>(element), run.width);
            }
        }
    }
}

// The index right after `prefix` + "[" in a plug path ("weightList[3].weights" after
// "weightList" → 3), if the path starts that way and the index is below kMaxElements.
std::optional<uint32_t> elementIndexAfter(std::string_view path, std::string_view prefix);

// The elements of the multi attribute stored under canonical key `key` (polyTweak's "tweak",
// "plist[0].controlPoints") as vectors of `width` components (at most 3, the rest zero): stored
// values, then the elements a connection drives, evaluated through the Evaluator.
std::map<uint32_t, glm::dvec3> vectorElements(Evaluator& ev, NodeId node, const std::string& key, int width);

}  // namespace pushpin::scene::detail
