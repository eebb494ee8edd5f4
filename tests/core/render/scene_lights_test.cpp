// A frame's lights and light linking (core/render/scene_lights.h) called directly: the lights read
// with their paths and numbers at the door, and the lit lights of each material slot worked out
// again from those paths.
#include "core/render/scene_lights.h"

#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "tests/support/ma_preamble.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

struct Loaded {
    scene::Graph graph;
    scene::Evaluator ev;
    scene::RenderSetup setup;
    explicit Loaded(const std::string& text)
        : graph(scene::MaReader::readString(text, "lights.ma")), ev(graph, 1.0), setup(scene::extractRenderSetup(graph)) {}
};

bool hasNote(const std::vector<std::string>& notes, const std::string& part) {
    return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

TEST(SceneLights, LightsComeWithTheirPathsAndNumbersAtTheDoor) {
    const std::string text = test::maPreamble(10) + R"(createNode transform -n "key";
	setAttr ".t" -type "double3" 1 2 3;
createNode pointLight -n "keyShape" -p "key";
	setAttr ".in" 2;
createNode transform -n "odd";
createNode spotLight -n "oddShape" -p "odd";
	setAttr ".dro" 1e40;
	setAttr ".de" 9;
createNode transform -n "blinding";
createNode directionalLight -n "blindingShape" -p "blinding";
	setAttr ".cl" -type "float3" 1e20 1 1;
	setAttr ".in" 1e20;
createNode transform -n "hidden";
	setAttr ".v" no;
createNode spotLight -n "hiddenShape" -p "hidden";
)";
    Loaded s(text);
    std::vector<std::string> notes;
    const SceneLights lights = readSceneLights(s.ev, s.setup, notes);
    ASSERT_EQ(lights.lights.size(), 2u);
    ASSERT_EQ(lights.paths.size(), 2u);
    EXPECT_EQ(lights.lights[0].name, "|key|keyShape");
    EXPECT_EQ(lights.paths[0].back(), s.graph.find("keyShape"));
    EXPECT_EQ(lights.paths[0].front(), s.graph.find("key"));
    EXPECT_DOUBLE_EQ(lights.lights[0].position.x, 1.0);
    EXPECT_DOUBLE_EQ(lights.lights[0].position.z, 3.0);
    EXPECT_FLOAT_EQ(lights.lights[0].color.x, 2.0f);
    // Beyond 1e30: the default, with a note; a decay rate out of range: none.
    EXPECT_EQ(lights.lights[1].name, "|odd|oddShape");
    EXPECT_EQ(lights.lights[1].dropoff, 0.0f);
    EXPECT_EQ(lights.lights[1].decayRate, 0);
    EXPECT_TRUE(hasNote(notes, "|odd|oddShape: dropoff"));
    EXPECT_TRUE(hasNote(notes, "|odd|oddShape: decayRate 9 out of range"));
    // Emitted colour past float's range: not rendered. A hidden light: not rendered.
    EXPECT_TRUE(hasNote(notes, "|blinding|blindingShape: color × intensity is beyond 1e30; light not rendered"));
    EXPECT_TRUE(hasNote(notes, "|hidden|hiddenShape: light"));
}

TEST(SceneLights, LinkingIsWorkedOutFromThePaths) {
    // Two cubes in two shading groups; "rim" links to bSG only, "key" lights everything through
    // the default light set, and pCube2 ignores key.
    std::string text = test::maPreamble(10);
    for (const char* name : {"pCube1", "pCube2"})
        text += std::string("createNode transform -n \"") + name + "\";\ncreateNode mesh -n \"" + name + "Shape\" -p \"" +
                name + "\";\ncreateNode polyCube -n \"" + name + "Creator\";\nconnectAttr \"" + name +
                "Creator.out\" \"" + name + "Shape.i\";\n";
    for (const char* m : {"a", "b"})
        text += std::string("createNode lambert -n \"") + m + "\";\ncreateNode shadingEngine -n \"" + m +
                "SG\";\nconnectAttr \"" + m + ".oc\" \"" + m + "SG.ss\";\nconnectAttr \"" + m +
                "SG.pa\" \":renderPartition.st\" -na;\n";
    text += R"(connectAttr "pCube1Shape.iog" "aSG.dsm" -na;
connectAttr "pCube2Shape.iog" "bSG.dsm" -na;
createNode transform -n "key";
createNode pointLight -n "keyShape" -p "key";
createNode transform -n "rim";
createNode pointLight -n "rimShape" -p "rim";
connectAttr "key.iog" ":defaultLightSet.dsm" -na;
relationship "link" ":lightLinker1" "aSG.message" ":defaultLightSet.message";
relationship "link" ":lightLinker1" "bSG.message" ":defaultLightSet.message";
relationship "link" ":lightLinker1" "bSG.message" "rim.message";
relationship "ignore" ":lightLinker1" "pCube2.message" "key.message";
)";
    Loaded s(text);
    FrameScene frame = buildFrameScene(s.ev, s.setup, RenderSettings{});
    ASSERT_EQ(frame.objects.size(), 2u);
    ASSERT_EQ(frame.lights.size(), 2u);
    std::vector<std::string> notes;
    const SceneLights lights = readSceneLights(s.ev, s.setup, notes);
    std::vector<std::vector<scene::NodeId>> objectPaths;
    for (RenderObject& o : frame.objects) {
        objectPaths.push_back(s.graph.dagPaths(o.shape).at(size_t(o.instance)));
        for (MaterialSlot& slot : o.materials) slot.lights.clear();
    }
    linkLights(s.graph, s.setup, lights.paths, objectPaths, frame);
    auto lit = [&](size_t object) {
        std::vector<std::string> names;
        for (uint32_t l : frame.objects[object].materials.at(0).lights) names.push_back(frame.lights[l].name);
        std::sort(names.begin(), names.end());
        return names;
    };
    const size_t cube1 = frame.objects[0].name == "|pCube1|pCube1Shape" ? 0 : 1;
    EXPECT_EQ(lit(cube1), std::vector<std::string>{"|key|keyShape"});
    EXPECT_EQ(lit(1 - cube1), std::vector<std::string>{"|rim|rimShape"});
}

}  // namespace
}  // namespace pushpin::render
