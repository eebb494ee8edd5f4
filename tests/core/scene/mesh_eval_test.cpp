// Tests for core/scene/mesh_eval.h: stored mesh data, construction history and skips.
#include "core/scene/mesh_eval.h"

#include "core/geom/mesh_pieces.h"
#include "core/geom/poly_primitives.h"
#include "core/scene/components.h"
#include "core/scene/ma_reader.h"

#include "tests/support/ma_corpus.h"
#include "tests/support/stored_grid.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>

namespace pushpin::scene {
namespace {

// ------------------------------------------------------------------ graph-building helpers
void set(Graph& g, NodeId n, std::string_view attr, std::vector<double> values,
         Numbers::Kind kind = Numbers::Kind::Plain) {
    Numbers nums;
    nums.kind = kind;
    nums.tupleSize = kind == Numbers::Kind::Tuple ? int(values.size()) : 1;
    nums.values = std::move(values);
    g.setValue(n, *parsePlugPath(attr), nums);
}

void connect(Graph& g, NodeId src, std::string_view srcAttr, NodeId dst, std::string_view dstAttr) {
    g.connect(Plug{src, std::string(srcAttr)}, Plug{dst, std::string(dstAttr)});
}

struct ShapeUnderTransform {
    NodeId transform;
    NodeId shape;
};
ShapeUnderTransform addMesh(Graph& g, const std::string& name) {
    const NodeId t = g.createNode("transform", name);
    return {t, g.createNode("mesh", name + "Shape", t)};
}

// A unit polyCube feeding pCubeShape1 (under pCube1) through the history nodes `chain`, in
// order, each taking the one before on inputPolymesh. `nodes` makes them (createNode and setAttr
// lines); `cubeLines` follows the polyCube's createNode.
std::string cubeThrough(std::string_view nodes, std::initializer_list<std::string_view> chain,
                        std::string_view cubeLines = {}) {
    std::string text = "createNode transform -n \"pCube1\";\ncreateNode mesh -n \"pCubeShape1\" -p \"pCube1\";\n"
                       "createNode polyCube -n \"polyCube1\";\n";
    text += cubeLines;
    text += nodes;
    std::string from = "polyCube1";
    for (std::string_view node : chain) {
        text += "connectAttr \"" + from + ".out\" \"" + std::string(node) + ".ip\";\n";
        from = node;
    }
    return text + "connectAttr \"" + from + ".out\" \"pCubeShape1.i\";\n";
}

MeshEvaluation evaluate(const Graph& g, NodeId shape, double frame = 1.0) {
    Evaluator ev(g, frame);
    return evaluateMeshShape(ev, shape);
}

// The polyFaces worked example of reference/ma-format.md.
const char* kWorkedCube = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr -k off ".v";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr -s 14 ".uvst[0].uvsp[0:13]" -type "float2" 0.375 0 0.625 0 0.375 0.25
		 0.625 0.25 0.375 0.5 0.625 0.5 0.375 0.75 0.625 0.75 0.375 1 0.625 1
		 0.875 0 0.875 0.25 0.125 0 0.125 0.25;
	setAttr ".cuvs" -type "string" "map1";
	setAttr -s 8 ".vt[0:7]"  -0.5 -0.5 0.5 0.5 -0.5 0.5 -0.5 0.5 0.5 0.5 0.5 0.5
		 -0.5 0.5 -0.5 0.5 0.5 -0.5 -0.5 -0.5 -0.5 0.5 -0.5 -0.5;
	setAttr -s 12 ".ed[0:11]"  0 1 0 2 3 0 4 5 0 6 7 0 0 2 0 1 3 0
		 2 4 0 3 5 0 4 6 0 5 7 0 6 0 0 7 1 0;
	setAttr -s 6 -ch 24 ".fc[0:5]" -type "polyFaces"
		f 4 0 5 -2 -5      mu 0 4 0 1 3 2
		f 4 1 7 -3 -7      mu 0 4 2 3 5 4
		f 4 2 9 -4 -9      mu 0 4 4 5 7 6
		f 4 3 11 -1 -11    mu 0 4 6 7 9 8
		f 4 -12 -10 -8 -6  mu 0 4 1 10 11 3
		f 4 10 4 6 8       mu 0 4 12 0 2 13;
)";

TEST(MeshEval, DecodesThePolyFacesWorkedExample) {
    const Graph g = MaReader::readString(kWorkedCube, "worked.ma");
    const NodeId shape = g.find("pCubeShape1");
    ASSERT_NE(shape, kNoNode);
    EXPECT_TRUE(hasStoredMesh(g, shape));
    const MeshEvaluation e = evaluate(g, shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& m = *e.mesh;
    ASSERT_EQ(m.faceCount(), 6u);
    EXPECT_EQ(m.faceVertices,
              (std::vector<uint32_t>{0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4}));
    const glm::dvec3 normals[] = {{0, 0, 1}, {0, 1, 0}, {0, 0, -1}, {0, -1, 0}, {1, 0, 0}, {-1, 0, 0}};
    for (size_t f = 0; f < 6; ++f)
        EXPECT_NEAR(glm::length(m.faceNormal(f) - normals[f]), 0.0, 1e-9) << "face " << f;
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-9);
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].name, "map1");
    EXPECT_EQ(m.uvSets[0].uvs.size(), 14u);
    EXPECT_EQ(m.uvSets[0].faceVertexUvs,
              (std::vector<int32_t>{0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 9, 8, 1, 10, 11, 3, 12, 0, 2, 13}));
    ASSERT_EQ(m.edges.size(), 12u);
    for (const geom::MeshEdge& edge : m.edges) EXPECT_FALSE(edge.smooth);
    EXPECT_TRUE(e.history.empty());
    EXPECT_TRUE(e.notes.empty()) << e.notes.front();

    // The generator reproduces the same cube.
    const std::optional<geom::Mesh> generated = geom::makePolyCube({});
    ASSERT_TRUE(generated);
    EXPECT_EQ(generated->points, m.points);
    EXPECT_EQ(generated->faceVertices, m.faceVertices);
    EXPECT_EQ(generated->uvSets[0].faceVertexUvs, m.uvSets[0].faceVertexUvs);
}

