// core/scene/schema.h: what pushpin knows about Maya node types: for each supported type its
// attributes with long/short names, types, units and Maya's defaults (reference/nodes.md,
// reference/render-globals.md), and its base type. Types and attributes outside the schema are
// kept generically by the Graph and reported as unsupported. The tables are built once, on first
// use, and are read-only afterwards: every function here is thread-safe.
#pragma once

#include "core/scene/units.h"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace pushpin::scene {

enum class AttrType : unsigned char {
    Bool, Int, Enum, Float, Double,                // scalars
    Double2, Double3, Double4, Float2, Float3,     // numeric compounds (children are components)
    Long2, Long3, Short2, Short3,
    String, StringArray, Matrix, Message,
    Compound,                                      // compound with non-component children
    Mesh, NurbsCurve, NurbsSurface,                // geometry data
    ComponentList, PolyFaces, Int32Array, DoubleArray, PointArray, VectorArray,
    Generic,                                       // any data
};

// Number of numeric components of a value of this type (1 for scalars, 3 for Double3 …), 0 otherwise.
int componentCount(AttrType type);

struct AttrSpec {
    std::string longName;
    std::string shortName;
    AttrType type = AttrType::Double;
    UnitKind unit = UnitKind::None;  // applies to every numeric component
    bool multi = false;              // an array attribute (`name[i]`)
    std::string parent;              // long name of the compound parent, empty at top level
    int component = -1;              // index within a numeric compound parent (translateX → 0)
    std::array<double, 4> defaults{0, 0, 0, 0};
};

class NodeSchema {
public:
    NodeSchema(std::string type, const NodeSchema* base);
    const std::string& type() const { return m_type; }
    const NodeSchema* base() const { return m_base; }
    // Finds an attribute by long or short name, searching base types too; nullptr if unknown.
    const AttrSpec* find(std::string_view name) const;
    // True if this type is `type` or derives from it (e.g. blinn isA "lambert", mesh isA "dagNode").
    bool isA(std::string_view type) const;
    bool isA(const NodeSchema* type) const {
        for (const NodeSchema* s = this; s; s = s->m_base)
            if (s == type) return true;
        return false;
    }
    bool isDag() const { return m_dag; }  // isA("dagNode")
    // Attributes declared on this type (not its bases).
    const std::vector<AttrSpec>& ownAttributes() const { return m_attrs; }

    void add(AttrSpec spec);  // used while building the tables
    // Builds the lookup of every name, own and inherited, once all the tables are built.
    void finalize();

private:
    struct NameHash {
        using is_transparent = void;
        size_t operator()(std::string_view s) const { return std::hash<std::string_view>()(s); }
    };
    std::string m_type;
    const NodeSchema* m_base;
    bool m_dag = false;
    std::vector<AttrSpec> m_attrs;
    // Long and short names of this type's and its bases' attributes; a name declared here hides
    // the same name on a base. Filled by finalize().
    std::unordered_map<std::string, const AttrSpec*, NameHash, std::equal_to<>> m_byName;
};

// The schema of a node type, or nullptr if pushpin does not model that type.
const NodeSchema* findSchema(std::string_view type);
// Every modelled node type (for tests and documentation).
std::vector<std::string> schemaTypes();

}  // namespace pushpin::scene
