// Tests for core/render/frame_scene.h: geometry handles per instance, materials per face, skips, lights, light
// linking and NURBS tessellation.
#include "core/render/frame_scene.h"

#include "core/scene/ma_reader.h"

#include "tests/support/ma_corpus.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>

namespace pushpin::render {
namespace {

// ------------------------------------------------------------------ helpers

// A loaded scene with its evaluator (which refers to the graph) and the built frame.
struct Built {
    std::unique_ptr<scene::Graph> graph;
    std::unique_ptr<scene::Evaluator> ev;
    scene::RenderSetup setup;
    FrameScene frame;
};

std::unique_ptr<Built> build(const std::string& text, RenderSettings settings = {}) {
    auto b = std::make_unique<Built>();
    b->graph = std::make_unique<scene::Graph>(scene::MaReader::readString(text, "test.ma"));
    b->ev = std::make_unique<scene::Evaluator>(*b->graph, 1.0);
    b->setup = scene::extractRenderSetup(*b->graph);
    b->frame = buildFrameScene(*b->ev, b->setup, settings);
    return b;
}

const RenderObject* findObject(const FrameScene& f, const std::string& name) {
    for (const RenderObject& o : f.objects)
        if (o.name == name) return &o;
    return nullptr;
}

bool hasNote(const FrameScene& f, const std::string& part) {
    return std::any_of(f.notes.begin(), f.notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

std::string allNotes(const FrameScene& f) {
    std::string s;
    for (const std::string& n : f.notes) s += n + "\n";
    return s;
}

// An object's triangles, made once per handle for the test's lifetime.
const geom::Tessellation& tess(const RenderObject& o) {
    static std::map<const geom::GeometryHandle*, std::pair<std::shared_ptr<const geom::GeometryHandle>, geom::Tessellation>> made;
    auto it = made.find(o.geometry.get());
    if (it == made.end()) it = made.emplace(o.geometry.get(), std::make_pair(o.geometry, o.geometry->tessellate())).first;
    return it->second.second;
}

double triangleArea(const geom::Tessellation& g, size_t t) {
    const glm::dvec3 a(g.position(3 * t)), b(g.position(3 * t + 1)), c(g.position(3 * t + 2));
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

glm::dvec3 triangleNormal(const geom::Tessellation& g, size_t t) {
    const glm::dvec3 a(g.position(3 * t)), b(g.position(3 * t + 1)), c(g.position(3 * t + 2));
    return glm::cross(b - a, c - a);
}

// The shading group name of triangle t of an object.
std::string groupOf(const FrameScene& f, const RenderObject& o, size_t t) {
    return f.shadingGroups[o.materials[tess(o).material[t]].shadingGroup].name;
}

constexpr const char* kHeader = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
)";

// A polyCube under `name` (transform) / `name`Shape, with optional extra shape lines.
std::string cube(const std::string& name, const std::string& shapeLines = "", const std::string& transformLines = "") {
    return "createNode transform -n \"" + name + "\";\n" + transformLines + "createNode mesh -n \"" + name +
           "Shape\" -p \"" + name + "\";\n" + shapeLines + "createNode polyCube -n \"" + name + "Creator\";\n" +
           "connectAttr \"" + name + "Creator.out\" \"" + name + "Shape.i\";\n";
}

std::string material(const std::string& name) {
    return "createNode lambert -n \"" + name + "\";\ncreateNode shadingEngine -n \"" + name + "SG\";\nconnectAttr \"" +
           name + ".oc\" \"" + name + "SG.ss\";\nconnectAttr \"" + name + "SG.pa\" \":renderPartition.st\" -na;\n";
}

std::string assign(const std::string& shape, const std::string& sg) {
    return "connectAttr \"" + shape + ".iog\" \"" + sg + ".dsm\" -na;\n";
}

// ------------------------------------------------------------------ buildFrameScene: objects

TEST(FrameScene, TwoMaterialCubeByFaceComponents) {
    const std::string text = std::string(kHeader) +
                             cube("pCube1", "\tsetAttr -s 2 \".iog[0].og\";\n"
                                            "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[0:1]\";\n"
                                            "\tsetAttr \".iog[0].og[1].gcl\" -type \"componentList\" 2 \"f[2]\" \"f[3:5]\";\n") +
                             material("red") + material("blue") +
                             "connectAttr \"pCube1Shape.iog.og[0]\" \"redSG.dsm\" -na;\n"
                             "connectAttr \"pCube1Shape.iog.og[1]\" \"blueSG.dsm\" -na;\n";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
    const RenderObject& o = b->frame.objects[0];
    ASSERT_EQ(o.materials.size(), 2u);
    ASSERT_EQ(tess(o).triangleCount(), 12u);
    for (size_t t = 0; t < tess(o).triangleCount(); ++t)
        EXPECT_EQ(groupOf(b->frame, o, t), tess(o).face[t] < 2 ? "redSG" : "blueSG") << "triangle " << t;
    ASSERT_EQ(b->frame.shadingGroups.size(), 2u);
    for (const RenderShadingGroup& sg : b->frame.shadingGroups) EXPECT_NE(sg.network, nullptr);
    // Material borders are hard, and every cube edge has a neighbour.
    for (size_t t = 0; t < tess(o).triangleCount(); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t n = tess(o).neighbors[3 * t + k];
            ASSERT_NE(n, kNoTriangle);
            const uint32_t other = n & ~kHardEdgeBit;
            if (tess(o).material[t] != tess(o).material[other]) {
                EXPECT_NE(n & kHardEdgeBit, 0u);
            }
        }
}

TEST(FrameScene, PerFaceGroupOverridesTheWholeObjectGroupAndUnassignedFacesAreDropped) {
    std::string text = std::string(kHeader) +
                       cube("pCube1", "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[4]\";\n") +
                       material("red") + material("blue") + assign("pCube1Shape", "blueSG") +
                       "connectAttr \"pCube1Shape.iog.og[0]\" \"redSG.dsm\" -na;\n";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u);
    const RenderObject& o = b->frame.objects[0];
    for (size_t t = 0; t < tess(o).triangleCount(); ++t)
        EXPECT_EQ(groupOf(b->frame, o, t), tess(o).face[t] == 4 ? "redSG" : "blueSG");

    // Only per-face membership covering two faces: the other four are not rendered.
    text = std::string(kHeader) + cube("pCube1", "\tsetAttr \".iog[0].og[0].gcl\" -type \"componentList\" 1 \"f[1:2]\";\n") +
           material("red") + "connectAttr \"pCube1Shape.iog.og[0]\" \"redSG.dsm\" -na;\n";
    b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u);
    EXPECT_EQ(tess(b->frame.objects[0]).triangleCount(), 4u);
    for (uint32_t f : tess(b->frame.objects[0]).face) EXPECT_TRUE(f == 1 || f == 2);
    EXPECT_TRUE(hasNote(b->frame, "4 face(s) in no shading group")) << allNotes(b->frame);
}

TEST(FrameScene, GroupPartsComponentsAssignFacesThroughGroupId) {
    // The wiring Maya writes when faces are assigned before the history is deleted: the member's
    // objectGrpCompList is empty and the groupParts node tied to the same groupId lists the faces.
    const std::string text = std::string(kHeader) + R"(
createNode transform -n "pCube1";
createNode mesh -n "pCubeShape1" -p "pCube1";
	setAttr -s 2 ".iog[0].og";
createNode polyCube -n "polyCube1";
createNode groupId -n "groupId1";
createNode groupParts -n "groupParts1";
	setAttr ".ic" -type "componentList" 1 "f[1]";
createNode groupId -n "groupId2";
createNode groupParts -n "groupParts2";
	setAttr ".ic" -type "componentList" 2 "f[0]" "f[2:5]";
)" + material("red") + material("green") + R"(
connectAttr "polyCube1.out" "groupParts1.ig";
connectAttr "groupId1.id" "groupParts1.gi";
connectAttr "groupParts1.og" "groupParts2.ig";
connectAttr "groupId2.id" "groupParts2.gi";
connectAttr "groupParts2.og" "pCubeShape1.i";
connectAttr "groupId1.id" "pCubeShape1.iog.og[0].gid";
connectAttr "groupId2.id" "pCubeShape1.iog.og[1].gid";
connectAttr "pCubeShape1.iog.og[0]" "redSG.dsm" -na;
connectAttr "pCubeShape1.iog.og[1]" "greenSG.dsm" -na;
)";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
    const RenderObject& o = b->frame.objects[0];
    ASSERT_EQ(tess(o).triangleCount(), 12u);
    for (size_t t = 0; t < tess(o).triangleCount(); ++t)
        EXPECT_EQ(groupOf(b->frame, o, t), tess(o).face[t] == 1 ? "redSG" : "greenSG");
}

TEST(FrameScene, OnlyShadingGroupsOfTheRenderPartitionRender) {
    // A group Maya would not render (not wired to renderPartition.sets) leaves its object out.
    std::string unwired = material("red");
    unwired.erase(unwired.find("connectAttr \"redSG.pa\""));
    auto b = build(std::string(kHeader) + cube("pCube1") + unwired + assign("pCube1Shape", "redSG"));
    EXPECT_TRUE(b->frame.objects.empty());
    EXPECT_TRUE(hasNote(b->frame, "its shading groups are not in the renderPartition")) << allNotes(b->frame);
    // Wired, it renders.
    b = build(std::string(kHeader) + cube("pCube1") + material("red") + assign("pCube1Shape", "redSG"));
    EXPECT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
}

TEST(FrameScene, ObjectInNoShadingGroupIsSkippedWithANote) {
    auto b = build(std::string(kHeader) + cube("pCube1"));
    EXPECT_TRUE(b->frame.objects.empty());
    EXPECT_EQ(b->frame.skippedShapes, 1u);
    EXPECT_TRUE(hasNote(b->frame, "|pCube1|pCube1Shape: belongs to no shading group")) << allNotes(b->frame);
}

TEST(FrameScene, InvisibleIntermediateAndPrimaryInvisibleShapesAreSkipped) {
    const std::string text = std::string(kHeader) + cube("hidden", "", "\tsetAttr \".v\" no;\n") +
                             cube("orig", "\tsetAttr \".io\" yes;\n") + cube("noPrimary", "\tsetAttr \".vis\" no;\n") +
                             cube("shown") + material("m") + assign("hiddenShape", "mSG") + assign("origShape", "mSG") +
                             assign("noPrimaryShape", "mSG") + assign("shownShape", "mSG");
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
    EXPECT_EQ(b->frame.objects[0].name, "|shown|shownShape");
    EXPECT_EQ(b->frame.skippedShapes, 3u);
    EXPECT_TRUE(hasNote(b->frame, "|hidden|hiddenShape: hidden by 'hidden'")) << allNotes(b->frame);
    EXPECT_TRUE(hasNote(b->frame, "|orig|origShape: intermediate object"));
    EXPECT_TRUE(hasNote(b->frame, "|noPrimary|noPrimaryShape: primaryVisibility is off"));
}

TEST(FrameScene, InstancedShapeGivesOneObjectPerInstance) {
    const std::string text = std::string(kHeader) + cube("pCube1") +
                             "createNode transform -n \"pCube2\";\n\tsetAttr \".t\" -type \"double3\" 5 0 0 ;\n"
                             "parent -s -nc -r -add \"|pCube1|pCube1Shape\" \"pCube2\";\n" +
                             material("m") + "connectAttr \"pCube1Shape.iog[0]\" \"mSG.dsm\" -na;\n"
                                             "connectAttr \"pCube1Shape.iog[1]\" \"mSG.dsm\" -na;\n";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 2u) << allNotes(b->frame);
    const RenderObject* a = findObject(b->frame, "|pCube1|pCube1Shape");
    const RenderObject* c = findObject(b->frame, "|pCube2|pCube1Shape");
    ASSERT_TRUE(a && c);
    EXPECT_EQ(a->shape, c->shape);
    EXPECT_NE(a->instance, c->instance);
    EXPECT_EQ(a->worldFromObject[3], glm::dvec4(0, 0, 0, 1));
    EXPECT_EQ(c->worldFromObject[3], glm::dvec4(5, 0, 0, 1));
    // The cube's bounds come from its creator's sizes, widened by a millionth for float rounding.
    EXPECT_NEAR(c->worldBounds.lo.x, 4.5, 1e-6);
    EXPECT_LE(c->worldBounds.lo.x, 4.5);
    EXPECT_NEAR(a->worldBounds.lo.x, -0.5, 1e-6);
    EXPECT_LE(a->worldBounds.lo.x, -0.5);
    // The instances share one geometry handle, and so one tessellation.
    EXPECT_EQ(a->geometry.get(), c->geometry.get());
}

