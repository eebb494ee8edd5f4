// The shading node type table and the port builders (core/shade/node_library.h).
#include "core/shade/node_library.h"

#include "cache/error.h"

#include <cctype>

namespace pushpin::shade {

int NodeType::inputChannels() const {
    int n = 0;
    for (const PortSpec& p : inputs)
        if (!p.multi) n += p.width;
    return n;
}

int NodeType::outputChannels() const {
    int n = 0;
    for (const PortSpec& p : outputs) n += p.width;
    return n;
}

int NodeType::findInput(std::string_view longName) const {
    for (size_t i = 0; i < inputs.size(); ++i)
        if (inputs[i].longName == longName) return int(i);
    return -1;
}

int NodeType::findOutput(std::string_view longName) const {
    for (size_t i = 0; i < outputs.size(); ++i)
        if (outputs[i].longName == longName) return int(i);
    return -1;
}

PortSpec scalarPort(const char* longName, const char* shortName, float value) {
    PortSpec p;
    p.longName = longName;
    p.shortName = shortName;
    p.width = 1;
    p.defaults = {value, value, value};
    return p;
}

namespace {

PortSpec compoundPort(const char* longName, const char* shortName, const char* suffixes, int width,
                      std::array<float, 3> defaults) {
    PortSpec p;
    p.longName = longName;
    p.shortName = shortName;
    p.width = width;
    p.defaults = defaults;
    for (int k = 0; k < width; ++k) {
        const char s = suffixes[k];
        p.childLong[size_t(k)] = std::string(longName) + s;
        p.childShort[size_t(k)] = std::string(shortName) + char(std::tolower(static_cast<unsigned char>(s)));
    }
    return p;
}

}  // namespace

PortSpec colorPort(const char* longName, const char* shortName, float r, float g, float b) {
    return compoundPort(longName, shortName, "RGB", 3, {r, g, b});
}

PortSpec vectorPort(const char* longName, const char* shortName, const char* suffixes, float x, float y, float z) {
    return compoundPort(longName, shortName, suffixes, 3, {x, y, z});
}

PortSpec vector2Port(const char* longName, const char* shortName, const char* suffixes, float x, float y) {
    return compoundPort(longName, shortName, suffixes, 2, {x, y, 0.0f});
}

PortSpec rendererPort(const char* longName, const char* shortName) {
    const std::string_view name(longName);
    auto xyz = [&](Field first) {
        PortSpec p = vectorPort(longName, shortName, "XYZ", 0, 0, 0);
        for (int k = 0; k < 3; ++k) p.fields[size_t(k)] = Field(int(first) + k);
        return p;
    };
    if (name == "pointCamera") return xyz(Field::PointCameraX);
    if (name == "normalCamera") return xyz(Field::NormalCameraX);
    if (name == "rayDirection") return xyz(Field::RayDirectionX);
    if (name == "pointWorld") return xyz(Field::PointWorldX);
    if (name == "pointObj") return xyz(Field::PointObjX);
    if (name == "tangentUCamera") return xyz(Field::TangentUX);
    if (name == "tangentVCamera") return xyz(Field::TangentVX);
    if (name == "uvCoord") {
        PortSpec p = vector2Port(longName, shortName, "UV", 0, 0);
        p.childLong = {"uCoord", "vCoord", ""};
        p.childShort = {"u", "v", ""};
        p.fields = {Field::UCoord, Field::VCoord, Field::None};
        return p;
    }
    if (name == "pixelCenter") {
        PortSpec p = vector2Port(longName, shortName, "XY", 0, 0);
        p.fields = {Field::PixelCenterX, Field::PixelCenterY, Field::None};
        return p;
    }
    if (name == "facingRatio" || name == "flippedNormal") {
        PortSpec p = scalarPort(longName, shortName, 0.0f);
        p.fields[0] = name == "facingRatio" ? Field::FacingRatio : Field::FlippedNormal;
        return p;
    }
    throw Error("rendererPort: '" + std::string(name) + "' is not a renderer attribute");
}

const NodeType* findNodeType(std::string_view type) {
    // Built once and never changed afterwards, so the pointers handed out stay valid.
    static const std::vector<NodeType> table = [] {
        std::vector<NodeType> t;
        detail::addMaterialTypes(t);
        detail::addUtilityTypes(t);
        return t;
    }();
    for (const NodeType& n : table)
        if (n.name == type) return &n;
    return nullptr;
}

}  // namespace pushpin::shade
