// core/scene/detail/multi_elements.h: reading the elements of multi attributes during geometry
// evaluation (mesh history, deformers): stored numeric runs, element indices of connection plugs,
// and per-element vectors with their driven elements evaluated.
// Thread safety: as the Graph and the Evaluator passed in. Memory: results are owned by the caller.
#pragma once

#include "core/scene/evaluator.h"
#include "core/scene/graph.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace pushpin::scene::detail {

// Elements beyond this index are refused: a hostile `.vt[2000000000]` must not allocate 24 GB.
constexpr uint64_t kMaxElements = uint64_t(1) << 27;

// "type (name)": how evaluation messages name a node.
std::string nodeLabel(const Node& n);

// Calls fn(index, values, width) for the stored numeric elements of a multi attribute in
// [first, end), in index order.
template <class F>
void forEachNumericIn(const AttrData& a, uint64_t first, uint64_t end, F&& fn) {
    const auto& runs = a.multi.runs();
    auto it = runs.upper_bound(uint32_t(std::min<uint64_t>(first, UINT32_MAX)));
    if (it != runs.begin()) --it;
    // Compact runs are read a chunk of elements at a time (packed integers decode by blocks).
    constexpr size_t kChunkNumbers = 1024;
    double chunk[kChunkNumbers];
    for (; it != runs.end() && it->first < end; ++it) {
        const Numbers* nums = std::get_if<Numbers>(&it->second.value);
        if (!nums || it->second.width <= 0 || (nums->values.empty() && size_t(it->second.width) > kMaxCompactWidth))
            continue;
        const size_t width = size_t(it->second.width);
        const uint64_t from = std::max<uint64_t>(first, it->first);
        const uint64_t to = std::min<uint64_t>({end, uint64_t(it->first) + it->second.count, it->first + nums->size() / width});
        if (!nums->values.empty()) {
            for (uint64_t i = from; i < to; ++i) fn(i, nums->values.data() + size_t(i - it->first) * width, int(width));
            continue;
        }
        const uint64_t perChunk = kChunkNumbers / width;
        for (uint64_t i = from; i < to;) {
            const uint64_t n = std::min<uint64_t>(perChunk, to - i);
            nums->copyTo(size_t(i - it->first) * width, size_t(n) * width, chunk);
            for (uint64_t k = 0; k < n; ++k) fn(i + k, static_cast<const double*>(chunk + k * width), int(width));
            i += n;
        }
    }
}

// The same for every element below kMaxElements.
template <class F>
void forEachNumeric(const AttrData& a, F&& fn) {
    forEachNumericIn(a, 0, kMaxElements, std::forward<F>(fn));
}

// The index right after `prefix` + "[" in a plug path ("weightList[3].weights" after
// "weightList" → 3), if the path starts that way and the index is below kMaxElements.
std::optional<uint32_t> elementIndexAfter(std::string_view path, std::string_view prefix);

// The elements of the multi attribute stored under canonical key `key` (polyTweak's "tweak",
// "plist[0].controlPoints") as vectors of `width` components (at most 3, the rest zero): stored
// values, then the elements a connection drives, evaluated through the Evaluator.
std::map<uint32_t, glm::dvec3> vectorElements(Evaluator& ev, NodeId node, const std::string& key, int width);

}  // namespace pushpin::scene::detail
