#include "core/scene/detail/multi_elements.h"

#include <algorithm>
#include <vector>

namespace pushpin::scene::detail {

std::string nodeLabel(const Node& n) { return n.type + " (" + n.name + ")"; }

std::optional<uint32_t> elementIndexAfter(std::string_view path, std::string_view prefix) {
    if (path.size() <= prefix.size() + 1 || path.substr(0, prefix.size()) != prefix || path[prefix.size()] != '[')
        return std::nullopt;
    uint64_t v = 0;
    size_t i = prefix.size() + 1;
    for (; i < path.size() && path[i] >= '0' && path[i] <= '9'; ++i) {
        v = v * 10 + uint64_t(path[i] - '0');
        if (v >= kMaxElements) return std::nullopt;
    }
    if (i == prefix.size() + 1 || i >= path.size() || path[i] != ']') return std::nullopt;
    return uint32_t(v);
}

std::map<uint32_t, glm::dvec3> vectorElements(Evaluator& ev, NodeId node, const std::string& key, int width) {
    const Graph& g = ev.graph();
    width = std::clamp(width, 0, 3);
    std::map<uint32_t, glm::dvec3> out;
    if (const AttrData* a = g.findAttr(node, key))
        forEachNumeric(*a, [&](uint64_t i, const double* v, int w) {
            glm::dvec3 value(0.0);
            for (int k = 0; k < std::min(w, width); ++k) value[k] = v[k];
            out[uint32_t(i)] = value;
        });
    std::vector<double> v;
    for (const Connection* c : g.inputs(node)) {
        const std::optional<uint32_t> i = elementIndexAfter(c->dst.path, key);
        if (!i) continue;
        // The whole element is evaluated: a connection into one component updates that component.
        if (ev.numbers(node, key + "[" + std::to_string(*i) + "]", v) && v.size() >= size_t(width)) {
            glm::dvec3 value(0.0);
            for (int k = 0; k < width; ++k) value[k] = v[size_t(k)];
            out[*i] = value;
        }
    }
    return out;
}

}  // namespace pushpin::scene::detail