TEST(FrameScene, RenderStatsAreRead) {
    const std::string text = std::string(kHeader) +
                             cube("pCube1", "\tsetAttr \".ds\" no;\n\tsetAttr \".op\" yes;\n\tsetAttr \".csh\" no;\n"
                                            "\tsetAttr \".rcsh\" no;\n\tsetAttr \".smo\" no;\n\tsetAttr \".sso\" yes;\n"
                                            "\tsetAttr \".ssa\" 3;\n\tsetAttr \".msa\" 9;\n") +
                             cube("pCube2") + material("m") + assign("pCube1Shape", "mSG") + assign("pCube2Shape", "mSG");
    auto b = build(text);
    const RenderObject* o = findObject(b->frame, "|pCube1|pCube1Shape");
    const RenderObject* d = findObject(b->frame, "|pCube2|pCube2Shape");
    ASSERT_TRUE(o && d);
    EXPECT_FALSE(o->doubleSided);
    EXPECT_TRUE(o->opposite);
    EXPECT_FALSE(o->castsShadows);
    EXPECT_FALSE(o->receiveShadows);
    EXPECT_FALSE(o->smoothShading);
    EXPECT_TRUE(o->shadingSamplesOverride);
    EXPECT_EQ(o->shadingSamples, 3);
    EXPECT_EQ(o->maxShadingSamples, 9);
    EXPECT_TRUE(d->doubleSided && !d->opposite && d->castsShadows && d->receiveShadows && d->smoothShading);
    EXPECT_FALSE(d->shadingSamplesOverride);
    EXPECT_TRUE(o->primaryVisibility);
}

