// Tests for core/shade/node_library.h: the port builders and the consistency every registered
// node type must keep for the compiler (shading_network.cpp) to bind it.
#include "core/shade/node_library.h"

#include "cache/error.h"

#include <gtest/gtest.h>

namespace pushpin::shade {
namespace {

const char* kTypes[] = {"lambert", "blinn", "phong", "phongE", "surfaceShader", "samplerInfo", "reverse",
                        "multiplyDivide", "blendColors", "clamp", "condition", "plusMinusAverage", "setRange",
                        "luminance", "gammaCorrect"};

TEST(NodeLibrary, FindsEveryEvaluatedTypeAndNothingElse) {
    for (const char* name : kTypes) {
        const NodeType* t = findNodeType(name);
        ASSERT_NE(t, nullptr) << name;
        EXPECT_EQ(t->name, name);
    }
    EXPECT_EQ(findNodeType("file"), nullptr);
    EXPECT_EQ(findNodeType(""), nullptr);
    EXPECT_EQ(findNodeType("Lambert"), nullptr);
}

TEST(NodeLibrary, EveryTypeIsBindable) {
    for (const char* name : kTypes) {
        const NodeType& t = *findNodeType(name);
        EXPECT_LE(t.params.size(), 4u) << name;
        EXPECT_FALSE(t.outputs.empty()) << name;
        bool seenMulti = false;
        int multiPorts = 0;
        for (const PortSpec& p : t.inputs) {
            EXPECT_GE(p.width, 1) << name << "." << p.longName;
            EXPECT_LE(p.width, 3) << name << "." << p.longName;
            if (p.multi) seenMulti = true, ++multiPorts;
            else EXPECT_FALSE(seenMulti) << name << ": fixed port " << p.longName << " after a multi port";
            for (int k = 0; k < p.width && p.width > 1; ++k) {
                EXPECT_FALSE(p.childLong[size_t(k)].empty()) << name << "." << p.longName;
                EXPECT_FALSE(p.childShort[size_t(k)].empty()) << name << "." << p.longName;
            }
        }
        EXPECT_LE(multiPorts, 3) << name;
        if (!t.kernel) {
            // Without a kernel every output must pass an input through or be a renderer value.
            for (const PortSpec& p : t.outputs) {
                const bool alias = p.aliasOf >= 0 && p.aliasOf < int(t.inputs.size()) &&
                                   t.inputs[size_t(p.aliasOf)].width == p.width;
                EXPECT_TRUE(alias || p.implicit()) << name << "." << p.longName;
            }
        }
        if (t.transparencyInput >= 0) {
            ASSERT_LT(t.transparencyInput, int(t.inputs.size())) << name;
            EXPECT_EQ(t.inputs[size_t(t.transparencyInput)].width, 3) << name;
        }
    }
}

TEST(NodeLibrary, PortBuildersNameChildrenTheMayaWay) {
    const PortSpec c = colorPort("specularColor", "sc", 0.5f, 0.25f, 1.0f);
    EXPECT_EQ(c.childLong[0], "specularColorR");
    EXPECT_EQ(c.childLong[2], "specularColorB");
    EXPECT_EQ(c.childShort[1], "scg");
    EXPECT_EQ(c.defaults[1], 0.25f);
    const PortSpec v = vectorPort("input3D", "i3", "xyz", 0, 0, 0);
    EXPECT_EQ(v.childLong[0], "input3Dx");
    EXPECT_EQ(v.childShort[2], "i3z");
    const PortSpec uv = rendererPort("uvCoord", "uv");
    EXPECT_EQ(uv.width, 2);
    EXPECT_EQ(uv.childLong[0], "uCoord");
    EXPECT_EQ(uv.fields[1], Field::VCoord);
    EXPECT_TRUE(rendererPort("facingRatio", "fr").implicit());
    EXPECT_FALSE(scalarPort("diffuse", "dc", 0.8f).implicit());
    EXPECT_THROW(rendererPort("color", "c"), Error);
}

TEST(NodeLibrary, LambertFamilySharesTheInputLayout) {
    // materials.cpp indexes channels by a layout common to lambert and the reflect types.
    const NodeType& lambert = *findNodeType("lambert");
    for (const char* name : {"blinn", "phong", "phongE"}) {
        const NodeType& t = *findNodeType(name);
        ASSERT_GT(t.inputs.size(), lambert.inputs.size()) << name;
        for (size_t i = 0; i < lambert.inputs.size(); ++i) EXPECT_EQ(t.inputs[i].longName, lambert.inputs[i].longName);
        EXPECT_EQ(t.inputs[lambert.inputs.size()].longName, "specularColor") << name;
        EXPECT_EQ(t.inputChannels(), lambert.inputChannels() + 3 + (std::string(name) == "phongE" ? 5 : name[0] == 'b' ? 2 : 1));
    }
    EXPECT_EQ(lambert.findInput("normalCamera"), 5);
    EXPECT_EQ(lambert.findOutput("outTransparency"), 1);
    EXPECT_EQ(lambert.findInput("nothing"), -1);
}

}  // namespace
}  // namespace pushpin::shade
