// Tests for core/scene/deformer_eval.h: tweak, cluster, nonLinear and skinCluster deformation
// against results worked out by hand from the formulas the header documents.
#include "core/scene/deformer_eval.h"

#include "core/scene/ma_reader.h"
#include "core/scene/mesh_eval.h"

#include "tests/support/ma_corpus.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>

namespace pushpin::scene {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr const char* kHeader = "//Maya ASCII 2018 scene\ncurrentUnit -l centimeter -a degree -t film;\n";

geom::Mesh pointMesh(std::vector<glm::vec3> points) {
    geom::Mesh m;
    m.points = std::move(points);
    return m;
}

Graph read(const std::string& body) { return MaReader::readString(std::string(kHeader) + body, "test.ma"); }

NodeId node(const Graph& g, std::string_view name) {
    const NodeId id = g.find(name);
    EXPECT_NE(id, kNoNode) << name;
    return id;
}

// Applies `deformer` to `mesh` at frame 1 and expects success.
void deform(const Graph& g, std::string_view deformer, geom::Mesh& mesh, const std::vector<bool>* members = nullptr,
            std::vector<std::string>* notesOut = nullptr) {
    Evaluator ev(g, 1.0);
    std::vector<std::string> notes;
    const std::string reason = applyDeformer(ev, node(g, deformer), 0, members, mesh, notes);
    EXPECT_EQ(reason, "");
    if (notesOut) *notesOut = notes;
}

// The reason applyDeformer gives (empty on success).
std::string failure(const Graph& g, std::string_view deformer, geom::Mesh& mesh) {
    Evaluator ev(g, 1.0);
    std::vector<std::string> notes;
    return applyDeformer(ev, node(g, deformer), 0, nullptr, mesh, notes);
}

void expectNear(const glm::vec3& got, const glm::dvec3& want, double tolerance = 1e-5) {
    EXPECT_NEAR(got.x, want.x, tolerance) << "x";
    EXPECT_NEAR(got.y, want.y, tolerance) << "y";
    EXPECT_NEAR(got.z, want.z, tolerance) << "z";
}

// Stores `values` (a tuple when there are several) without going through the .ma reader, so that
// NaN and Inf reach the Graph.
void setNumbers(Graph& g, std::string_view nodeName, std::string_view attr, std::vector<double> values) {
    Numbers n;
    n.kind = values.size() > 1 ? Numbers::Kind::Tuple : Numbers::Kind::Plain;
    n.tupleSize = int(values.size());
    n.values = std::move(values);
    g.setValue(g.find(nodeName), *parsePlugPath(attr), n);
}

// ----------------------------------------------------------------------------- nonLinear
// A flare handle and its nonLinear node; `handleXform` is the handle transform's setAttr lines.
std::string flareScene(const std::string& handleXform, const std::string& params) {
    return "createNode transform -n \"flareHandle\";\n" + handleXform +
           "createNode deformFlare -n \"flareHandleShape\" -p \"flareHandle\";\n"
           "createNode nonLinear -n \"flare1\";\n"
           "\taddAttr -is true -ci true -k true -sn \"sfx\" -ln \"startFlareX\" -dv 1 -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"sfz\" -ln \"startFlareZ\" -dv 1 -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"efx\" -ln \"endFlareX\" -dv 1 -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"efz\" -ln \"endFlareZ\" -dv 1 -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"crv\" -ln \"curve\" -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"lb\" -ln \"lowBound\" -dv -1 -at \"double\";\n"
           "\taddAttr -is true -ci true -k true -sn \"hb\" -ln \"highBound\" -dv 1 -at \"double\";\n" +
           params +
           "connectAttr \"flareHandleShape.dd\" \"flare1.dd\";\n"
           "connectAttr \"flareHandle.wm\" \"flare1.ma\";\n";
}

const char* kFlareParams = "\tsetAttr -k on \".sfx\" 2;\n\tsetAttr -k on \".efx\" 0.5;\n\tsetAttr -k on \".efz\" 3;\n";

TEST(DeformerFlare, ScalesAPointByTheHandFormula) {
    const Graph g = read(flareScene("", kFlareParams));
    // t = (0.5 − (−1)) / 2 = 0.75: X scale 2 + (0.5 − 2)·0.75 = 0.875, Z scale 1 + (3 − 1)·0.75 = 2.5.
    geom::Mesh mesh = pointMesh({{1, 0.5f, 1}, {1, -3, 1}, {1, 7, -2}});
    deform(g, "flare1", mesh);
    expectNear(mesh.points[0], {0.875, 0.5, 2.5});
    // Beyond the bounds the flare of the nearer bound applies and Y is kept.
    expectNear(mesh.points[1], {2.0, -3.0, 1.0});
    expectNear(mesh.points[2], {0.5, 7.0, -6.0});
}

TEST(DeformerFlare, WorksInHandleSpace) {
    // Handle at y = 2 scaled by 2: object point (1, 3, 0) is (0.5, 0.5, 0) in handle space, t = 0.75.
    const Graph g = read(flareScene("\tsetAttr \".t\" -type \"double3\" 0 2 0 ;\n\tsetAttr \".s\" -type \"double3\" 2 2 2 ;\n",
                                    kFlareParams));
    geom::Mesh mesh = pointMesh({{1, 3, 0}});
    deform(g, "flare1", mesh);
    expectNear(mesh.points[0], {0.875, 3.0, 0.0});
}

TEST(DeformerFlare, TakesTheGeometryMatrixFromTheWorldMeshStartingTheChain) {
    // The geometry sits under a transform at y = 1: object (1, 2, 0) is world (1, 3, 0), the point
    // of the previous test; the result goes back to object space.
    const Graph g = read(flareScene("\tsetAttr \".t\" -type \"double3\" 0 2 0 ;\n\tsetAttr \".s\" -type \"double3\" 2 2 2 ;\n",
                                    kFlareParams) +
                         "createNode transform -n \"geo\";\n\tsetAttr \".t\" -type \"double3\" 0 1 0 ;\n"
                         "createNode mesh -n \"geoShapeOrig\" -p \"geo\";\n"
                         "createNode groupParts -n \"gp\";\n"
                         "connectAttr \"geoShapeOrig.w\" \"gp.ig\";\n"
                         "connectAttr \"gp.og\" \"flare1.ip[0].ig\";\n");
    geom::Mesh mesh = pointMesh({{1, 2, 0}});
    deform(g, "flare1", mesh);
    expectNear(mesh.points[0], {0.875, 2.0, 0.0});
}

TEST(DeformerFlare, ReadsTheHandleWhenTheNodeHasNoParameters) {
    const Graph g = read("createNode transform -n \"h\";\ncreateNode deformFlare -n \"hShape\" -p \"h\";\n"
                         "\tsetAttr \".sfx\" 3;\n"
                         "createNode nonLinear -n \"flare1\";\n"
                         "connectAttr \"hShape.dd\" \"flare1.dd\";\nconnectAttr \"h.wm\" \"flare1.ma\";\n");
    // t = 0 at the low bound: X scale is the start flare 3.
    geom::Mesh mesh = pointMesh({{1, -1, 1}});
    deform(g, "flare1", mesh);
    expectNear(mesh.points[0], {3.0, -1.0, 1.0});
}

TEST(DeformerBend, NinetyDegreesTurnsAUnitColumnIntoAQuarterCircle) {
    const Graph g = read("createNode transform -n \"bendHandle\";\n"
                         "createNode deformBend -n \"bendHandleShape\" -p \"bendHandle\";\n"
                         "createNode nonLinear -n \"bend1\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"cur\" -ln \"curvature\" -at \"doubleAngle\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"lb\" -ln \"lowBound\" -dv -1 -at \"double\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"hb\" -ln \"highBound\" -dv 1 -at \"double\";\n"
                         "\tsetAttr -k on \".cur\" 90;\n\tsetAttr -k on \".lb\" 0;\n"
                         "connectAttr \"bendHandleShape.dd\" \"bend1.dd\";\nconnectAttr \"bendHandle.wm\" \"bend1.ma\";\n");
    std::vector<glm::vec3> column;
    for (int k = 0; k <= 4; ++k) column.push_back({0, float(k) / 4, 0});
    column.push_back({0.1f, 1, 0.5f});  // off the axis: keeps its distance 0.1 inside the arc
    geom::Mesh mesh = pointMesh(column);
    deform(g, "bend1", mesh);
    // The column of length 1 turns by π/2: an arc of radius 2/π about (2/π, 0, 0).
    const double radius = 2.0 / kPi;
    for (int k = 0; k <= 4; ++k) {
        const double angle = kPi / 2 * k / 4;
        expectNear(mesh.points[size_t(k)], {radius - radius * std::cos(angle), radius * std::sin(angle), 0.0});
    }
    expectNear(mesh.points[4], {radius, radius, 0.0});
    expectNear(mesh.points[5], {radius, radius - 0.1, 0.5});
}

const char* kTwistScene = "createNode transform -n \"twistHandle\";\n"
                          "createNode deformTwist -n \"twistHandleShape\" -p \"twistHandle\";\n"
                          "createNode nonLinear -n \"twist1\";\n"
                          "\taddAttr -is true -ci true -k true -sn \"sa\" -ln \"startAngle\" -at \"doubleAngle\";\n"
                          "\taddAttr -is true -ci true -k true -sn \"ea\" -ln \"endAngle\" -at \"doubleAngle\";\n"
                          "\taddAttr -is true -ci true -k true -sn \"lb\" -ln \"lowBound\" -dv -1 -at \"double\";\n"
                          "\taddAttr -is true -ci true -k true -sn \"hb\" -ln \"highBound\" -dv 1 -at \"double\";\n"
                          "\tsetAttr -k on \".ea\" 90;\n"
                          "connectAttr \"twistHandleShape.dd\" \"twist1.dd\";\n"
                          "connectAttr \"twistHandle.wm\" \"twist1.ma\";\n";

TEST(DeformerTwist, RotatesAPointByTheInterpolatedAngle) {
    const Graph g = read(kTwistScene);
    // Halfway between the bounds the angle is 45°; at the high bound 90°; at the low bound 0.
    geom::Mesh mesh = pointMesh({{1, 0, 0}, {1, 1, 0}, {0, -1, 2}, {2, 0.5f, 0}});
    deform(g, "twist1", mesh);
    const double h = std::sqrt(0.5);
    expectNear(mesh.points[0], {h, 0.0, -h});
    expectNear(mesh.points[1], {0.0, 1.0, -1.0});
    expectNear(mesh.points[2], {0.0, -1.0, 2.0});
    const double a = kPi / 2 * 0.75;
    expectNear(mesh.points[3], {2 * std::cos(a), 0.5, -2 * std::sin(a)});
}

std::string squashScene(double factor) {
    return "createNode transform -n \"squashHandle\";\n"
           "createNode deformSquash -n \"squashHandleShape\" -p \"squashHandle\";\n"
           "createNode nonLinear -n \"squash1\";\n"
           "\taddAttr -is true -ci true -k true -sn \"fac\" -ln \"factor\" -at \"double\";\n"
           "\tsetAttr -k on \".fac\" " +
           std::to_string(factor) +
           ";\n"
           "connectAttr \"squashHandleShape.dd\" \"squash1.dd\";\n"
           "connectAttr \"squashHandle.wm\" \"squash1.ma\";\n";
}

TEST(DeformerSquash, ScalesHeightAndKeepsVolumeAtTheMaximumExpansion) {
    // factor −1 halves the height; at maxExpandPos (0.5: y = 0) X and Z grow by 1/√0.5.
    const Graph g = read(squashScene(-1));
    geom::Mesh mesh = pointMesh({{0, 0.8f, 0}, {1, 0, 0}, {0, 1.5f, 0}, {0, -1, 1}});
    deform(g, "squash1", mesh);
    expectNear(mesh.points[0], {0.0, 0.4, 0.0});
    expectNear(mesh.points[1], {std::sqrt(2.0), 0.0, 0.0});
    // A thin slice at the maximum expansion keeps its volume: area × height factors multiply to 1.
    const double radial = mesh.points[1].x;
    EXPECT_NEAR(radial * radial * 0.5, 1.0, 1e-5);
    // Beyond the high bound the shape moves with the bound (1 → 0.5) and is not widened.
    expectNear(mesh.points[2], {0.0, 1.0, 0.0});
    // At the low bound the profile is 0: no widening.
    expectNear(mesh.points[3], {0.0, -0.5, 1.0});

    const Graph stretch = read(squashScene(1));
    geom::Mesh column = pointMesh({{0, 0.5f, 0}, {1, 0, 0}});
    deform(stretch, "squash1", column);
    expectNear(column.points[0], {0.0, 1.0, 0.0});
    expectNear(column.points[1], {std::sqrt(0.5), 0.0, 0.0});
}

TEST(DeformerSine, DisplacesXAlongTheWave) {
    const Graph g = read("createNode transform -n \"h\";\ncreateNode deformSine -n \"hShape\" -p \"h\";\n"
                         "createNode nonLinear -n \"sine1\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"amp\" -ln \"amplitude\" -at \"double\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"wav\" -ln \"wavelength\" -dv 2 -at \"double\";\n"
                         "\tsetAttr -k on \".amp\" 0.5;\n"
                         "connectAttr \"hShape.dd\" \"sine1.dd\";\nconnectAttr \"h.wm\" \"sine1.ma\";\n");
    // Wavelength 2: a quarter wave at y = 0.5 gives the full amplitude.
    geom::Mesh mesh = pointMesh({{0, 0.5f, 0}, {1, 0, 0}});
    deform(g, "sine1", mesh);
    expectNear(mesh.points[0], {0.5, 0.5, 0.0});
    expectNear(mesh.points[1], {1.0, 0.0, 0.0});
}

TEST(DeformerWave, DisplacesYByDistanceFromTheAxis) {
    const Graph g = read("createNode transform -n \"h\";\ncreateNode deformWave -n \"hShape\" -p \"h\";\n"
                         "createNode nonLinear -n \"wave1\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"amp\" -ln \"amplitude\" -at \"double\";\n"
                         "\taddAttr -is true -ci true -k true -sn \"wav\" -ln \"wavelength\" -dv 1 -at \"double\";\n"
                         "\tsetAttr -k on \".amp\" 0.25;\n"
                         "connectAttr \"hShape.dd\" \"wave1.dd\";\nconnectAttr \"h.wm\" \"wave1.ma\";\n");
    // Radius 0.25 is a quarter wavelength: the full amplitude, whatever the direction.
    geom::Mesh mesh = pointMesh({{0.25f, 0, 0}, {0, 1, 0.25f}});
    deform(g, "wave1", mesh);
    expectNear(mesh.points[0], {0.25, 0.25, 0.0});
    expectNear(mesh.points[1], {0.0, 1.25, 0.25});
}

TEST(DeformerNonLinear, HonoursWeightsAndMembers) {
    const Graph g = read(flareScene("", kFlareParams + std::string("\tsetAttr \".wl[0].w[1]\" 0.5;\n")));
    geom::Mesh mesh = pointMesh({{1, 0.5f, 1}, {1, 0.5f, 1}, {1, 0.5f, 1}});
    const std::vector<bool> members{true, true, false};
    deform(g, "flare1", mesh, &members);
    expectNear(mesh.points[0], {0.875, 0.5, 2.5});
    expectNear(mesh.points[1], {(1 + 0.875) / 2, 0.5, (1 + 2.5) / 2});
    expectNear(mesh.points[2], {1.0, 0.5, 1.0});
}

TEST(DeformerNonLinear, WithoutAHandleGivesAReason) {
    const Graph g = read("createNode nonLinear -n \"lonely\";\n");
    geom::Mesh mesh = pointMesh({{1, 2, 3}});
    EXPECT_NE(failure(g, "lonely", mesh).find("handle"), std::string::npos);
    expectNear(mesh.points[0], {1, 2, 3});
}

// ------------------------------------------------------------------------------- tweak
TEST(DeformerTweak, AddsOffsetsFromBothLists) {
    const Graph g = read("createNode tweak -n \"tweak1\";\n"
                         "\tsetAttr -s 2 \".pl[0].cp\";\n"
                         "\tsetAttr \".pl[0].cp[1]\" -type \"double3\" 0 0.5 0 ;\n"
                         "\tsetAttr \".pl[0].cp[3]\" -type \"double3\" 1 1 1 ;\n"
                         "\tsetAttr \".vl[0].vt[2]\" -type \"float3\" 1 0 0 ;\n");
    geom::Mesh mesh = pointMesh({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
    std::vector<std::string> notes;
    deform(g, "tweak1", mesh, nullptr, &notes);
    expectNear(mesh.points[0], {0, 0, 0});
    expectNear(mesh.points[1], {1, 1.5, 1});
    expectNear(mesh.points[2], {3, 2, 2});
    // The offset for a point that does not exist is reported, not applied.
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("ignored"), std::string::npos) << notes[0];
}

TEST(DeformerTweak, EnvelopeScalesAndAbsoluteTweaksReplace) {
    const Graph g = read("createNode tweak -n \"half\";\n\tsetAttr \".en\" 0.5;\n"
                         "\tsetAttr \".pl[0].cp[0]\" -type \"double3\" 2 0 0 ;\n"
                         "createNode tweak -n \"absolute\";\n\tsetAttr \".rtw\" no;\n"
                         "\tsetAttr \".pl[0].cp[0]\" -type \"double3\" 5 6 7 ;\n");
    geom::Mesh mesh = pointMesh({{1, 1, 1}, {1, 1, 1}});
    deform(g, "half", mesh);
    expectNear(mesh.points[0], {2, 1, 1});
    deform(g, "absolute", mesh);
    expectNear(mesh.points[0], {5, 6, 7});
    expectNear(mesh.points[1], {1, 1, 1});
}

// ----------------------------------------------------------------------------- cluster
TEST(DeformerCluster, HalfWeightMovesHalfway) {
    const Graph g = read("createNode transform -n \"clusterHandle1\";\n\tsetAttr \".t\" -type \"double3\" 2 0 0 ;\n"
                         "createNode clusterHandle -n \"clusterHandleShape1\" -p \"clusterHandle1\";\n"
                         "createNode cluster -n \"cluster1\";\n"
                         "\tsetAttr \".wl[0].w[0]\" 0.5;\n"
                         "connectAttr \"clusterHandle1.wm\" \"cluster1.ma\";\n");
    geom::Mesh mesh = pointMesh({{0, 0, 0}, {0, 1, 0}});
    deform(g, "cluster1", mesh);
    expectNear(mesh.points[0], {1, 0, 0});
    expectNear(mesh.points[1], {2, 1, 0});  // weight 1 by default
}

TEST(DeformerCluster, RelativeUsesOnlyTheHandlesOwnTransformInItsParentsSpace) {
    // The parent is rotated 90° about Z and moved far away; relative mode ignores the move and
    // takes the handle's tx = 1 along the parent's X axis, which is world +Y.
    const Graph g = read("createNode transform -n \"parent\";\n"
                         "\tsetAttr \".t\" -type \"double3\" 10 20 30 ;\n\tsetAttr \".r\" -type \"double3\" 0 0 90 ;\n"
                         "createNode transform -n \"handle\" -p \"parent\";\n\tsetAttr \".t\" -type \"double3\" 1 0 0 ;\n"
                         "createNode cluster -n \"cluster1\";\n\tsetAttr \".rel\" yes;\n"
                         "\tsetAttr \".gm[0]\" -type \"matrix\" 1 0 0 0 0 1 0 0 0 0 1 0 0 0 5 1;\n"
                         "connectAttr \"handle.wm\" \"cluster1.ma\";\n");
    geom::Mesh mesh = pointMesh({{3, 0, 0}});
    deform(g, "cluster1", mesh);
    expectNear(mesh.points[0], {3, 1, 0});
}

TEST(DeformerCluster, AbsoluteModeUndoesTheBindPreMatrixInWorldSpace) {
    // Bound with the handle at x = 1 (bindPreMatrix moves by −1), now at x = 4; the geometry is
    // rotated 90° about Z in world, so a world +X motion of 3 is object −Y.
    const Graph g = read("createNode transform -n \"handle\";\n\tsetAttr \".t\" -type \"double3\" 4 0 0 ;\n"
                         "createNode cluster -n \"cluster1\";\n"
                         "\tsetAttr \".pm\" -type \"matrix\" 1 0 0 0 0 1 0 0 0 0 1 0 -1 0 0 1;\n"
                         "\tsetAttr \".gm[0]\" -type \"matrix\" 0 1 0 0 -1 0 0 0 0 0 1 0 0 0 0 1;\n"
                         "connectAttr \"handle.wm\" \"cluster1.ma\";\n");
    geom::Mesh mesh = pointMesh({{1, 1, 1}});
    deform(g, "cluster1", mesh);
    expectNear(mesh.points[0], {1, -2, 1});
}

// ------------------------------------------------------------------------- skinCluster
// Two joints, bound at the origin and at y = 1; joint2 has since moved up by 2 (and rotates by
// `rz2` degrees about Z).
std::string skinScene(const std::string& weights, const std::string& extra = "", double rz2 = 0) {
    return "createNode joint -n \"joint1\";\n"
           "createNode joint -n \"joint2\";\n\tsetAttr \".t\" -type \"double3\" 0 3 0 ;\n"
           "\tsetAttr \".r\" -type \"double3\" 0 0 " +
           std::to_string(rz2) +
           " ;\n"
           "createNode skinCluster -n \"skin1\";\n" +
           weights +
           "\tsetAttr \".pm[1]\" -type \"matrix\" 1 0 0 0 0 1 0 0 0 0 1 0 0 -1 0 1;\n" + extra +
           "connectAttr \"joint1.wm\" \"skin1.ma[0]\";\nconnectAttr \"joint2.wm\" \"skin1.ma[1]\";\n";
}

TEST(DeformerSkin, FiftyFiftyWeightsMoveToTheAverage) {
    const Graph g = read(skinScene("\tsetAttr \".wl[0].w[0]\" 0.5;\n\tsetAttr \".wl[0].w[1]\" 0.5;\n"
                                   "\tsetAttr \".wl[1].w[1]\" 1;\n"));
    geom::Mesh mesh = pointMesh({{1, 0, 0}, {0, 1, 0}, {7, 7, 7}});
    std::vector<std::string> notes;
    deform(g, "skin1", mesh, nullptr, &notes);
    expectNear(mesh.points[0], {1, 1, 0});  // joint1 leaves it, joint2 moves it by 2: average +1
    expectNear(mesh.points[1], {0, 3, 0});
    expectNear(mesh.points[2], {7, 7, 7});  // no weights: left in place, with a note
    ASSERT_FALSE(notes.empty());
    EXPECT_NE(notes.back().find("without skin weights"), std::string::npos) << notes.back();
}

TEST(DeformerSkin, PostNormalizationDividesByTheSum) {
    const Graph g = read(skinScene("\tsetAttr \".wl[0].w[0]\" 0.25;\n\tsetAttr \".wl[0].w[1]\" 0.25;\n",
                                   "\tsetAttr \".nw\" 2;\n"));
    geom::Mesh mesh = pointMesh({{1, 0, 0}});
    deform(g, "skin1", mesh);
    expectNear(mesh.points[0], {1, 1, 0});
}

TEST(DeformerSkin, DualQuaternionBlendsTheScrewMotion) {
    // joint2 is bound at y = 1 and now stands at y = 3 rotated 90° about Z: its motion maps
    // (x, y) to (1 − y, x + 3), a 90° rotation about its fixed point (−1, 2).
    const std::string weights = "\tsetAttr \".wl[0].w[1]\" 1;\n\tsetAttr \".wl[1].w[0]\" 0.5;\n\tsetAttr \".wl[1].w[1]\" 0.5;\n";
    const Graph linear = read(skinScene(weights, "", 90));
    const Graph dual = read(skinScene(weights, "\tsetAttr \".skm\" 1;\n", 90));
    geom::Mesh a = pointMesh({{1, 1, 0}, {1, 0, 0}});
    geom::Mesh b = a;
    deform(linear, "skin1", a);
    deform(dual, "skin1", b);
    // One rigid influence: both methods give (1 − 1, 1 + 3).
    expectNear(a.points[0], {0, 4, 0});
    expectNear(b.points[0], {0, 4, 0});
    // 50/50 with the identity: linear skinning averages (1, 0) and (1, 4); dual quaternions turn
    // by half the angle about the same fixed point: (−1, 2) + Rz45·(2, −2) = (−1 + 2√2, 2).
    expectNear(a.points[1], {1, 2, 0});
    expectNear(b.points[1], {-1 + 2 * std::sqrt(2.0), 2, 0});
}

TEST(DeformerSkin, DualQuaternionHalfRotationOfAPureRotation) {
    // joint2 bound at the origin and rotated 90° about Z in place: 50/50 with the identity is a
    // 45° rotation in dual quaternion skinning (radius kept), the chord midpoint in linear.
    const std::string scene = "createNode joint -n \"joint1\";\n"
                              "createNode joint -n \"joint2\";\n\tsetAttr \".r\" -type \"double3\" 0 0 90 ;\n"
                              "createNode skinCluster -n \"skin1\";\n"
                              "\tsetAttr \".wl[0].w[0]\" 0.5;\n\tsetAttr \".wl[0].w[1]\" 0.5;\n";
    const std::string links = "connectAttr \"joint1.wm\" \"skin1.ma[0]\";\nconnectAttr \"joint2.wm\" \"skin1.ma[1]\";\n";
    const Graph linear = read(scene + links);
    const Graph dual = read(scene + "\tsetAttr \".skm\" 1;\n" + links);
    const Graph blended = read(scene + "\tsetAttr \".skm\" 2;\n\tsetAttr \".bw[0]\" 0.5;\n" + links);
    geom::Mesh a = pointMesh({{1, 0, 0}}), b = a, c = a;
    deform(linear, "skin1", a);
    deform(dual, "skin1", b);
    deform(blended, "skin1", c);
    expectNear(a.points[0], {0.5, 0.5, 0});
    const double h = std::sqrt(0.5);
    expectNear(b.points[0], {h, h, 0});
    expectNear(c.points[0], {(0.5 + h) / 2, (0.5 + h) / 2, 0});
}

// --------------------------------------------------------------------- envelope, members
TEST(DeformerEnvelope, ZeroLeavesEveryTypeUnchanged) {
    const Graph g = read(flareScene("", kFlareParams + std::string("\tsetAttr \".en\" 0;\n")) +
                         "createNode tweak -n \"tweak1\";\n\tsetAttr \".en\" 0;\n"
                         "\tsetAttr \".pl[0].cp[0]\" -type \"double3\" 1 2 3 ;\n"
                         "createNode transform -n \"ch\";\n\tsetAttr \".t\" -type \"double3\" 5 0 0 ;\n"
                         "createNode cluster -n \"cluster1\";\n\tsetAttr \".en\" 0;\n"
                         "connectAttr \"ch.wm\" \"cluster1.ma\";\n" +
                         skinScene("\tsetAttr \".wl[0].w[1]\" 1;\n\tsetAttr \".wl[1].w[1]\" 1;\n", "\tsetAttr \".en\" 0;\n"));
    for (const char* deformer : {"flare1", "tweak1", "cluster1", "skin1"}) {
        geom::Mesh mesh = pointMesh({{1, 0.5f, 1}, {-2, 3, 4}});
        const geom::Mesh before = mesh;
        deform(g, deformer, mesh);
        for (size_t i = 0; i < mesh.points.size(); ++i) expectNear(mesh.points[i], glm::dvec3(before.points[i]), 0.0);
    }
}

TEST(DeformerMembers, OnlyTheSetsPointsMove) {
    const Graph g = read("createNode transform -n \"ch\";\n\tsetAttr \".t\" -type \"double3\" 0 0 1 ;\n"
                         "createNode cluster -n \"cluster1\";\nconnectAttr \"ch.wm\" \"cluster1.ma\";\n" +
                         skinScene("\tsetAttr \".wl[0].w[1]\" 1;\n\tsetAttr \".wl[1].w[1]\" 1;\n"));
    const std::vector<bool> members{false, true};  // shorter than the mesh: the third is outside
    for (const char* deformer : {"cluster1", "skin1"}) {
        geom::Mesh mesh = pointMesh({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}});
        deform(g, deformer, mesh, &members);
        expectNear(mesh.points[0], {0, 0, 0});
        EXPECT_GT(glm::length(glm::vec3(mesh.points[1])), 0.5f) << deformer;
        expectNear(mesh.points[2], {0, 0, 0});
    }
}

// --------------------------------------------------------------------- non-finite input
TEST(DeformerNonFinite, ParametersMatricesAndResultsGiveAReason) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    struct Case {
        const char* deformer;
        const char* node;
        const char* attr;
        std::vector<double> values;
    };
    const Case cases[] = {
        {"flare1", "flare1", "sfx", {nan}},
        {"flare1", "flare1", "en", {inf}},
        {"flare1", "flareHandle", "tx", {inf}},
        {"twist1", "twist1", "ea", {nan}},
        {"cluster1", "ch", "ty", {nan}},
        {"cluster1", "cluster1", "wl[0].w[0]", {inf}},
        {"skin1", "skin1", "wl[0].w[0]", {nan}},
        {"skin1", "joint2", "tz", {inf}},
        {"tweak1", "tweak1", "pl[0].cp[0]", {nan, 0, 0}},
        // Finite, but the result overflows: 1e10 · 1e300.
        {"flare1", "flare1", "efx", {1e300}},
    };
    for (const Case& c : cases) {
        Graph g = read(flareScene("", kFlareParams) + kTwistScene +
                       "createNode tweak -n \"tweak1\";\n"
                       "createNode transform -n \"ch\";\ncreateNode cluster -n \"cluster1\";\n"
                       "connectAttr \"ch.wm\" \"cluster1.ma\";\n" +
                       skinScene("\tsetAttr \".wl[0].w[0]\" 0.5;\n\tsetAttr \".wl[0].w[1]\" 0.5;\n"));
        geom::Mesh mesh = pointMesh({{1e10f, 1, 1}});
        const geom::Mesh before = mesh;
        EXPECT_EQ(failure(g, c.deformer, mesh), "") << "before setting " << c.node << "." << c.attr;
        mesh = before;
        setNumbers(g, c.node, c.attr, c.values);
        const std::string reason = failure(g, c.deformer, mesh);
        EXPECT_FALSE(reason.empty()) << c.node << "." << c.attr;
        EXPECT_EQ(mesh.points, before.points) << c.node << "." << c.attr;
    }
}