TEST(FrameScene, UnevaluableAndInvalidGeometryIsSkipped) {
    const std::string text = std::string(kHeader) + R"(
createNode transform -n "bad";
createNode mesh -n "badShape" -p "bad";
	setAttr -s 3 ".vt[0:2]"  0 0 0  1 0 0  0 1 0;
	setAttr -s 3 ".ed[0:2]"  0 1 0  1 2 0  2 0 0;
	setAttr -s 1 ".fc[0]" -type "polyFaces" f 3 0 1 5;
createNode transform -n "split";
createNode mesh -n "splitShape" -p "split";
createNode polySplitRing -n "polySplitRing1";
connectAttr "polySplitRing1.out" "splitShape.i";
createNode transform -n "empty";
createNode mesh -n "emptyShape" -p "empty";
)" + material("m") + assign("badShape", "mSG") +
                             assign("splitShape", "mSG") + assign("emptyShape", "mSG");
    std::unique_ptr<Built> b;
    ASSERT_NO_THROW(b = build(text));
    EXPECT_TRUE(b->frame.objects.empty()) << allNotes(b->frame);
    EXPECT_EQ(b->frame.skippedShapes, 3u);
    EXPECT_TRUE(hasNote(b->frame, "|bad|badShape: ")) << allNotes(b->frame);
    EXPECT_TRUE(hasNote(b->frame, "|split|splitShape: ")) << allNotes(b->frame);
    EXPECT_TRUE(hasNote(b->frame, "|empty|emptyShape: ")) << allNotes(b->frame);
}