TEST(MeshEval, DecodesHolesAndSoftEdges) {
    // A 2×2 square with a 1×1 square hole; the hole walks its edges backwards.
    const char* text = R"(createNode transform -n "frame";
createNode mesh -n "frameShape" -p "frame";
	setAttr -s 8 ".vt[0:7]" -1 0 1  1 0 1  1 0 -1  -1 0 -1
		-0.5 0 0.5  0.5 0 0.5  0.5 0 -0.5  -0.5 0 -0.5;
	setAttr -s 8 ".ed[0:7]" 0 1 1  1 2 1  2 3 1  3 0 0  4 5 1  5 6 1  6 7 1  7 4 1;
	setAttr ".fc[0]" -type "polyFaces" f 4 0 1 2 3 h 4 -8 -7 -6 -5;
)";
    const Graph g = MaReader::readString(text);
    const MeshEvaluation e = evaluate(g, g.find("frameShape"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& m = *e.mesh;
    EXPECT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(m.holeCount(0), 1u);
    EXPECT_EQ(std::vector<uint32_t>(m.loop(1).begin(), m.loop(1).end()), (std::vector<uint32_t>{4, 7, 6, 5}));
    EXPECT_NEAR(glm::length(m.faceAreaVector(0)), 3.0, 1e-6);
    EXPECT_GT(m.faceNormal(0).y, 0.99);
    EXPECT_TRUE(m.edges[0].smooth);
    EXPECT_FALSE(m.edges[3].smooth);
    EXPECT_TRUE(m.uvSets.empty());
}

// Faces from several runs, one index left without a record; a hole whose uv records come after
// it, with the outer loop's (`mf`) after those of the hole (`mh`); colours on the outer loop.
TEST(MeshEval, StoredFacesFromRunsWithHoleUvsAfterTheHole) {
    const char* text = R"(createNode transform -n "frame";
createNode mesh -n "frameShape" -p "frame";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr -s 12 ".uvst[0].uvsp[0:11]" -type "float2" 0 0 1 0 1 1 0 1  0.25 0.25 0.75 0.25 0.75 0.75 0.25 0.75
		0.3 0.3 0.7 0.3 0.7 0.7 0.3 0.7;
	setAttr ".clst[0].clsn" -type "string" "colorSet1";
	setAttr -s 4 ".clst[0].clsp[0:3]" 1 0 0 1  0 1 0 1  0 0 1 1  1 1 1 1;
	setAttr -s 8 ".vt[0:7]" -1 0 1  1 0 1  1 0 -1  -1 0 -1
		-0.5 0 0.5  0.5 0 0.5  0.5 0 -0.5  -0.5 0 -0.5;
	setAttr -s 8 ".ed[0:7]" 0 1 1  1 2 1  2 3 1  3 0 0  4 5 1  5 6 1  6 7 1  7 4 1;
	setAttr ".fc[0]" -type "polyFaces" f 4 0 1 2 3 fc 4 0 1 2 3 h 4 -8 -7 -6 -5 mh 4 7 6 5 4 mf 4 0 1 2 3;
	setAttr ".fc[1]" -type "polyFaces" f 4 4 5 6 7 mu 0 4 8 9 10 11;
	setAttr ".fc[3]" -type "polyFaces" f 4 4 5 6 7;
)";
    const Graph g = MaReader::readString(text);
    const MeshEvaluation e = evaluate(g, g.find("frameShape"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& m = *e.mesh;
    ASSERT_EQ(m.faceCount(), 3u);
    EXPECT_EQ(m.holeCount(0), 1u);
    EXPECT_EQ(m.faceVertices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 7, 6, 5, 4, 5, 6, 7, 4, 5, 6, 7}));
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].faceVertexUvs,
              (std::vector<int32_t>{0, 1, 2, 3, 7, 6, 5, 4, 8, 9, 10, 11, -1, -1, -1, -1}));
    ASSERT_EQ(m.colorSets.size(), 1u);
    EXPECT_EQ(m.colorSets[0].faceVertexColors,
              (std::vector<int32_t>{0, 1, 2, 3, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1}));
    ASSERT_EQ(e.notes.size(), 1u);
    EXPECT_NE(e.notes[0].find("1 face indices have no polyFaces record"), std::string::npos) << e.notes[0];
}

TEST(MeshEval, StoredTweaksNormalsAndUvSets) {
    // cgkit's objects.ma layout: .pt tweaks added to .vt; plus .n with "not set" entries.
    const char* text = R"(createNode transform -n "mesh";
createNode mesh -n "meshShape" -p "mesh";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr ".uvst[1].uvsn" -type "string" "extra";
	setAttr -s 3 ".uvst[1].uvsp[0:2]" -type "float2" 0 0 1 0 0 1;
	setAttr ".cuvs" -type "string" "extra";
	setAttr ".pt[0]" -type "float3" 0.25 0 -0.25 ;
	setAttr ".pt[9]" -type "float3" 1 1 1 ;
	setAttr -s 3 ".vt[0:2]" 0 0 0  1 0 0  0 1 0;
	setAttr -s 3 ".ed[0:2]" 0 1 0  1 2 0  2 0 0;
	setAttr -s 3 ".n[0:2]" -type "float3" 1e+20 1e+20 1e+20  0 0 2  1e+20 1e+20 1e+20;
	setAttr ".fc[0]" -type "polyFaces" f 3 0 1 2 mu 1 3 0 1 2;
)";
    const Graph g = MaReader::readString(text);
    const MeshEvaluation e = evaluate(g, g.find("meshShape"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& m = *e.mesh;
    EXPECT_EQ(m.points[0], glm::vec3(0.25f, 0.0f, -0.25f));
    EXPECT_EQ(m.points[1], glm::vec3(1.0f, 0.0f, 0.0f));
    ASSERT_EQ(m.normals.size(), 3u);
    EXPECT_EQ(m.normals[0], glm::vec3(0.0f));
    EXPECT_EQ(m.normals[1], glm::vec3(0, 0, 1));
    ASSERT_EQ(m.uvSets.size(), 2u);
    EXPECT_EQ(m.currentUvSet, 1);
    EXPECT_TRUE(m.uvSets[0].faceVertexUvs.empty());  // map1 maps no face
    EXPECT_EQ(m.uvSets[1].faceVertexUvs, (std::vector<int32_t>{0, 1, 2}));
    // The tweak of point 9 (there are 3) is reported, not applied.
    ASSERT_EQ(e.notes.size(), 1u);
    EXPECT_NE(e.notes[0].find("1 tweaks ignored"), std::string::npos) << e.notes[0];
}

TEST(MeshEval, CorruptStoredDataIsSkippedWithAReason) {
    const char* badEdge = R"(createNode mesh -n "bad";
	setAttr -s 3 ".vt[0:2]" 0 0 0  1 0 0  0 1 0;
	setAttr -s 3 ".ed[0:2]" 0 1 0  1 2 0  2 0 0;
	setAttr ".fc[0]" -type "polyFaces" f 3 0 1 7;
)";
    Graph g = MaReader::readString(badEdge);
    MeshEvaluation e = evaluate(g, g.find("bad"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("edge that does not exist"), std::string::npos) << e.skipReason;

    const char* badVertex = R"(createNode mesh -n "bad";
	setAttr -s 3 ".vt[0:2]" 0 0 0  1 0 0  0 1 0;
	setAttr -s 3 ".ed[0:2]" 0 1 0  1 5 0  5 0 0;
	setAttr ".fc[0]" -type "polyFaces" f 3 0 1 2;
)";
    g = MaReader::readString(badVertex);
    e = evaluate(g, g.find("bad"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("vertex that does not exist"), std::string::npos) << e.skipReason;

    // Edges that do not join up still give a mesh, with a note.
    const char* broken = R"(createNode mesh -n "odd";
	setAttr -s 4 ".vt[0:3]" 0 0 0  1 0 0  0 1 0  1 1 0;
	setAttr -s 3 ".ed[0:2]" 0 1 0  2 3 0  2 0 0;
	setAttr ".fc[0]" -type "polyFaces" f 3 0 1 2;
)";
    g = MaReader::readString(broken);
    e = evaluate(g, g.find("odd"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    ASSERT_FALSE(e.notes.empty());
    EXPECT_NE(e.notes[0].find("do not meet"), std::string::npos);
}

TEST(MeshEval, EmptyMeshAndNonMeshNodesAreSkipped) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "empty");
    MeshEvaluation e = evaluate(g, s.shape);
    EXPECT_FALSE(e.mesh);
    EXPECT_EQ(e.skipReason, "mesh emptyShape stores no geometry and has no construction history");
    e = evaluate(g, s.transform);
    EXPECT_FALSE(e.mesh);
    EXPECT_EQ(e.skipReason, "empty is a transform, not a mesh");
    e = evaluate(g, NodeId(g.size() + 5));
    EXPECT_FALSE(e.mesh);
    std::string reason;
    Evaluator ev(g, 1.0);
    EXPECT_FALSE(evaluateMesh(ev, s.shape, &reason));
    EXPECT_NE(reason.find("stores no geometry"), std::string::npos);
}