TEST(DeformerTypes, OnlyTheFourEvaluatedTypesAreClaimed) {
    for (const char* t : {"tweak", "cluster", "nonLinear", "skinCluster"}) EXPECT_TRUE(isEvaluatedDeformer(t)) << t;
    for (const char* t : {"lattice", "blendShape", "wire", "ffd", "polyTweak", ""}) EXPECT_FALSE(isEvaluatedDeformer(t)) << t;
    const Graph g = read("createNode blendShape -n \"bs\";\n");
    geom::Mesh mesh = pointMesh({{1, 2, 3}});
    EXPECT_NE(failure(g, "bs", mesh).find("not evaluated"), std::string::npos);
    Evaluator ev(g, 1.0);
    std::vector<std::string> notes;
    EXPECT_FALSE(applyDeformer(ev, kNoNode, 0, nullptr, mesh, notes).empty());
}

// ------------------------------------------------------------------------ a real scene
// LavaLamp's lamp glass: a polyCylinder (r 1, h 2.5) under a transform at y = 0.437, through
// tweak1 and flare1, whose handle sits at the same height scaled by 2.25. In handle space the
// cylinder spans y = ±1.25 / 2.25, so t = (±0.5556 + 1) / 2 and the radius at the bottom is
// 1.2396 + (0.4958 − 1.2396)·0.2222 = 1.0743, at the top 1.2396 − 0.7438·0.7778 = 0.6611.
TEST(DeformerCorpus, LavaLampFlareTapersTheCylinder) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const std::filesystem::path file = test::maCorpusDir() / "tws0002__pop2-project__LavaLamp.ma";
    ASSERT_TRUE(std::filesystem::exists(file)) << file;
    const Graph g = MaReader::readFile(file);
    Evaluator ev(g, 1.0);
    std::string why;
    std::optional<geom::Mesh> mesh = evaluateMesh(ev, g.find("pCylinderShape1Orig"), &why);
    ASSERT_TRUE(mesh) << why;
    // pCylinderShape1Orig is evaluated from polyCylinder1 in its object space.
    std::vector<std::string> notes;
    ASSERT_EQ(applyDeformer(ev, g.find("tweak1"), 0, nullptr, *mesh, notes), "");
    ASSERT_EQ(applyDeformer(ev, g.find("flare1"), 0, nullptr, *mesh, notes), "");
    double bottom = 0, top = 0;
    for (const glm::vec3& p : mesh->points) {
        const double r = std::hypot(p.x, p.z);
        if (std::abs(p.y + 1.25) < 1e-4) bottom = std::max(bottom, r);
        if (std::abs(p.y - 1.25) < 1e-4) top = std::max(top, r);
    }
    const double tBottom = (-1.25 / 2.25 + 1) / 2, tTop = (1.25 / 2.25 + 1) / 2;
    EXPECT_NEAR(bottom, 1.2396 + (0.4958 - 1.2396) * tBottom, 1e-4);
    EXPECT_NEAR(top, 1.2396 + (0.4958 - 1.2396) * tTop, 1e-4);
}

}  // namespace
}  // namespace pushpin::scene