TEST(FrameScene, NonFinitePointsSkipTheShape) {
    // A stored triangle whose first point becomes NaN (the .ma reader refuses such numbers, so
    // the value is set on the graph): validation rejects the mesh, nothing crashes.
    const std::string text = std::string(kHeader) + R"(
createNode transform -n "tri";
createNode mesh -n "triShape" -p "tri";
	setAttr -s 3 ".vt[0:2]"  0 0 0  1 0 0  0 1 0;
	setAttr -s 3 ".ed[0:2]"  0 1 0  1 2 0  2 0 0;
	setAttr -s 1 ".fc[0]" -type "polyFaces" f 3 0 1 2;
)" + material("m") + assign("triShape", "mSG");
    for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        auto graph = std::make_unique<scene::Graph>(scene::MaReader::readString(text, "test.ma"));
        const scene::NodeId shape = graph->find("triShape");
        {
            scene::Evaluator ev(*graph, 1.0);
            ASSERT_EQ(buildFrameScene(ev, scene::extractRenderSetup(*graph), RenderSettings{}).objects.size(), 1u);
        }
        scene::Numbers point;
        point.kind = scene::Numbers::Kind::Tuple;
        point.tupleSize = 3;
        point.values = {bad, 0.0, 0.0};
        graph->setValue(shape, *scene::parsePlugPath("vt[0]"), point);
        scene::Evaluator ev(*graph, 1.0);
        FrameScene f;
        ASSERT_NO_THROW(f = buildFrameScene(ev, scene::extractRenderSetup(*graph), RenderSettings{}));
        EXPECT_TRUE(f.objects.empty());
        EXPECT_EQ(f.skippedShapes, 1u);
        EXPECT_TRUE(hasNote(f, "|tri|triShape: ")) << allNotes(f);
    }
}

// ------------------------------------------------------------------ NURBS