// ------------------------------------------------------------------ history via the Graph API
TEST(MeshEval, PolyCubeHistoryThroughTheGraphApi) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    set(g, cube, "w", {2.0});
    set(g, cube, "sw", {2.0});
    connect(g, cube, "out", s.shape, "i");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 12u);
    EXPECT_EQ(e.mesh->faceCount(), 10u);
    EXPECT_NEAR(e.mesh->bounds().hi.x, 1.0, 1e-6);
    EXPECT_NEAR(e.mesh->bounds().hi.y, 0.5, 1e-6);
    EXPECT_EQ(e.history, (std::vector<std::string>{"polyCube polyCube1"}));
    EXPECT_FALSE(e.usedCachedData);
}

TEST(MeshEval, EveryCreatorEvaluatesWithDefaults) {
    struct Case { const char* type; size_t points, faces; };
    for (const Case c : {Case{"polyCube", 8, 6}, Case{"polySphere", 382, 400}, Case{"polyPlane", 121, 100},
                         Case{"polyCylinder", 42, 60}, Case{"polyCone", 21, 21}, Case{"polyTorus", 400, 400},
                         Case{"polyPlatonicSolid", 20, 12}}) {
        Graph g;
        const ShapeUnderTransform s = addMesh(g, "obj");
        const NodeId creator = g.createNode(c.type, std::string(c.type) + "1");
        connect(g, creator, "output", s.shape, "inMesh");
        const MeshEvaluation e = evaluate(g, s.shape);
        ASSERT_TRUE(e.mesh) << c.type << ": " << e.skipReason;
        EXPECT_EQ(e.mesh->points.size(), c.points) << c.type;
        EXPECT_EQ(e.mesh->faceCount(), c.faces) << c.type;
        EXPECT_TRUE(e.mesh->validate().ok());
    }
}

TEST(MeshEval, CreatorAttributeEdgeCases) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pSphere1");
    const NodeId sphere = g.createNode("polySphere", "polySphere1");
    connect(g, sphere, "output", s.shape, "inMesh");
    set(g, sphere, "sa", {0.0});
    set(g, sphere, "sh", {1.0});
    MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 5u);  // clamped to 3 around, 2 high

    set(g, sphere, "r", {std::numeric_limits<double>::quiet_NaN()});
    e = evaluate(g, s.shape);
    EXPECT_FALSE(e.mesh);
    EXPECT_EQ(e.skipReason, "polySphere: radius is not a finite number (polySphere1)");

    set(g, sphere, "r", {2.0});
    set(g, sphere, "ax", {1.0, 0.0, 0.0}, Numbers::Kind::Tuple);
    set(g, sphere, "cuv", {0.0});
    e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_TRUE(e.mesh->uvSets.empty());
    EXPECT_NEAR(e.mesh->bounds().hi.x, 2.0, 1e-5);
}

TEST(MeshEval, PolyTweakTransformGeometryAndShapeTweaks) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId tweak = g.createNode("polyTweak", "polyTweak1");
    const NodeId xform = g.createNode("transformGeometry", "transformGeometry1");
    set(g, tweak, "tk[0]", {0.0, -1.0, 0.0}, Numbers::Kind::Tuple);
    set(g, tweak, "tk[50]", {5.0, 5.0, 5.0}, Numbers::Kind::Tuple);  // past the end: reported
    // Row-major, translation in the 4th row: move by (0, 0, 10).
    Numbers m;
    m.kind = Numbers::Kind::Matrix;
    m.values = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 10, 1};
    g.setValue(xform, *parsePlugPath("txf"), m);
    set(g, s.shape, "pt[1]", {1.0, 0.0, 0.0}, Numbers::Kind::Tuple);
    connect(g, cube, "output", tweak, "inputPolymesh");
    connect(g, tweak, "output", xform, "inputGeometry");
    connect(g, xform, "outputGeometry", s.shape, "inMesh");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& mesh = *e.mesh;
    EXPECT_EQ(mesh.points[0], glm::vec3(-0.5f, -1.5f, 10.5f));
    EXPECT_EQ(mesh.points[1], glm::vec3(1.5f, -0.5f, 10.5f));  // the shape's tweak comes last
    EXPECT_EQ(mesh.points[2], glm::vec3(-0.5f, 0.5f, 10.5f));
    EXPECT_EQ(e.history, (std::vector<std::string>{"transformGeometry transformGeometry1", "polyTweak polyTweak1",
                                                   "polyCube polyCube1"}));
    ASSERT_EQ(e.notes.size(), 1u);
    EXPECT_NE(e.notes[0].find("polyTweak1"), std::string::npos);

    Graph inverted;
    const ShapeUnderTransform si = addMesh(inverted, "p");
    const NodeId c2 = inverted.createNode("polyCube", "polyCube1");
    const NodeId x2 = inverted.createNode("transformGeometry", "transformGeometry1");
    inverted.setValue(x2, *parsePlugPath("txf"), m);
    set(inverted, x2, "itf", {1.0});
    connect(inverted, c2, "output", x2, "inputGeometry");
    connect(inverted, x2, "outputGeometry", si.shape, "inMesh");
    const MeshEvaluation ei = evaluate(inverted, si.shape);
    ASSERT_TRUE(ei.mesh) << ei.skipReason;
    EXPECT_NEAR(ei.mesh->bounds().center().z, -10.0, 1e-5);
}

TEST(MeshEval, DeleteComponentRemovesFacesAndCompacts) {
    struct Case { const char* component; size_t faces, points; };
    // A cube corner is on three edges: Maya deletes only points on two edges, so it stays.
    for (const Case c : {Case{"f[0:1]", 4, 8}, Case{"vtx[0]", 6, 8}, Case{"f[*]", 0, 0}, Case{"f[2]", 5, 8}}) {
        Graph g;
        const ShapeUnderTransform s = addMesh(g, "pCube1");
        const NodeId cube = g.createNode("polyCube", "polyCube1");
        const NodeId del = g.createNode("deleteComponent", "deleteComponent1");
        g.setValue(del, *parsePlugPath("dc"), ComponentList{{c.component}});
        connect(g, cube, "output", del, "inputGeometry");
        connect(g, del, "outputGeometry", s.shape, "inMesh");
        const MeshEvaluation e = evaluate(g, s.shape);
        ASSERT_TRUE(e.mesh) << e.skipReason;
        EXPECT_EQ(e.mesh->faceCount(), c.faces) << c.component;
        EXPECT_EQ(e.mesh->points.size(), c.points) << c.component;
        EXPECT_TRUE(e.mesh->validate().ok());
    }
    // An edge dissolves: its two faces become one.
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId del = g.createNode("deleteComponent", "deleteComponent1");
    g.setValue(del, *parsePlugPath("dc"), ComponentList{{"e[0]", "f[99]", "junk"}});
    connect(g, cube, "output", del, "inputGeometry");
    connect(g, del, "outputGeometry", s.shape, "inMesh");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 5u);
    EXPECT_EQ(e.mesh->points.size(), 8u);
    EXPECT_EQ(e.notes.size(), 2u);  // the bad item and the face past the end
}

