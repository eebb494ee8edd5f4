// core/scene/components.h: Maya component strings ("f[0:5]", "vtx[3]", "e[*]", "map[1:4]",
// "vtxFace[2][0:1]") as they appear in componentList values (objectGrpCompList of per-face
// shading assignments, groupParts.inputComponents, deleteComponent.deleteComponents), parsed
// into index ranges, and turned into per-element masks.
// Pure functions; thread-safe. Bad input gives error text, never an exception or a crash.
#pragma once

#include "core/scene/value.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pushpin::scene {

enum class ComponentKind : unsigned char {
    Face,        // f[...]
    Vertex,      // vtx[...]
    Edge,        // e[...]
    Uv,          // map[...]
    VertexFace,  // vtxFace[vertex][face]
    Other,       // any other name (cv, u, v, sf …): parsed, never matched to mesh elements
};

// "[*]" (every index) as a range end.
constexpr int64_t kAllIndices = -1;

struct IndexRange {
    int64_t first = 0;
    int64_t last = kAllIndices;  // inclusive; kAllIndices: to the end
    bool all() const { return last == kAllIndices; }
};

struct ComponentRange {
    ComponentKind kind = ComponentKind::Other;
    std::string name;               // as written: "f", "vtx", "vtxFace" …
    IndexRange range;               // first bracket
    std::optional<IndexRange> second;  // second bracket of two-index components (vtxFace)
};

// Parses one component string. Accepts surrounding whitespace and an object prefix before the
// last '.' ("pCubeShape1.f[2]"). Indices are non-negative decimal integers below 2^31; a range
// is "a:b" with a ≤ b, or "*". Returns nullopt and sets `error` on malformed input.
std::optional<ComponentRange> parseComponent(std::string_view text, std::string* error = nullptr);

struct ParsedComponents {
    std::vector<ComponentRange> ranges;
    std::vector<std::string> errors;  // one per item that did not parse, naming it
};
// Parses every item of a componentList; items that fail are reported and skipped.
ParsedComponents parseComponents(const ComponentList& list);

// Marks the elements of `kind` that `ranges` cover, for `count` elements. Ranges reaching past
// the end are clipped and reported in `error` (when given); ranges of other kinds are ignored.
std::vector<bool> componentMask(const std::vector<ComponentRange>& ranges, ComponentKind kind, size_t count,
                                std::string* error = nullptr);

// Per-face selection of a componentList for a mesh of `faceCount` faces (shading-group
// assignment through objectGrpCompList). Unparsable items, non-face items and indices past
// the end are reported in `error` (joined with "; ") and otherwise ignored.
std::vector<bool> faceMask(const ComponentList& list, size_t faceCount, std::string* error = nullptr);

}  // namespace pushpin::scene