TEST(FrameScene, NurbsSphereTessellatesWithOutwardNormals) {
    const std::string text = std::string(kHeader) + R"(
createNode transform -n "nurbsSphere1";
createNode nurbsSurface -n "nurbsSphereShape1" -p "nurbsSphere1";
createNode makeNurbSphere -n "makeNurbSphere1";
	setAttr ".r" 2;
connectAttr "makeNurbSphere1.os" "nurbsSphereShape1.cr";
)" + material("m") + assign("nurbsSphereShape1", "mSG");
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
    const geom::Tessellation& g = tess(b->frame.objects[0]);
    // Default sections 8, spans 4, numberU/V 3 × 1.5 → 5 divisions per span: two triangle ids a
    // cell. In the two pole rows one triangle of each cell has zero area: its three corners are
    // one vertex.
    EXPECT_EQ(g.triangleCount(), 2u * 20u * 40u);
    auto pole = [&](size_t t) { return g.corners[3 * t] == g.corners[3 * t + 1] && g.corners[3 * t] == g.corners[3 * t + 2]; };
    size_t poles = 0;
    for (size_t t = 0; t < g.triangleCount(); ++t) poles += pole(t) ? 1 : 0;
    EXPECT_EQ(poles, 2u * 40u);
    ASSERT_EQ(g.uvs.size(), g.positions.size());
    for (size_t c = 0; c < g.positions.size(); ++c) {  // per vertex
        const glm::vec3 p = g.positions[c];
        EXPECT_NEAR(glm::length(p), 2.0f, 0.05f);
        EXPECT_GT(glm::dot(g.normals[c], glm::normalize(p)), 0.9f) << "vertex " << c;
        EXPECT_NEAR(glm::length(g.normals[c]), 1.0f, 1e-5f);
        EXPECT_TRUE(g.uvs[c].x >= 0.0f && g.uvs[c].x <= 1.0f && g.uvs[c].y >= 0.0f && g.uvs[c].y <= 1.0f);
    }
    for (size_t t = 0; t < g.triangleCount(); ++t) {
        if (pole(t)) continue;
        const glm::dvec3 centre = (glm::dvec3(g.position(3 * t)) + glm::dvec3(g.position(3 * t + 1)) +
                                   glm::dvec3(g.position(3 * t + 2))) / 3.0;
        EXPECT_GT(glm::dot(triangleNormal(g, t), centre), 0.0) << "triangle " << t << " winds inward";
        // A closed surface: seams and poles welded, every edge soft.
        for (int k = 0; k < 3; ++k) {
            const uint32_t n = g.neighbors[3 * t + size_t(k)];
            EXPECT_NE(n, kNoTriangle);
            EXPECT_EQ(n & kHardEdgeBit, 0u);
        }
    }
}

TEST(FrameScene, NurbsDivisionsFollowTheShapeAttributes) {
    const std::string text = std::string(kHeader) + R"(
createNode transform -n "plane";
createNode nurbsSurface -n "planeShape" -p "plane";
	setAttr ".nu" 2;
	setAttr ".nufa" 1;
	setAttr ".nv" 1;
	setAttr ".nvfa" 0.1;
createNode makeNurbPlane -n "makeNurbPlane1";
	setAttr ".u" 2;
	setAttr ".v" 3;
connectAttr "makeNurbPlane1.os" "planeShape.cr";
)" + material("m") + assign("planeShape", "mSG");
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u) << allNotes(b->frame);
    const geom::Tessellation& g = tess(b->frame.objects[0]);
    // u: 2 spans × 2 divisions; v: 3 spans × max(1, ceil(0.1)) = 1.
    EXPECT_EQ(g.triangleCount(), 2u * (2u * 2u) * (3u * 1u));
    double area = 0.0;
    for (size_t t = 0; t < g.triangleCount(); ++t) area += triangleArea(g, t);
    EXPECT_NEAR(area, 1.0, 1e-6);  // the default plane is 1 × 1
    std::vector<uint32_t> patches(g.face.begin(), g.face.end());
    std::sort(patches.begin(), patches.end());
    patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
    EXPECT_EQ(patches.size(), 6u);
}

// ------------------------------------------------------------------ lights

constexpr const char* kLitCube = R"(
createNode transform -n "pCube1";
createNode mesh -n "pCube1Shape" -p "pCube1";
createNode polyCube -n "pCube1Creator";
connectAttr "pCube1Creator.out" "pCube1Shape.i";
connectAttr "pCube1Shape.iog" ":initialShadingGroup.dsm" -na;
)";