TEST(MeshEval, GroupPartsRecordsComponentGroups) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId parts = g.createNode("groupParts", "groupParts1");
    const NodeId id = g.createNode("groupId", "groupId1");
    set(g, id, "id", {3.0});
    g.setValue(parts, *parsePlugPath("ic"), ComponentList{{"f[0:3]"}});
    connect(g, id, "id", parts, "gi");
    connect(g, cube, "output", parts, "ig");
    connect(g, parts, "og", s.shape, "i");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    ASSERT_EQ(e.groups.size(), 1u);
    EXPECT_EQ(e.groups[0].groupParts, "groupParts1");
    EXPECT_EQ(e.groups[0].groupId, 3);
    EXPECT_EQ(faceMask(e.groups[0].components, e.mesh->faceCount()),
              (std::vector<bool>{true, true, true, true, false, false}));
}

TEST(MeshEval, CreateColorSetPassesGeometryThrough) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId colors = g.createNode("createColorSet", "createColorSet1");
    g.setValue(colors, *parsePlugPath("colos"), StringValue{"paint"});
    connect(g, cube, "output", colors, "ig");
    connect(g, colors, "og", s.shape, "i");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    ASSERT_EQ(e.mesh->colorSets.size(), 1u);
    EXPECT_EQ(e.mesh->colorSets[0].name, "paint");
}

TEST(MeshEval, UnknownHistoryIsSkippedUnlessTheShapeCachesGeometry) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId mirror = g.createNode("polyMirror", "polyMirror1");
    connect(g, cube, "output", mirror, "inputPolymesh");
    connect(g, mirror, "output", s.shape, "inMesh");
    MeshEvaluation e = evaluate(g, s.shape);
    EXPECT_FALSE(e.mesh);
    EXPECT_EQ(e.skipReason, "history node polyMirror (polyMirror1) is not evaluated");

    // With the final mesh cached on the shape, that is used instead.
    Graph cached = MaReader::readString(kWorkedCube);
    const NodeId shape = cached.find("pCubeShape1");
    const NodeId pipe = cached.createNode("polyPipe", "polyPipe1");
    connect(cached, pipe, "output", shape, "inMesh");
    e = evaluate(cached, shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_TRUE(e.usedCachedData);
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    ASSERT_FALSE(e.notes.empty());
    EXPECT_NE(e.notes[0].find("polyPipe (polyPipe1) is not evaluated"), std::string::npos);
}

TEST(MeshEval, OrigShapeFeedingDeformers) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId orig = g.createNode("mesh", "pCubeShape1Orig", s.transform);
    set(g, orig, "io", {1.0});
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    connect(g, cube, "output", orig, "inMesh");
    // Orig → shape directly: evaluates through the other shape.
    connect(g, orig, "outMesh", s.shape, "inMesh");
    MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    EXPECT_EQ(e.history.front(), "mesh pCubeShape1Orig");

    // Orig.worldMesh → tweak → skinCluster → shape: the deformers take the points in object space
    // (the transform's translate is not applied twice), and a skin without weights leaves them.
    set(g, s.transform, "t", {5.0, 0.0, 0.0});
    const NodeId tweak = g.createNode("tweak", "tweak1");
    const NodeId skin = g.createNode("skinCluster", "skinCluster1");
    connect(g, orig, "worldMesh[0]", tweak, "input[0].inputGeometry");
    connect(g, tweak, "outputGeometry[0]", skin, "input[0].inputGeometry");
    connect(g, skin, "outputGeometry[0]", s.shape, "inMesh");
    e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    const geom::Bounds3 b = e.mesh->bounds();
    EXPECT_NEAR(b.lo.x, -0.5, 1e-6);
    EXPECT_NEAR(b.hi.x, 0.5, 1e-6);
    EXPECT_EQ(e.history.front(), "skinCluster skinCluster1");
}

TEST(MeshEval, ClothIsNotSimulatedItsInputMeshRenders) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "outputCloth1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId cloth = g.createNode("nCloth", "nClothShape1");
    connect(g, cube, "output", cloth, "inputMesh");
    connect(g, cloth, "outputMesh", s.shape, "inMesh");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    ASSERT_FALSE(e.notes.empty());
    EXPECT_NE(e.notes.back().find("not simulated"), std::string::npos) << e.notes.back();
}

TEST(MeshEval, HistoryCycleIsReportedNotFollowedForever) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "loop");
    const NodeId tweak = g.createNode("polyTweak", "polyTweak1");
    connect(g, s.shape, "outMesh", tweak, "inputPolymesh");
    connect(g, tweak, "output", s.shape, "inMesh");
    const MeshEvaluation e = evaluate(g, s.shape);
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("cycle"), std::string::npos) << e.skipReason;
}

TEST(MeshEval, PolySoftEdgeSetsEdgeSmoothingByAngle) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId soft = g.createNode("polySoftEdge", "polySoftEdge1");
    set(g, soft, "a", {std::numbers::pi});  // the Graph holds angles in radians
    g.setValue(soft, *parsePlugPath("ics"), ComponentList{{"e[*]"}});
    connect(g, cube, "output", soft, "ip");
    connect(g, soft, "out", s.shape, "i");
    MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    for (const geom::MeshEdge& edge : e.mesh->edges) EXPECT_TRUE(edge.smooth);
    set(g, soft, "a", {std::numbers::pi / 6});
    e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    for (const geom::MeshEdge& edge : e.mesh->edges) EXPECT_FALSE(edge.smooth);
}

// ------------------------------------------------------------------ .ma snippets with history
TEST(MeshEval, ReadsHistoryChainsFromMaText) {
    // cgkit's objects.ma: polyCube with ax = (1 0 0), h = 2, d = 3 feeding pCubeShape1.
    const char* text = R"(//Maya ASCII 7.0 scene
requires maya "7.0";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "pCube1";
	setAttr ".t" -type "double3" -2.1707668811066378 0 0 ;
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr ".uvst[0].uvsn" -type "string" "map1";
	setAttr ".cuvs" -type "string" "map1";
createNode polyCube -n "polyCube1";
	setAttr ".ax" -type "double3" 1 0 0 ;
	setAttr ".h" 2;
	setAttr ".d" 3;
connectAttr "polyCube1.out" "pCubeShape1.i";
)";
    const Graph g = MaReader::readString(text, "objects.ma");
    const MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Bounds3 b = e.mesh->bounds();
    EXPECT_NEAR(b.hi.x, 1.0, 1e-6);
    EXPECT_NEAR(b.hi.y, 0.5, 1e-6);
    EXPECT_NEAR(b.hi.z, 1.5, 1e-6);
    EXPECT_NEAR(e.mesh->signedVolume(), 6.0, 1e-5);
}

