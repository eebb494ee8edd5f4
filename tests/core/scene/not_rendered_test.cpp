// notRenderedFeatures: what a scene turns on that pushpin does not render, with its nodes.
#include "core/scene/not_rendered.h"

#include "core/scene/ma_reader.h"

#include <gtest/gtest.h>

#include <string>

namespace pushpin::scene {
namespace {

std::vector<NotRendered> featuresOf(const std::string& text) {
    const Graph g = MaReader::readString(text, "features.ma");
    const RenderSetup setup = extractRenderSetup(g);
    Evaluator ev(g, 1.0);
    return notRenderedFeatures(ev, setup);
}

const NotRendered* find(const std::vector<NotRendered>& all, std::string_view feature) {
    for (const NotRendered& n : all)
        if (n.feature == feature) return &n;
    return nullptr;
}

const char* kLitBall = R"(createNode transform -n "ball";
createNode mesh -n "ballShape" -p "ball";
createNode polySphere -n "polySphere1";
connectAttr "polySphere1.out" "ballShape.i";
createNode blinn -n "shiny";
	setAttr ".gi" 0.3;
	setAttr ".rfc" yes;
createNode shadingEngine -n "shinySG";
connectAttr "shiny.oc" "shinySG.ss";
connectAttr "ballShape.iog" "shinySG.dsm" -na;
createNode transform -n "key";
createNode spotLight -n "keyShape" -p "key";
	setAttr ".urs" yes;
createNode transform -n "fill";
createNode pointLight -n "fillShape" -p "fill";
	setAttr ".urs" no;
	setAttr ".dms" yes;
)";

// Ray tracing, motion blur and glow turned on: each is listed with the nodes that ask for it.
TEST(NotRendered, RayTracingMotionBlurAndGlowAreListed) {
    const std::string text = std::string(kLitBall) +
                             "select -ne :defaultRenderQuality;\n\tsetAttr \".ert\" yes;\n"
                             "select -ne :defaultRenderGlobals;\n\tsetAttr \".mb\" yes;\n";
    const std::vector<NotRendered> all = featuresOf(text);
    for (const char* feature : {"ray tracing", "motion blur", "glow and optical effects", "ray-traced shadows",
                                "ray-traced reflections", "ray-traced refractions", "depth-map shadows"})
        EXPECT_NE(find(all, feature), nullptr) << feature;
    EXPECT_EQ(find(all, "ray-traced shadows")->nodes, (std::vector<std::string>{"keyShape"}));
    EXPECT_EQ(find(all, "depth-map shadows")->nodes, (std::vector<std::string>{"fillShape"}));
    EXPECT_EQ(find(all, "glow and optical effects")->nodes, (std::vector<std::string>{"shiny"}));
    EXPECT_EQ(find(all, "motion blur")->nodes, (std::vector<std::string>{"defaultRenderGlobals"}));
    EXPECT_EQ(describeNotRendered(*find(all, "glow and optical effects")), "glow and optical effects (shiny)");
}

// Without ray tracing, ray-traced shadows, reflections and refractions are not asked for: Maya
// Software traces nothing then. The depth map and the glow still are.
TEST(NotRendered, RayTracedEffectsNeedRayTracingOn) {
    const std::vector<NotRendered> all = featuresOf(kLitBall);
    EXPECT_EQ(find(all, "ray tracing"), nullptr);
    EXPECT_EQ(find(all, "ray-traced shadows"), nullptr);
    EXPECT_EQ(find(all, "ray-traced reflections"), nullptr);
    EXPECT_EQ(find(all, "motion blur"), nullptr);
    EXPECT_NE(find(all, "depth-map shadows"), nullptr);
    EXPECT_NE(find(all, "glow and optical effects"), nullptr);
}

// A plain scene asks for nothing pushpin leaves out.
TEST(NotRendered, PlainSceneListsNothing) {
    EXPECT_TRUE(featuresOf("createNode transform -n \"ball\";\ncreateNode mesh -n \"ballShape\" -p \"ball\";\n").empty());
}

// Types that stand for a feature, plug-in shading, and the node list's bound.
TEST(NotRendered, FeatureNodesPlugInsAndBound) {
    std::string text = "createNode imagePlane -n \"ip1\";\ncreateNode envFog -n \"fog1\";\ncreateNode renderLayer -n \"layer1\";\n"
                       "createNode transform -n \"sky\";\ncreateNode aiSkyDomeLight -n \"skyShape\" -p \"sky\";\n"
                       "createNode transform -n \"cloth\";\ncreateNode nCloth -n \"clothShape\" -p \"cloth\";\n";
    for (int i = 0; i < 60; ++i) text += "createNode particle -n \"p" + std::to_string(i) + "\";\n";
    const std::vector<NotRendered> all = featuresOf(text);
    EXPECT_NE(find(all, "image planes"), nullptr);
    EXPECT_NE(find(all, "fog and volume shaders"), nullptr);
    ASSERT_NE(find(all, "render layers other than the default"), nullptr);
    EXPECT_EQ(find(all, "render layers other than the default")->nodes, (std::vector<std::string>{"layer1"}));
    EXPECT_NE(find(all, "plug-in lights"), nullptr);
    ASSERT_NE(find(all, "cloth simulation (the cloth's input mesh is rendered)"), nullptr);
    EXPECT_EQ(find(all, "cloth simulation (the cloth's input mesh is rendered)")->nodes,
              (std::vector<std::string>{"clothShape"}));
    const NotRendered* particles = find(all, "particles and strokes");
    ASSERT_NE(particles, nullptr);
    EXPECT_EQ(particles->count, 60u);
    EXPECT_EQ(particles->nodes.size(), kMaxNotRenderedNodes);
    EXPECT_EQ(describeNotRendered(*particles), "particles and strokes (p0, p1, p2, p3, p4, and 55 more)");
}

}  // namespace
}  // namespace pushpin::scene