TEST(FrameScene, LightsAreReadWithEveryAttribute) {
    const std::string text = std::string(kHeader) + kLitCube + R"(
createNode transform -n "spot";
	setAttr ".t" -type "double3" 1 5 2 ;
	setAttr ".r" -type "double3" -90 0 0 ;
createNode spotLight -n "spotShape" -p "spot";
	setAttr ".cl" -type "float3" 1 0.5 0.25 ;
	setAttr ".in" 2;
	setAttr ".de" 2;
	setAttr ".ca" 30;
	setAttr ".pa" -5;
	setAttr ".dro" 3;
	setAttr ".edi" no;
createNode transform -n "amb";
createNode ambientLight -n "ambShape" -p "amb";
	setAttr ".as" 0.7;
	setAttr ".in" 0.5;
createNode transform -n "sun";
	setAttr ".r" -type "double3" 0 90 0 ;
createNode directionalLight -n "sunShape" -p "sun";
	setAttr ".esp" no;
createNode transform -n "bulb";
	setAttr ".t" -type "double3" 0 0 -3 ;
createNode pointLight -n "bulbShape" -p "bulb";
	setAttr ".de" 7;
createNode transform -n "off";
	setAttr ".v" no;
createNode pointLight -n "offShape" -p "off";
createNode transform -n "dome";
createNode aiSkyDomeLight -n "domeShape" -p "dome";
)";
    auto b = build(text);
    const FrameScene& f = b->frame;
    ASSERT_EQ(f.lights.size(), 4u) << allNotes(f);
    EXPECT_FALSE(f.usesDefaultLight);
    auto light = [&](const std::string& name) -> const shade::Light* {
        for (const shade::Light& l : f.lights)
            if (l.name == name) return &l;
        return nullptr;
    };
    const shade::Light* spot = light("|spot|spotShape");
    ASSERT_NE(spot, nullptr);
    EXPECT_EQ(spot->type, shade::LightType::Spot);
    EXPECT_EQ(spot->shape, b->graph->find("spotShape"));
    EXPECT_NEAR(spot->position.x, 1.0, 1e-9);
    EXPECT_NEAR(spot->position.y, 5.0, 1e-9);
    EXPECT_NEAR(spot->position.z, 2.0, 1e-9);
    EXPECT_NEAR(spot->direction.x, 0.0, 1e-9);
    EXPECT_NEAR(spot->direction.y, -1.0, 1e-9);
    EXPECT_NEAR(spot->direction.z, 0.0, 1e-9);
    EXPECT_NEAR(spot->color.r, 2.0f, 1e-6f);
    EXPECT_NEAR(spot->color.g, 1.0f, 1e-6f);
    EXPECT_NEAR(spot->color.b, 0.5f, 1e-6f);
    EXPECT_EQ(spot->decayRate, 2);
    EXPECT_NEAR(spot->coneAngle, 30.0 * std::numbers::pi / 180.0, 1e-5);
    EXPECT_NEAR(spot->penumbraAngle, -5.0 * std::numbers::pi / 180.0, 1e-5);
    EXPECT_NEAR(spot->dropoff, 3.0f, 1e-6f);
    EXPECT_FALSE(spot->emitDiffuse);
    EXPECT_TRUE(spot->emitSpecular);

    const shade::Light* amb = light("|amb|ambShape");
    ASSERT_NE(amb, nullptr);
    EXPECT_EQ(amb->type, shade::LightType::Ambient);
    EXPECT_NEAR(amb->ambientShade, 0.7f, 1e-6f);
    EXPECT_NEAR(amb->color.r, 0.5f, 1e-6f);

    const shade::Light* sun = light("|sun|sunShape");
    ASSERT_NE(sun, nullptr);
    EXPECT_EQ(sun->type, shade::LightType::Directional);
    EXPECT_NEAR(sun->direction.x, -1.0, 1e-9);  // −Z turned 90° about +Y
    EXPECT_NEAR(sun->direction.z, 0.0, 1e-9);
    EXPECT_TRUE(sun->emitDiffuse);
    EXPECT_FALSE(sun->emitSpecular);

    const shade::Light* bulb = light("|bulb|bulbShape");
    ASSERT_NE(bulb, nullptr);
    EXPECT_EQ(bulb->type, shade::LightType::Point);
    EXPECT_NEAR(bulb->position.z, -3.0, 1e-9);
    EXPECT_EQ(bulb->decayRate, 0);
    EXPECT_TRUE(hasNote(f, "|bulb|bulbShape: decayRate 7 out of range")) << allNotes(f);

    EXPECT_TRUE(hasNote(f, "|off|offShape: light hidden")) << allNotes(f);
    EXPECT_TRUE(hasNote(f, "|dome|domeShape: light type aiSkyDomeLight is not supported")) << allNotes(f);
    // No links in the scene: every light lights the cube.
    ASSERT_EQ(f.objects.size(), 1u);
    EXPECT_EQ(f.objects[0].materials[0].lights, (std::vector<uint32_t>{0, 1, 2, 3}));
}