TEST(MeshEval, AnimatedCreatorAttributesAndUnits) {
    // Radius keyed 1 → 3 between frames 1 and 10, in a file written in metres.
    const char* text = R"(currentUnit -l meter -a degree -t film;
createNode transform -n "pSphere1";
createNode mesh -n "pSphereShape1" -p "pSphere1";
createNode polySphere -n "polySphere1";
	setAttr ".sa" 8;
	setAttr ".sh" 6;
createNode animCurveTL -n "polySphere1_radius";
	setAttr ".tan" 18;
	setAttr -s 2 ".ktv[0:1]"  1 1 10 3;
connectAttr "polySphere1_radius.o" "polySphere1.r";
connectAttr "polySphere1.out" "pSphereShape1.i";
)";
    const Graph g = MaReader::readString(text, "anim.ma");
    const NodeId shape = g.find("pSphereShape1");
    MeshEvaluation e = evaluate(g, shape, 1.0);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 8u * 5u + 2u);
    EXPECT_NEAR(e.mesh->bounds().hi.y, 100.0, 1e-3);  // 1 m in centimetres
    e = evaluate(g, shape, 10.0);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_NEAR(e.mesh->bounds().hi.y, 300.0, 1e-3);
}

TEST(MeshEval, PerFaceShadingAssignmentFromMaText) {
    const char* text = R"(createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr -s 2 ".iog[0].og";
	setAttr ".iog[0].og[0].gcl" -type "componentList" 1 "f[0:3]";
	setAttr ".iog[0].og[1].gcl" -type "componentList" 2 "f[4]" "f[5]";
createNode polyCube -n "polyCube1";
createNode groupId -n "groupId1";
createNode groupParts -n "groupParts1";
	setAttr ".ic" -type "componentList" 1 "f[0:3]";
connectAttr "polyCube1.out" "groupParts1.ig";
connectAttr "groupId1.id" "groupParts1.gi";
connectAttr "groupParts1.og" "pCubeShape1.i";
)";
    const Graph g = MaReader::readString(text);
    const NodeId shape = g.find("pCubeShape1");
    const MeshEvaluation e = evaluate(g, shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    ASSERT_EQ(e.groups.size(), 1u);
    const Value* first = g.value(shape, "iog[0].og[0].gcl");
    const Value* second = g.value(shape, "iog[0].og[1].gcl");
    ASSERT_TRUE(first && std::holds_alternative<ComponentList>(*first));
    ASSERT_TRUE(second && std::holds_alternative<ComponentList>(*second));
    std::string error;
    EXPECT_EQ(faceMask(std::get<ComponentList>(*first), e.mesh->faceCount(), &error),
              (std::vector<bool>{true, true, true, true, false, false}));
    EXPECT_EQ(faceMask(std::get<ComponentList>(*second), e.mesh->faceCount(), &error),
              (std::vector<bool>{false, false, false, false, true, true}));
    EXPECT_TRUE(error.empty()) << error;
}

// ------------------------------------------------------------------ public corpus
TEST(MeshEval, PublicCorpusEvaluatesOrSkipsEveryShape) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const std::vector<std::filesystem::path> files = test::maCorpusFiles();
    size_t totalShapes = 0, totalEvaluated = 0, totalCached = 0;
    for (const std::filesystem::path& file : files) {
        Graph g;
        try {
            g = MaReader::readFile(file);
        } catch (const Error& err) {
            std::cout << "[corpus] " << file.filename().string() << ": not read: " << err.what() << "\n";
            continue;
        }
        Evaluator ev(g, 1.0);
        size_t shapes = 0, evaluated = 0, cached = 0, notes = 0;
        std::map<std::string, int> reasons;
        for (NodeId shape : g.nodesOfType("mesh")) {
            ++shapes;
            MeshEvaluation e;
            EXPECT_NO_THROW(e = evaluateMeshShape(ev, shape)) << file << " " << g.node(shape).name;
            notes += e.notes.size();
            if (e.mesh) {
                ++evaluated;
                cached += e.usedCachedData;
                EXPECT_TRUE(e.mesh->validate().ok()) << file << " " << g.node(shape).name;
            } else {
                EXPECT_FALSE(e.skipReason.empty());
                // Group reasons by their kind, without node names.
                std::string kind = e.skipReason;
                if (const size_t paren = kind.find(" ("); paren != std::string::npos) kind = kind.substr(0, paren);
                if (kind.rfind("mesh ", 0) == 0) kind = "mesh: " + kind.substr(kind.find(' ', 5) + 1);
                ++reasons[kind];
            }
        }
        std::cout << "[corpus] " << file.filename().string() << ": " << shapes << " meshes, " << evaluated
                  << " evaluated (" << cached << " from cached data), " << shapes - evaluated << " skipped, "
                  << notes << " notes";
        for (const auto& [why, count] : reasons) std::cout << "; " << count << "x " << why;
        std::cout << "\n";
        totalShapes += shapes;
        totalEvaluated += evaluated;
        totalCached += cached;
    }
    std::cout << "[corpus] total: " << totalShapes << " meshes, " << totalEvaluated << " evaluated (" << totalCached
              << " from cached data)\n";
    EXPECT_GT(totalEvaluated, 0u);
}

// polyTriangulate on a cube: 6 quads become 12 triangles over the same 8 points, the surface
// area and the enclosed volume unchanged, every UV corner carried over; a listed face only.
TEST(MeshEval, PolyTriangulateSplitsFacesKeepingTheSurface) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId tri = g.createNode("polyTriangulate", "polyTriangulate1");
    connect(g, cube, "out", tri, "ip");
    connect(g, tri, "out", s.shape, "i");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    const geom::Mesh& m = *e.mesh;
    EXPECT_EQ(m.points.size(), 8u);
    ASSERT_EQ(m.faceCount(), 12u);
    double area = 0.0;
    for (size_t f = 0; f < m.faceCount(); ++f) {
        EXPECT_EQ(m.faceOuterLoop(f).size(), 3u);
        area += glm::length(m.faceAreaVector(f));
    }
    EXPECT_NEAR(area, 6.0, 1e-6);
    EXPECT_NEAR(m.signedVolume(), 1.0, 1e-6);
    ASSERT_FALSE(m.uvSets.empty());
    EXPECT_EQ(m.uvSets[0].faceVertexUvs.size(), 36u);
    for (int32_t id : m.uvSets[0].faceVertexUvs) EXPECT_GE(id, 0);
    EXPECT_EQ(m.edges.size(), 18u);  // 12 cube edges and one diagonal per face

    ComponentList only;
    only.items = {"f[2]"};
    g.setValue(tri, *parsePlugPath("ics"), only);
    const MeshEvaluation one = evaluate(g, s.shape);
    ASSERT_TRUE(one.mesh) << one.skipReason;
    EXPECT_EQ(one.mesh->faceCount(), 7u);
}

// Ear clipping keeps a concave face inside its outline: an L of six corners becomes four
// triangles whose areas add up to the L's.
TEST(MeshEval, TriangulationOfAConcaveFace) {
    geom::Mesh m;
    m.points = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    m.addFace({0, 1, 2, 3, 4, 5});
    EXPECT_EQ(geom::triangulateFaces(m), 0u);
    ASSERT_EQ(m.faceCount(), 4u);
    double area = 0.0;
    for (size_t f = 0; f < m.faceCount(); ++f) {
        const glm::dvec3 a = m.faceAreaVector(f);
        EXPECT_GT(a.z, 0.0) << "triangle " << f << " is flipped or outside the outline";
        area += a.z;
    }
    EXPECT_NEAR(area, 3.0, 1e-9);
}

