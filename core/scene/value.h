// core/scene/value.h: the typed values a .ma `setAttr` can carry, as plain data.
// Values are immutable once stored in a Graph; large payloads are shared, never copied.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace pushpin::scene {

// Numbers of any `setAttr` form: scalars, tuples (double3 …), numeric arrays and matrices.
// `kind` records the declared layout; `values` holds all numbers flat.
struct Numbers {
    enum class Kind : unsigned char {
        Plain,        // no -type: scalars/bools/enums, or a flat list for a range of elements
        Tuple,        // double2/3/4, float2/3, long2/3, short2/3 (also repeated for ranges)
        Int32Array,   // N values
        DoubleArray,  // N values
        PointArray,   // N × (x y z w)
        VectorArray,  // N × (x y z)
        Matrix,       // 16 values, row-major, translation in the 4th row
    };
    Kind kind = Kind::Plain;
    int tupleSize = 1;  // components per element for Tuple (2..4), 4 for PointArray, 3 for VectorArray
    std::vector<double> values;
};

struct StringValue { std::string text; };
struct StringArray { std::vector<std::string> items; };

// `-type "componentList" N "f[0:5]" "vtx[3]" …`
struct ComponentList { std::vector<std::string> items; };

// `-type "polyFaces"`: face records with edge loops (signed edge ids, see reference/ma-format.md).
struct PolyFaceLoop {
    std::vector<int32_t> edges;                                 // signed; e < 0 walks edge ~e backwards
    std::vector<std::pair<int32_t, std::vector<int32_t>>> uvs;  // (uv set index, uv ids per vertex)
    std::vector<int32_t> colors;                                // colour ids per vertex (`fc`), may be empty
};
struct PolyFace {
    PolyFaceLoop outer;
    std::vector<PolyFaceLoop> holes;
};
struct PolyFaces { std::vector<PolyFace> faces; };

// `-type "nurbsCurve"`: degree spans form rational dimension / knots / CVs.
struct NurbsCurveData {
    int degree = 3;
    int spans = 0;
    int form = 0;  // 0 open, 1 closed, 2 periodic
    bool rational = false;
    int dimension = 3;          // 2 or 3
    std::vector<double> knots;  // Maya's knot vector (two fewer than the textbook one)
    std::vector<double> cvs;    // dimension (+1 weight if rational) numbers per CV
};

// `-type "nurbsSurface"`: CVs U-major (V varies fastest), see reference/ma-format.md.
struct NurbsSurfaceData {
    int degreeU = 3, degreeV = 3;
    int formU = 0, formV = 0;  // 0 open, 1 closed, 2 periodic
    bool rational = false;
    bool trimmed = false;  // TRIM token present
    std::vector<double> knotsU, knotsV;
    int cvCountU = 0, cvCountV = 0;  // derived: knots + 1 − degree
    std::vector<double> cvs;         // 3 (or 4 when rational) numbers per CV
};

// Any `-type` the reader keeps as tokens without interpreting them (dataPolyComponent, mesh, …).
struct RawData {
    std::string type;
    std::vector<std::string> tokens;
};

using Value = std::variant<std::monostate, Numbers, StringValue, StringArray, ComponentList,
                           std::shared_ptr<const PolyFaces>, std::shared_ptr<const NurbsCurveData>,
                           std::shared_ptr<const NurbsSurfaceData>, RawData>;

}  // namespace pushpin::scene