TEST(FrameScene, DefaultLightOnlyWithoutSceneLights) {
    auto b = build(std::string(kHeader) + kLitCube);
    EXPECT_TRUE(b->frame.usesDefaultLight);
    EXPECT_TRUE(b->frame.lights.empty());
    RenderSettings noDefault;
    noDefault.enableDefaultLight = false;
    b = build(std::string(kHeader) + kLitCube, noDefault);
    EXPECT_FALSE(b->frame.usesDefaultLight);
    b = build(std::string(kHeader) + kLitCube + "createNode transform -n \"l\";\ncreateNode pointLight -n \"lShape\" -p \"l\";\n");
    EXPECT_FALSE(b->frame.usesDefaultLight);
    EXPECT_EQ(b->frame.lights.size(), 1u);
}

TEST(FrameScene, LightLinkingHonoursLinksAndIgnores) {
    // key lights every shading group through defaultLightSet; rim is linked to pCube2 only and
    // explicitly ignored by pCube1; fill is in no set and no link.
    const std::string text = std::string(kHeader) + cube("pCube1") + cube("pCube2") + material("a") + material("b") +
                             assign("pCube1Shape", "aSG") + assign("pCube2Shape", "bSG") + R"(
createNode transform -n "key";
createNode pointLight -n "keyShape" -p "key";
createNode transform -n "rim";
createNode pointLight -n "rimShape" -p "rim";
createNode transform -n "fill";
createNode pointLight -n "fillShape" -p "fill";
connectAttr "key.iog" ":defaultLightSet.dsm" -na;
connectAttr "rim.iog" ":defaultLightSet.dsm" -na;
relationship "link" ":lightLinker1" "aSG.message" "key.message";
relationship "link" ":lightLinker1" "pCube2.message" ":defaultLightSet.message";
relationship "ignore" ":lightLinker1" "pCube1Shape.message" "rim.message";
relationship "link" ":lightLinker1" "aSG.message" "rimShape.message";
)";
    auto b = build(text);
    const FrameScene& f = b->frame;
    ASSERT_EQ(f.lights.size(), 3u);
    auto lightIndex = [&](const std::string& name) {
        for (size_t l = 0; l < f.lights.size(); ++l)
            if (f.lights[l].name == name) return uint32_t(l);
        return uint32_t(~0u);
    };
    const uint32_t key = lightIndex("|key|keyShape"), rim = lightIndex("|rim|rimShape");
    const RenderObject* c1 = findObject(f, "|pCube1|pCube1Shape");
    const RenderObject* c2 = findObject(f, "|pCube2|pCube2Shape");
    ASSERT_TRUE(c1 && c2);
    EXPECT_EQ(c1->materials[0].lights, std::vector<uint32_t>{key});  // rim linked via aSG but ignored
    std::vector<uint32_t> expected{key, rim};
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(c2->materials[0].lights, expected);  // through its transform and defaultLightSet
}

TEST(FrameScene, LightLinkerConnectionsLinkAsWell) {
    const std::string text = std::string(kHeader) + cube("pCube1") + material("a") + assign("pCube1Shape", "aSG") + R"(
createNode transform -n "key";
createNode pointLight -n "keyShape" -p "key";
createNode transform -n "other";
createNode pointLight -n "otherShape" -p "other";
connectAttr "key.iog" ":defaultLightSet.dsm" -na;
connectAttr ":defaultLightSet.msg" "lightLinker1.lnk[0].llnk";
connectAttr "aSG.msg" "lightLinker1.lnk[0].olnk";
)";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u);
    ASSERT_EQ(b->frame.lights.size(), 2u);
    ASSERT_EQ(b->frame.objects[0].materials[0].lights.size(), 1u);
    EXPECT_EQ(b->frame.lights[b->frame.objects[0].materials[0].lights[0]].name, "|key|keyShape");
}

TEST(FrameScene, IgnoreWithoutAnyLinkStillUnlinks) {
    const std::string text = std::string(kHeader) + cube("pCube1") + material("a") + assign("pCube1Shape", "aSG") + R"(
createNode transform -n "key";
createNode pointLight -n "keyShape" -p "key";
createNode transform -n "rim";
createNode pointLight -n "rimShape" -p "rim";
relationship "ignore" ":lightLinker1" "pCube1.message" "rim.message";
)";
    auto b = build(text);
    ASSERT_EQ(b->frame.objects.size(), 1u);
    ASSERT_EQ(b->frame.lights.size(), 2u);
    const std::vector<uint32_t>& lit = b->frame.objects[0].materials[0].lights;
    ASSERT_EQ(lit.size(), 1u);
    EXPECT_EQ(b->frame.lights[lit[0]].name, "|key|keyShape");
}