// History nodes that only edit UVs pass the geometry through with a note.
TEST(MeshEval, UvOnlyHistoryPassesGeometryThrough) {
    Graph g;
    const ShapeUnderTransform s = addMesh(g, "pCube1");
    const NodeId cube = g.createNode("polyCube", "polyCube1");
    const NodeId proj = g.createNode("polyAutoProj", "polyAutoProj1");
    const NodeId unfold = g.createNode("Unfold3DUnfold", "Unfold3DUnfold1");
    connect(g, cube, "out", proj, "ip");
    connect(g, proj, "out", unfold, "im");
    connect(g, unfold, "om", s.shape, "i");
    const MeshEvaluation e = evaluate(g, s.shape);
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 6u);
    ASSERT_EQ(e.notes.size(), 2u);
    EXPECT_NE(e.notes[0].find("UV edits are not applied"), std::string::npos) << e.notes[0];
    // Node types pushpin evaluates are not reported as unsupported.
    EXPECT_TRUE(g.unsupportedTypes().empty()) << g.unsupportedTypes().begin()->first;
    Graph h;
    for (const char* type : {"polyTriangulate", "polySoftEdge", "polyNormal", "polyNormalPerVertex", "polyMapCut",
                             "polyPlanarProj", "polyMergeUV", "createUVSet", "Unfold3DUnfold"})
        h.createNode(type, std::string(type) + "1");
    EXPECT_TRUE(h.unsupportedTypes().empty()) << h.unsupportedTypes().begin()->first;
}


namespace extrude_text {

// A metre scene: the cube is 2 m (200 cm) wide, moved 10 m up by its transform. The extrusion
// works in world space: its local translate of 1 m along the top face's normal, and a tweak whose
// float3 values are centimetres whatever the file's unit.
constexpr const char* kExtrudeScene = R"(currentUnit -l meter -a degree -t film;
createNode transform -n "pCube1";
	setAttr ".t" -type "double3" 0 10 0 ;
createNode mesh -n "pCubeShape1" -p "pCube1";
createNode polyCube -n "polyCube1";
	setAttr ".w" 2;
	setAttr ".h" 2;
	setAttr ".d" 2;
createNode polyExtrudeFace -n "polyExtrudeFace1";
	setAttr ".ics" -type "componentList" 1 "f[1]";
	setAttr ".ix" -type "matrix" 1 0 0 0 0 2 0 0 0 0 1 0 0 1000 0 1;
	setAttr ".ws" yes;
	setAttr ".lt" -type "double3" 0 0 1 ;
	setAttr ".off" 0.25;
createNode polyTweak -n "polyTweak1";
	setAttr -s 4 ".tk[8:11]" -type "float3" 0 50 0 0 50 0 0 50 0 0 50 0;
connectAttr "polyCube1.out" "polyExtrudeFace1.ip";
connectAttr "polyExtrudeFace1.out" "polyTweak1.ip";
connectAttr "polyTweak1.out" "pCubeShape1.i";
)";

}  // namespace extrude_text

TEST(MeshEval, PolyExtrudeFaceMovesInWorldSpaceAndNamesWhatItDoesNotApply) {
    const Graph g = MaReader::readString(extrude_text::kExtrudeScene, "extrude.ma");
    const MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 12u);
    EXPECT_EQ(e.mesh->faceCount(), 10u);
    // Top at 100 cm; 1 m along the normal in world space, where inputMatrix doubles y, is 50 cm
    // in object space; the tweak adds 50 cm more.
    EXPECT_NEAR(e.mesh->bounds().hi.y, 200.0, 1e-3);
    EXPECT_NEAR(e.mesh->bounds().hi.x, 100.0, 1e-3);
    bool offsetNoted = false;
    for (const std::string& n : e.notes) offsetNoted |= n.find("offset not applied") != std::string::npos;
    EXPECT_TRUE(offsetNoted);
}

TEST(MeshEval, PolyExtrudeFaceWithoutComponentsOrWithBadValues) {
    std::string text = extrude_text::kExtrudeScene;
    // No components: the mesh passes through.
    std::string none = text;
    none.replace(none.find("\tsetAttr \".ics\""), std::string("\tsetAttr \".ics\" -type \"componentList\" 1 \"f[1]\";\n").size(), "");
    Graph g = MaReader::readString(none, "none.ma");
    MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 8u);
    // A scale that takes the cap past the largest double skips the shape with a reason naming the node.
    std::string bad = text;
    bad.replace(bad.find("\tsetAttr \".off\""), 0, "\tsetAttr \".s\" -type \"double3\" 1e308 1e308 1e308 ;\n");
    g = MaReader::readString(bad, "bad.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("polyExtrudeFace1"), std::string::npos) << e.skipReason;
}

