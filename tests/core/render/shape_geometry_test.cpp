// A shape's geometry as the frame scene gets it (core/render/shape_geometry.h) called directly:
// per-span divisions with their defaults and cap, meshes and surfaces evaluated once, and shapes
// that cannot render failed with their reason.
#include "core/render/shape_geometry.h"

#include "core/scene/ma_reader.h"
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
    explicit Loaded(const std::string& text) : graph(scene::MaReader::readString(text, "shapes.ma")), ev(graph, 1.0) {}
};

bool hasNote(const std::vector<std::string>& notes, const std::string& part) {
    return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

TEST(ShapeGeometry, SpanDivisionsRoundUpFallBackAndCap) {
    Loaded s(test::maPreamble(10) + R"(createNode transform -n "p";
createNode nurbsSurface -n "a" -p "p";
	setAttr ".nu" 2;
	setAttr ".nufa" 1.5;
	setAttr ".nv" 1000;
	setAttr ".nvfa" 10;
createNode nurbsSurface -n "b" -p "p";
	setAttr ".nu" 2;
	setAttr ".nufa" 0.1;
)");
    std::vector<std::string> notes;
    const scene::NodeId a = s.graph.find("a"), b = s.graph.find("b");
    EXPECT_EQ(spanDivisions(s.ev, a, "numberU", "uDivisionsFactor", "a", notes), 3);
    EXPECT_TRUE(notes.empty());
    EXPECT_EQ(spanDivisions(s.ev, a, "numberV", "vDivisionsFactor", "a", notes), 256);
    EXPECT_TRUE(hasNote(notes, "a: numberV × vDivisionsFactor capped at 256 divisions per span"));
    EXPECT_EQ(spanDivisions(s.ev, b, "numberU", "uDivisionsFactor", "b", notes), 1);  // ceil(0.2), at least 1
    // Unset: Maya's defaults, 3 × 1.5.
    EXPECT_EQ(spanDivisions(s.ev, b, "numberV", "vDivisionsFactor", "b", notes), 5);
}

TEST(ShapeGeometry, MeshesAndSurfacesAreEvaluatedOnce) {
    Loaded s(test::maPreamble(10) + R"(createNode transform -n "box";
createNode mesh -n "boxShape" -p "box";
createNode polyCube -n "boxCreator";
connectAttr "boxCreator.out" "boxShape.i";
createNode transform -n "plane";
createNode nurbsSurface -n "planeShape" -p "plane";
	setAttr ".nu" 2;
	setAttr ".nufa" 1;
createNode makeNurbPlane -n "makeNurbPlane1";
	setAttr ".u" 2;
	setAttr ".v" 3;
connectAttr "makeNurbPlane1.os" "planeShape.cr";
)");
    std::vector<std::string> notes;
    ShapeGeometry box;
    evaluateShape(s.ev, s.graph.find("boxShape"), "box", box, notes);
    ASSERT_FALSE(box.failed) << box.skipReason;
    ASSERT_TRUE(box.mesh);
    EXPECT_EQ(box.mesh->faceCount(), 6u);
    EXPECT_FALSE(box.degenerate);
    EXPECT_FALSE(box.surface);
    ShapeGeometry plane;
    evaluateShape(s.ev, s.graph.find("planeShape"), "plane", plane, notes);
    ASSERT_FALSE(plane.failed) << plane.skipReason;
    ASSERT_TRUE(plane.surface);
    EXPECT_FALSE(plane.mesh);
    EXPECT_EQ(plane.divU, 2);
    EXPECT_EQ(plane.divV, 5);
}

TEST(ShapeGeometry, ShapesThatCannotRenderFailWithTheirReason) {
    Loaded s(test::maPreamble(10) + R"(createNode transform -n "empty";
createNode mesh -n "emptyShape" -p "empty";
createNode transform -n "flat";
createNode mesh -n "flatShape" -p "flat";
	setAttr -s 4 ".vt[0:3]" 0 0 0 1 0 0 1 1 0 2 0 0;
	setAttr -s 5 ".ed[0:4]" 0 1 0 1 2 0 2 0 0 1 3 0 3 0 0;
	setAttr -s 2 ".fc[0:1]" -type "polyFaces" f 3 0 1 2 f 2 3 4;
)");
    std::vector<std::string> notes;
    ShapeGeometry empty;
    evaluateShape(s.ev, s.graph.find("emptyShape"), "empty", empty, notes);
    EXPECT_TRUE(empty.failed);
    EXPECT_FALSE(empty.skipReason.empty());
    EXPECT_FALSE(empty.mesh);
    // A face whose loop has two edges is degenerate: marked and noted, the other face kept.
    ShapeGeometry flat;
    evaluateShape(s.ev, s.graph.find("flatShape"), "flat", flat, notes);
    ASSERT_FALSE(flat.failed) << flat.skipReason;
    ASSERT_TRUE(flat.degenerate);
    ASSERT_EQ(flat.degenerate->size(), 2u);
    EXPECT_FALSE((*flat.degenerate)[0]);
    EXPECT_TRUE((*flat.degenerate)[1]);
    EXPECT_TRUE(hasNote(notes, "flat: 1 degenerate face(s) not rendered"));
}

}  // namespace
}  // namespace pushpin::render