TEST(FrameScene, ObjectGroupWithoutComponentsIsNoted) {
    const std::string text = std::string(kHeader) + cube("pCube1") + material("a") +
                             "connectAttr \"pCube1Shape.iog.og[0]\" \"aSG.dsm\" -na;\n";
    auto b = build(text);
    EXPECT_TRUE(b->frame.objects.empty());
    EXPECT_EQ(b->frame.skippedShapes, 1u);
    EXPECT_TRUE(hasNote(b->frame, "|pCube1|pCube1Shape: objectGroups[0] in aSG lists no components")) << allNotes(b->frame);
    EXPECT_TRUE(hasNote(b->frame, "|pCube1|pCube1Shape: no face belongs to a shading group")) << allNotes(b->frame);
    EXPECT_TRUE(b->frame.shadingGroups.empty());  // nothing rendered with it: not compiled
}

// ------------------------------------------------------------------ corpus

TEST(FrameScene, CorpusScenesBuildWithoutThrowing) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    size_t objects = 0;
    for (const auto& path : test::maCorpusFiles()) {
        SCOPED_TRACE(path.filename().string());
        std::unique_ptr<scene::Graph> graph;
        try {
            graph = std::make_unique<scene::Graph>(scene::MaReader::readFile(path));
        } catch (const Error&) {
            continue;  // the reader's own tests cover files it rejects
        }
        scene::Evaluator ev(*graph, 1.0);
        const scene::RenderSetup setup = scene::extractRenderSetup(*graph);
        FrameScene f;
        ASSERT_NO_THROW(f = buildFrameScene(ev, setup, RenderSettings{}));
        objects += f.objects.size();
        for (const RenderObject& o : f.objects) {
            const geom::Tessellation& g = tess(o);
            ASSERT_EQ(g.corners.size(), 3 * g.triangleCount());
            for (uint32_t v : g.corners) ASSERT_LT(v, g.vertexCount());
            // The handle's count bounds the tessellation's (ear clipping gives up on a few real
            // faces; NURBS poles drop triangles).
            ASSERT_LE(g.triangleCount(), o.geometry->triangleCount()) << o.name;
            ASSERT_EQ(g.normals.size(), g.positions.size());
            ASSERT_TRUE(g.uvs.empty() || g.uvs.size() == g.positions.size());
            ASSERT_EQ(g.material.size(), g.triangleCount());
            ASSERT_EQ(g.neighbors.size(), 3 * g.triangleCount());
            for (uint16_t m : g.material) ASSERT_LT(m, o.materials.size());
            for (const MaterialSlot& s : o.materials) {
                ASSERT_LT(s.shadingGroup, f.shadingGroups.size());
                for (uint32_t l : s.lights) ASSERT_LT(l, f.lights.size());
            }
            for (uint32_t n : g.neighbors)
                if (n != kNoTriangle) {
                    ASSERT_LT(n & ~kHardEdgeBit, g.triangleCount());
                }
            for (const glm::vec3& p : g.positions) ASSERT_TRUE(std::isfinite(p.x + p.y + p.z));
        }
    }
    EXPECT_GT(objects, 0u);
}

TEST(FrameScene, CorpusFaceMaterialsSceneUsesFourGroups) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const auto path = test::maCorpusDir() / "appleseedhq__appleseed-maya__face_materials.ma";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing " << path;
    const scene::Graph graph = scene::MaReader::readFile(path);
    scene::Evaluator ev(graph, 1.0);
    const FrameScene f = buildFrameScene(ev, scene::extractRenderSetup(graph), RenderSettings{});
    const RenderObject* o = findObject(f, "|pCylinder1|pCylinderShape1");
    ASSERT_NE(o, nullptr) << allNotes(f);
    EXPECT_EQ(o->materials.size(), 4u);
    for (size_t t = 0; t < tess(*o).triangleCount(); ++t) {
        const uint32_t face = tess(*o).face[t];
        const std::string sg = groupOf(f, *o, t);
        std::string expected;
        if (face == 4 || face == 6 || face == 8) expected = "initialShadingGroup";
        else if (face == 22 || face == 25 || face == 39) expected = "lambert4SG";
        else if (face <= 3) expected = "lambert3SG";
        else if (face == 20 || face == 21) expected = "lambert2SG";
        else continue;
        EXPECT_EQ(sg, expected) << "face " << face;
    }
}

}  // namespace
}  // namespace pushpin::render