TEST(MeshEval, PolySplitRingAndPolyMergeVertFromMaText) {
    // A cube cut round its middle, then two corners of one end merged into one.
    const std::string text = cubeThrough(R"(createNode polySplitRing -n "polySplitRing1";
	setAttr ".ics" -type "componentList" 2 "e[6:7]" "e[10:11]";
	setAttr ".wt" 0.5;
	setAttr ".re" 7;
createNode polyMergeVert -n "polyMergeVert1";
	setAttr ".ics" -type "componentList" 2 "vtx[0]" "vtx[1]";
	setAttr ".mtc" -type "componentList" 1 "vtx[1]";
)", {"polySplitRing1", "polyMergeVert1"}, "\tsetAttr \".d\" 8;\n");
    Graph g = MaReader::readString(text, "split.ma");
    MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 11u);  // 8 + 4 from the split, 1 merged away
    EXPECT_EQ(e.mesh->faceCount(), 10u);
    EXPECT_NEAR(e.mesh->points[0].x, 0.5, 1e-6);  // merged at vtx[1]'s place
    // Several loops (splitType 2): `divisions` loops evenly along the ring, at z = 2, 0 and -2.
    std::string multi = text;
    multi.replace(multi.find("\tsetAttr \".re\" 7;"), 0, "\tsetAttr \".stp\" 2;\n\tsetAttr \".div\" 3;\n");
    g = MaReader::readString(multi, "multi.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 8u + 12u - 1u);
    EXPECT_EQ(e.mesh->faceCount(), 18u);
    std::map<int, int> atZ;
    for (const glm::vec3& q : e.mesh->points) ++atZ[int(std::lround(q.z))];
    EXPECT_EQ(atZ[2], 4);
    EXPECT_EQ(atZ[0], 4);
    EXPECT_EQ(atZ[-2], 4);
    // An absolute distance (splitType 1) is not evaluated: the shape is skipped, naming the node.
    std::string absolute = text;
    absolute.replace(absolute.find("\tsetAttr \".re\" 7;"), 0, "\tsetAttr \".stp\" 1;\n");
    g = MaReader::readString(absolute, "absolute.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("polySplitRing1"), std::string::npos) << e.skipReason;
    EXPECT_NE(e.skipReason.find("absolute distance"), std::string::npos) << e.skipReason;
}

TEST(MeshEval, PolySplitFromMaText) {
    // A unit cube cut down its front face (0 1 3 2) from the middle of e[0] (0→1, along the
    // bottom) to the middle of e[1] (2→3, along the top). Edge descriptors are the edge number
    // with bit 31 set.
    const std::string text = cubeThrough(R"(createNode polySplit -n "polySplit1";
	setAttr -s 2 ".e[0:1]"  0.5 0.5;
	setAttr -s 2 ".d[0:1]"  -2147483648 -2147483647;
	setAttr ".sma" 180;
)", {"polySplit1"});
    Graph g = MaReader::readString(text, "split.ma");
    MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    ASSERT_EQ(e.mesh->points.size(), 10u);
    EXPECT_EQ(e.mesh->faceCount(), 7u);
    EXPECT_EQ(e.mesh->points[8], glm::vec3(0.0f, -0.5f, 0.5f));
    EXPECT_EQ(e.mesh->points[9], glm::vec3(0.0f, 0.5f, 0.5f));
    EXPECT_TRUE(e.mesh->edges.back().smooth);

    // Through a free point. Maya 2015's files give its face in `edge` and its slot in `vertices`
    // in `desc`; older ones give the face in `desc` and -1 in `edge`.
    const std::string free2015 = cubeThrough(R"(createNode polySplit -n "polySplit1";
	setAttr -s 1 ".v[0]" -type "float3" 0.2 0 0.5;
	setAttr -s 3 ".e[0:2]"  0.5 0 0.5;
	setAttr -s 3 ".d[0:2]"  -2147483648 0 -2147483647;
	setAttr ".m2015" yes;
)", {"polySplit1"});
    std::string older = free2015;
    older.replace(older.find("0.5 0 0.5;"), 9, "0.5 -1 0.5;");
    older.replace(older.find("\tsetAttr \".m2015\" yes;\n"), 23, "");
    for (const std::string& variant : {free2015, older}) {
        g = MaReader::readString(variant, "free.ma");
        e = evaluate(g, g.find("pCubeShape1"));
        ASSERT_TRUE(e.mesh) << e.skipReason;
        ASSERT_EQ(e.mesh->points.size(), 11u);
        EXPECT_EQ(e.mesh->faceCount(), 7u);
        EXPECT_EQ(e.mesh->points[9], glm::vec3(0.0f, 0.5f, 0.5f));  // the edge points first
        EXPECT_NEAR(e.mesh->points[10].x, 0.2, 1e-6);               // then the free point
        EXPECT_NEAR(e.mesh->points[10].z, 0.5, 1e-6);
        EXPECT_FALSE(e.mesh->edges.back().smooth);  // the default smoothing angle is 0
        ASSERT_TRUE(e.mesh->validate().ok());
    }

    // An edge the mesh does not have skips the shape, naming the node.
    std::string bad = text;
    bad.replace(bad.find("-2147483647"), 11, "-2147483000");
    g = MaReader::readString(bad, "bad.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("polySplit1"), std::string::npos) << e.skipReason;
    EXPECT_NE(e.skipReason.find("edge 648"), std::string::npos) << e.skipReason;

    // Split points given by face triangles (Maya 2011's splitPoints) are not evaluated yet.
    std::string triangles = text;
    triangles.replace(triangles.find("\tsetAttr \".sma\" 180;"), 0,
                      "\tsetAttr \".sps[0].sp[0].f\" 0;\n\tsetAttr \".sps[0].sp[0].bc\" -type \"double3\" 0.5 0.5 0;\n");
    g = MaReader::readString(triangles, "triangles.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("splitPoints"), std::string::npos) << e.skipReason;
}

TEST(MeshEval, PolyBevelChamfersTheListedEdges) {
    // polyBevel3 with Maya's defaults (fraction 0.5 of half the shortest edge) on every edge of a
    // unit cube: 26 faces, the closed-form volume with d = 0.25.
    const std::string text = cubeThrough(R"(createNode polyBevel3 -n "polyBevel1";
	setAttr ".ics" -type "componentList" 1 "e[0:11]";
)", {"polyBevel1"});
    Graph g = MaReader::readString(text, "bevel.ma");
    MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 26u);
    const double d = 0.25;
    EXPECT_NEAR(e.mesh->signedVolume(), 1.0 - 12 * 0.5 * d * d * (1 - 2 * d) - 8 * (5.0 / 6.0) * d * d * d, 1e-6);
    EXPECT_TRUE(std::any_of(e.notes.begin(), e.notes.end(), [](const std::string& n) { return n.find("chamfer") != std::string::npos; }));
    // The old polyBevel takes an absolute offset; more than one segment is not evaluated.
    std::string old = text;
    old.replace(old.find("polyBevel3"), 10, "polyBevel");
    old.replace(old.find("\tsetAttr \".ics\""), 0, "\tsetAttr \".o\" 0.1;\n");
    g = MaReader::readString(old, "old.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_NEAR(e.mesh->signedVolume(), 1.0 - 12 * 0.5 * 0.01 * 0.8 - 8 * (5.0 / 6.0) * 0.001, 1e-6);
    std::string rounded = text;
    rounded.replace(rounded.find("\tsetAttr \".ics\""), 0, "\tsetAttr \".sg\" 3;\n");
    g = MaReader::readString(rounded, "rounded.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("3 segments"), std::string::npos) << e.skipReason;
}

TEST(MeshEval, PolySmoothFaceAndSmoothMeshPreview) {
    const std::string text = cubeThrough(R"(createNode polySmoothFace -n "polySmoothFace1";
	setAttr ".ics" -type "componentList" 1 "f[*]";
)", {"polySmoothFace1"});
    Graph g = MaReader::readString(text, "smooth.ma");
    MeshEvaluation e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 24u);
    EXPECT_TRUE(e.faceOrigin.empty());  // history smoothing renumbers the faces for good

    // The linear method is not evaluated: the shape is skipped, naming the node.
    std::string linear = text;
    linear.replace(linear.find("connectAttr"), 0, "setAttr \"polySmoothFace1.mth\" 1;\n");
    g = MaReader::readString(linear, "linear.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("polySmoothFace1"), std::string::npos) << e.skipReason;

    // Smooth mesh preview at level 2 renders 96 faces, each mapped to the cube face it came from.
    const char* preview = R"(createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr ".dsm" 2;
createNode polyCube -n "polyCube1";
connectAttr "polyCube1.out" "pCubeShape1.i";
)";
    g = MaReader::readString(preview, "preview.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 96u);
    ASSERT_EQ(e.faceOrigin.size(), 96u);
    EXPECT_EQ(e.sourceFaceCount, 6u);
    EXPECT_EQ(e.faceOrigin[95], 5u);
    // With useSmoothPreviewForRender off, renderSmoothLevel (1) decides.
    std::string render = preview;
    render.replace(render.find("createNode polyCube"), 0, "\tsetAttr \".uspr\" no;\n");
    g = MaReader::readString(render, "render.ma");
    e = evaluate(g, g.find("pCubeShape1"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->faceCount(), 24u);
}

TEST(MeshEval, PolyUniteSeparateAndDelEdgeFromMaText) {
    // Two cubes, one moved 5 along X by its transform, united in world space; then the second
    // shell separated out again, and an edge of it deleted with its winged ends.
    const char* text = R"(createNode transform -n "a";
createNode mesh -n "aShape" -p "a";
	setAttr ".io" yes;
createNode transform -n "b";
	setAttr ".t" -type "double3" 5 0 0 ;
createNode mesh -n "bShape" -p "b";
	setAttr ".io" yes;
createNode transform -n "united";
createNode mesh -n "unitedShape" -p "united";
createNode transform -n "piece";
createNode mesh -n "pieceShape" -p "piece";
createNode polyCube -n "polyCube1";
createNode polyCube -n "polyCube2";
createNode polyUnite -n "polyUnite1";
createNode polySeparate -n "polySeparate1";
createNode polyDelEdge -n "polyDelEdge1";
	setAttr ".ics" -type "componentList" 1 "e[0]";
	setAttr ".cv" yes;
connectAttr "polyCube1.out" "aShape.i";
connectAttr "polyCube2.out" "bShape.i";
connectAttr "aShape.o" "polyUnite1.ip[0]";
connectAttr "bShape.o" "polyUnite1.ip[1]";
connectAttr "aShape.wm" "polyUnite1.im[0]";
connectAttr "bShape.wm" "polyUnite1.im[1]";
connectAttr "polyUnite1.out" "unitedShape.i";
connectAttr "polyUnite1.out" "polySeparate1.ip";
connectAttr "polySeparate1.out[1]" "polyDelEdge1.ip";
connectAttr "polyDelEdge1.out" "pieceShape.i";
)";
    Graph g = MaReader::readString(text, "unite.ma");
    MeshEvaluation e = evaluate(g, g.find("unitedShape"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    EXPECT_EQ(e.mesh->points.size(), 16u);
    EXPECT_EQ(e.mesh->faceCount(), 12u);
    EXPECT_NEAR(e.mesh->bounds().hi.x, 5.5, 1e-6);
    EXPECT_NEAR(e.mesh->bounds().lo.x, -0.5, 1e-6);
    EXPECT_EQ(e.mesh->uvSets.size(), 1u);
    EXPECT_TRUE(e.mesh->validate().ok());

    e = evaluate(g, g.find("pieceShape"));
    ASSERT_TRUE(e.mesh) << e.skipReason;
    // The second cube (at x = 5), its edge 0-1 dissolved and both ends, left on two edges, gone.
    EXPECT_EQ(e.mesh->faceCount(), 5u);
    EXPECT_EQ(e.mesh->points.size(), 6u);
    EXPECT_NEAR(e.mesh->bounds().lo.x, 4.5, 1e-6);
    EXPECT_TRUE(e.mesh->validate().ok());

    // A shell past the last is a skip with a reason.
    std::string past = text;
    past.replace(past.find("polySeparate1.out[1]"), std::string("polySeparate1.out[1]").size(), "polySeparate1.out[7]");
    g = MaReader::readString(past, "past.ma");
    e = evaluate(g, g.find("pieceShape"));
    EXPECT_FALSE(e.mesh);
    EXPECT_NE(e.skipReason.find("shell"), std::string::npos) << e.skipReason;
}


// ------------------------------------------------------------------ windows of a stored mesh

TEST(MeshEval, AStoredMeshMakesEachPieceFromItsOwnWindow) {
    const Graph g = MaReader::readString(test::storedGridMesh("grid", 30, 20, "\".dsm\" 0;"));
    const NodeId shape = g.find("gridShape");
    Evaluator ev(g, 1.0);
    ASSERT_TRUE(storedMeshMakesWindows(ev, shape));
    std::string error;
    const std::optional<geom::Mesh> mesh = decodeStoredMesh(g, shape, &error);
    ASSERT_TRUE(mesh) << error;
    ASSERT_TRUE(mesh->validate().ok());
    ASSERT_EQ(mesh->normals.size(), mesh->faceVertexCount());
    ASSERT_EQ(mesh->currentUvSet, 1);
    const std::vector<uint16_t> material;
    const std::vector<bool> degenerate;
    for (uint32_t maxSlots : {1u, 30u, 100u, 450u})
        for (const geom::MeshPieces::Layout layout : {geom::MeshPieces::Layout::Spatial, geom::MeshPieces::Layout::FaceOrder}) {
        const geom::MeshPieces pieces = geom::MeshPieces::split(*mesh, material, degenerate, maxSlots, layout);
        ASSERT_TRUE(pieces.mapsUvs());
        ASSERT_GE(pieces.pieces().size(), 3u);
        EXPECT_EQ(pieces.spatial(), layout == geom::MeshPieces::Layout::Spatial);
        for (size_t k = 0; k < pieces.pieces().size(); ++k) {
            const geom::MeshWindow cut = geom::cutMeshWindow(*mesh, pieces, k);
            const std::optional<geom::MeshWindow> made = decodeStoredMeshWindow(g, shape, pieces, k, mesh->faceVertexCount());
            ASSERT_TRUE(made) << "piece " << k;
            const geom::Mesh& a = made->mesh;
            const geom::Mesh& b = cut.mesh;
            EXPECT_EQ(a.points, b.points) << "piece " << k;
            EXPECT_EQ(a.faceVertices, b.faceVertices) << "piece " << k;
            EXPECT_EQ(a.loopStarts, b.loopStarts) << "piece " << k;
            EXPECT_EQ(a.faceLoopStarts, b.faceLoopStarts) << "piece " << k;
            EXPECT_EQ(a.normals, b.normals) << "piece " << k;
            ASSERT_EQ(a.edges.size(), b.edges.size()) << "piece " << k;
            for (size_t e = 0; e < a.edges.size(); ++e) {
                EXPECT_EQ(a.edges[e].v0, b.edges[e].v0);
                EXPECT_EQ(a.edges[e].v1, b.edges[e].v1);
                EXPECT_EQ(a.edges[e].smooth, b.edges[e].smooth);
            }
            ASSERT_EQ(a.uvSets.size(), 1u);
            ASSERT_EQ(b.uvSets.size(), 1u);
            EXPECT_EQ(a.uvSets[0].name, "cur");
            EXPECT_EQ(a.uvSets[0].name, b.uvSets[0].name);
            EXPECT_EQ(a.uvSets[0].uvs, b.uvSets[0].uvs) << "piece " << k;
            EXPECT_EQ(a.uvSets[0].faceVertexUvs, b.uvSets[0].faceVertexUvs) << "piece " << k;
            // And so the same triangles as the piece made from the whole mesh.
            const geom::Tessellation whole = geom::triangulateMeshPiece(*mesh, material, true, degenerate, pieces, k);
            const geom::Tessellation alone = geom::triangulateMeshPiece(*made, material, true, degenerate, pieces, k);
            EXPECT_EQ(alone.corners, whole.corners);
            EXPECT_EQ(alone.neighbors, whole.neighbors);
            EXPECT_EQ(alone.positions, whole.positions);
            EXPECT_EQ(alone.normals, whole.normals);
            EXPECT_EQ(alone.uvs, whole.uvs);
        }
    }
}

TEST(MeshEval, OnlyAShapeThatIsItsStoredMeshMakesWindows) {
    auto makesWindows = [](const std::string& text) {
        const Graph g = MaReader::readString(text);
        Evaluator ev(g, 1.0);
        return storedMeshMakesWindows(ev, g.find("gridShape"));
    };
    EXPECT_TRUE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".dsm\" 0;")));
    EXPECT_FALSE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".dsm\" 1;")));                       // smooth mesh preview
    EXPECT_FALSE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".pt[3]\" -type \"float3\" 0 0 0;")));  // a point tweak
    EXPECT_FALSE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".uvpt[0]\" -type \"float2\" 0 0;")));  // the old uv layout
    EXPECT_FALSE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".dsm\" 0;", true)));                  // faces without records
    EXPECT_FALSE(makesWindows(test::storedGridMesh("grid", 30, 20, "\".dsm\" 0;") +
                              "createNode polyCube -n \"cube\";\nconnectAttr \"cube.out\" \"gridShape.i\";\n"));
}

}  // namespace
}  // namespace pushpin::scene
