// core/geom/union_find.h: disjoint sets over 0..n-1 whose root is always the lowest index of its
// set, so that "the group keeps its lowest index" rules (merged points, extrusion regions, welded
// seams, smoothing groups) read the root directly. Path halving; no ranks (the lowest-index rule
// fixes the root). Thread safety: a value; find() mutates (path halving).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace pushpin::geom {

class LowestRootSets {
public:
    explicit LowestRootSets(size_t n) : m_parent(n) { std::iota(m_parent.begin(), m_parent.end(), 0u); }

    uint32_t find(uint32_t x) {
        while (m_parent[x] != x) x = m_parent[x] = m_parent[m_parent[x]];
        return x;
    }
    void join(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) m_parent[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<uint32_t> m_parent;
};

}  // namespace pushpin::geom
