// Tests for core/scene/evaluator.h on graphs built directly through the Graph API (values in
// internal units, as the .ma reader stores them, except animCurve keys, which keep the file's units).
#include "core/scene/evaluator.h"

#include "core/scene/ma_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

namespace pushpin::scene {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

void set(Graph& g, NodeId n, const char* path, std::vector<double> v, Numbers::Kind kind = Numbers::Kind::Plain) {
    auto segs = parsePlugPath(path);
    ASSERT_TRUE(segs.has_value()) << path;
    const int width = kind == Numbers::Kind::Tuple ? int(v.size()) : 1;
    g.setValue(n, *segs, Numbers{kind, width, std::move(v)});
}

void set3(Graph& g, NodeId n, const char* path, double x, double y, double z) {
    set(g, n, path, {x, y, z}, Numbers::Kind::Tuple);
}

void link(Graph& g, NodeId src, const char* srcPlug, NodeId dst, const char* dstPlug) {
    g.connect(Plug{src, srcPlug}, Plug{dst, dstPlug});
}

// An animCurve with linear tangents through (time, value) pairs, written like `.ktv[0:n]`.
NodeId linearCurve(Graph& g, const char* type, const char* name, std::vector<double> ktv) {
    const NodeId c = g.createNode(type, name);
    const size_t n = ktv.size() / 2;
    const std::string range = "ktv[0:" + std::to_string(n - 1) + "]";
    set(g, c, range.c_str(), std::move(ktv));
    set(g, c, ("kit[0:" + std::to_string(n - 1) + "]").c_str(), std::vector<double>(n, 2.0));
    set(g, c, ("kot[0:" + std::to_string(n - 1) + "]").c_str(), std::vector<double>(n, 2.0));
    set(g, c, "wgt", {0.0});
    return c;
}

glm::dvec3 apply(const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec4 q = m * glm::dvec4(p, 1.0);
    return {q.x, q.y, q.z};
}

void expectNear(const glm::dvec3& got, const glm::dvec3& want, double tol = 1e-12) {
    EXPECT_NEAR(got.x, want.x, tol) << "x";
    EXPECT_NEAR(got.y, want.y, tol) << "y";
    EXPECT_NEAR(got.z, want.z, tol) << "z";
}

TEST(Evaluator, StaticValuesAndDefaults) {
    Graph g;
    const NodeId t = g.createNode("transform", "pCube1");
    set3(g, t, "t", 1, 2, 3);
    Evaluator e(g, 1.0);
    EXPECT_EQ(e.getDouble3(t, "translate"), glm::dvec3(1, 2, 3));
    EXPECT_DOUBLE_EQ(e.getDouble(t, "ty"), 2.0);
    EXPECT_EQ(e.getDouble3(t, "scale"), glm::dvec3(1, 1, 1));
    EXPECT_TRUE(e.getBool(t, "visibility"));
    std::vector<double> out;
    EXPECT_FALSE(e.numbers(t, "noSuchAttribute", out));
    EXPECT_FALSE(e.numbers(t, "t[", out));
    EXPECT_FALSE(e.numbers(NodeId(g.size() + 5), "t", out));
    EXPECT_DOUBLE_EQ(e.getDouble(t, "noSuchAttribute", -7.0), -7.0);
}

TEST(Evaluator, ParentRotationCarriesChildTranslation) {
    Graph g;
    const NodeId parent = g.createNode("transform", "parent");
    const NodeId child = g.createNode("transform", "child", parent);
    set3(g, parent, "t", 1, 0, 0);
    set3(g, parent, "r", 0, 0, 90 * kDeg);
    set3(g, child, "t", 0, 2, 0);
    Evaluator e(g, 1.0);
    // The child's (0,2,0) turns to (−2,0,0) under the parent's z 90°, then moves by (1,0,0).
    expectNear(apply(e.worldMatrix({parent, child}), {0, 0, 0}), {-1, 0, 0});
    expectNear(apply(e.localMatrix(child), {0, 0, 0}), {0, 2, 0});
    expectNear(apply(e.worldMatrix({}), {3, 4, 5}), {3, 4, 5});
}

TEST(Evaluator, InheritsTransformOffIgnoresParents) {
    Graph g;
    const NodeId parent = g.createNode("transform", "parent");
    const NodeId child = g.createNode("transform", "child", parent);
    const NodeId grandchild = g.createNode("transform", "grandchild", child);
    set3(g, parent, "t", 10, 0, 0);
    set3(g, child, "t", 0, 1, 0);
    set3(g, grandchild, "t", 0, 0, 1);
    set(g, child, "it", {0.0});
    Evaluator e(g, 1.0);
    expectNear(apply(e.worldMatrix({parent, child}), {0, 0, 0}), {0, 1, 0});
    // Descendants of a non-inheriting node still follow it.
    expectNear(apply(e.worldMatrix({parent, child, grandchild}), {0, 0, 0}), {0, 1, 1});
}

TEST(Evaluator, InstancedPathsHaveTheirOwnWorldMatrices) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    const NodeId shape = g.createNode("mesh", "shape", a);
    g.setParent(shape, b, true);
    set3(g, a, "t", 5, 0, 0);
    set3(g, b, "s", 2, 2, 2);
    set3(g, b, "t", 0, -1, 0);
    Evaluator e(g, 1.0);
    const auto paths = g.dagPaths(shape);
    ASSERT_EQ(paths.size(), 2u);
    std::vector<glm::dvec3> seen;
    for (const auto& p : paths) seen.push_back(apply(e.worldMatrix(p), {1, 1, 1}));
    // Through a: (6,1,1); through b: (2,2,2) − (0,1,0) = (2,1,2).
    const bool firstIsA = paths[0][0] == a;
    expectNear(seen[firstIsA ? 0 : 1], {6, 1, 1});
    expectNear(seen[firstIsA ? 1 : 0], {2, 1, 2});
    // The shape itself adds nothing: shapes live in their parent transform's space.
    expectNear(apply(e.localMatrix(shape), {1, 2, 3}), {1, 2, 3});
}

TEST(Evaluator, JointChainCompensatesParentScale) {
    Graph g;
    const NodeId j1 = g.createNode("joint", "joint1");
    const NodeId j2 = g.createNode("joint", "joint2", j1);
    set3(g, j1, "s", 2, 2, 2);
    set3(g, j2, "t", 1, 0, 0);
    {
        Evaluator e(g, 1.0);
        // (1,0,0) in joint2: ·IS (½) → (0.5,0,0), +T → (1.5,0,0), ·joint1 scale 2 → (3,0,0).
        expectNear(apply(e.worldMatrix({j1, j2}), {1, 0, 0}), {3, 0, 0});
    }
    link(g, j1, "s", j2, "is");  // what Maya writes for parented joints: same result
    {
        Evaluator e(g, 1.0);
        expectNear(apply(e.worldMatrix({j1, j2}), {1, 0, 0}), {3, 0, 0});
    }
    set(g, j2, "ssc", {0.0});
    {
        Evaluator e(g, 1.0);
        expectNear(apply(e.worldMatrix({j1, j2}), {1, 0, 0}), {4, 0, 0});
    }
}

TEST(Evaluator, JointOrientInWorldMatrix) {
    Graph g;
    const NodeId j = g.createNode("joint", "joint1");
    set3(g, j, "jo", 0, 0, 90 * kDeg);
    set3(g, j, "t", 0, 0, 3);
    Evaluator e(g, 1.0);
    expectNear(apply(e.worldMatrix({j}), {1, 0, 0}), {0, 1, 3});
}

TEST(Evaluator, AnimatedTranslateThroughAnimCurveTL) {
    Graph g;
    const NodeId t = g.createNode("transform", "pCube1");
    set3(g, t, "t", 0, 7, 0);
    const NodeId c = linearCurve(g, "animCurveTL", "pCube1_translateX", {1, 0, 11, 10});
    link(g, c, "o", t, "tx");
    struct {
        double frame, x;
    } cases[] = {{1, 0}, {6, 5}, {11, 10}, {3.5, 2.5}, {0, 0}, {20, 10}};
    for (auto [frame, x] : cases) {
        Evaluator e(g, frame);
        EXPECT_NEAR(e.getDouble(t, "tx"), x, 1e-12) << frame;
        expectNear(e.getDouble3(t, "translate"), {x, 7, 0});
        expectNear(apply(e.worldMatrix({t}), {0, 0, 0}), {x, 7, 0});
    }
}

TEST(Evaluator, AnimCurveKeysAreConvertedFromFileUnits) {
    Graph g;
    g.units.cmPerLinearUnit = 100.0;  // currentUnit -l meter
    const NodeId t = g.createNode("transform", "t");
    link(g, linearCurve(g, "animCurveTL", "tx", {0, 0, 10, 2}), "o", t, "tx");
    link(g, linearCurve(g, "animCurveTA", "rz", {0, 0, 10, 180}), "o", t, "rz");  // degrees
    link(g, linearCurve(g, "animCurveTU", "sx", {0, 1, 10, 3}), "o", t, "sx");    // unitless
    Evaluator e(g, 5.0);
    EXPECT_NEAR(e.getDouble(t, "tx"), 100.0, 1e-12);  // 1 m
    EXPECT_NEAR(e.getDouble(t, "rz"), 90 * kDeg, 1e-12);
    EXPECT_NEAR(e.getDouble(t, "sx"), 2.0, 1e-12);
    // scale 2 on x, then z 90° takes (1,0,0) → (2,0,0) → (0,2,0), then +100 cm on x.
    expectNear(apply(e.worldMatrix({t}), {1, 0, 0}), {100, 2, 0}, 1e-9);
}

TEST(Evaluator, FixedTangentsAreInSecondsAndInternalUnits) {
    Graph g;  // degrees, 24 fps
    const NodeId t = g.createNode("transform", "t");
    const NodeId c = g.createNode("animCurveTA", "rx");
    set(g, c, "ktv[0:1]", {0, 0, 48, 0});
    set(g, c, "tan", {1.0});  // fixed
    set(g, c, "wgt", {0.0});
    // Out tangent of key 0: direction (1 s, π/2 rad) → slope (π/2)/24 radians per frame.
    set(g, c, "kox[0]", {1.0});
    set(g, c, "koy[0]", {kPi / 2});
    link(g, c, "o", t, "rx");
    const double h = 1e-5;
    Evaluator at0(g, 0.0), atH(g, h);
    EXPECT_NEAR((atH.getDouble(t, "rx") - at0.getDouble(t, "rx")) / h, kPi / 2 / 24.0, 1e-5);
}

TEST(Evaluator, StepTangentsOnAnimatedVisibility) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId c = g.createNode("animCurveTU", "t_visibility");
    set(g, c, "tan", {9.0});
    set(g, c, "wgt", {0.0});
    set(g, c, "ktv[0:2]", {1, 1, 5, 0, 9, 1});
    set(g, c, "kot[0:2]", {5, 5, 5});
    link(g, c, "o", t, "v");
    EXPECT_TRUE(Evaluator(g, 4.9).visible({t}));
    EXPECT_FALSE(Evaluator(g, 5.0).visible({t}));
    EXPECT_FALSE(Evaluator(g, 8.99).visible({t}));
    EXPECT_TRUE(Evaluator(g, 9.0).visible({t}));
}

TEST(Evaluator, UnitConversionChain) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId curve = linearCurve(g, "animCurveTU", "driver", {0, 0, 10, 10});
    const NodeId uc1 = g.createNode("unitConversion", "unitConversion1");
    const NodeId uc2 = g.createNode("unitConversion", "unitConversion2");
    set(g, uc1, "cf", {2.0});
    set(g, uc2, "conversionFactor", {3.0});
    link(g, curve, "output", uc1, "input");
    link(g, uc1, "output", uc2, "i");
    link(g, uc2, "o", t, "tz");
    Evaluator e(g, 5.0);
    EXPECT_NEAR(e.getDouble(t, "tz"), 30.0, 1e-12);
    EXPECT_NEAR(e.getDouble(uc1, "output"), 10.0, 1e-12);
}

TEST(Evaluator, UnitConversionOfACompound) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    const NodeId uc = g.createNode("unitConversion", "uc");
    set3(g, a, "t", 1, 2, 3);
    set(g, uc, "cf", {0.5});
    link(g, a, "t", uc, "i");
    link(g, uc, "o", b, "r");
    Evaluator e(g, 1.0);
    expectNear(e.getDouble3(b, "rotate"), {0.5, 1.0, 1.5});
    EXPECT_NEAR(e.getDouble(b, "ry"), 1.0, 1e-15);
}

TEST(Evaluator, TimeNodeGivesTheFrame) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId time = g.find("time1");
    ASSERT_NE(time, kNoNode);
    const NodeId uc = g.createNode("unitConversion", "uc");
    set(g, uc, "cf", {0.5});
    link(g, time, "outTime", uc, "input");
    link(g, uc, "output", t, "ty");
    EXPECT_NEAR(Evaluator(g, 8.0).getDouble(t, "ty"), 4.0, 1e-12);
    EXPECT_NEAR(Evaluator(g, -3.0).getDouble(t, "ty"), -1.5, 1e-12);
}

TEST(Evaluator, TimeCurveWithConnectedInputIsRetimed) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId curve = linearCurve(g, "animCurveTL", "tx", {0, 0, 10, 10});
    const NodeId warp = g.createNode("unitConversion", "warp");
    set(g, warp, "cf", {2.0});
    link(g, g.find("time1"), "o", warp, "i");
    link(g, warp, "o", curve, "input");
    link(g, curve, "o", t, "tx");
    EXPECT_NEAR(Evaluator(g, 3.0).getDouble(t, "tx"), 6.0, 1e-12);
}

TEST(Evaluator, DrivenKeyCurveFollowsItsInput) {
    Graph g;
    const NodeId driver = g.createNode("transform", "driver");
    const NodeId driven = g.createNode("transform", "driven");
    set3(g, driver, "t", 5, 0, 0);
    const NodeId curve = linearCurve(g, "animCurveUL", "driven_ty", {0, 0, 10, 100});
    link(g, driver, "tx", curve, "i");
    link(g, curve, "o", driven, "ty");
    Evaluator e(g, 123.0);  // the frame does not matter to a driven key
    EXPECT_NEAR(e.getDouble(driven, "ty"), 50.0, 1e-12);
    // Driven angle curve: keys in degrees, output in radians.
    const NodeId rot = linearCurve(g, "animCurveUA", "driven_rz", {0, 0, 10, 90});
    link(g, driver, "tx", rot, "input");
    link(g, rot, "output", driven, "rz");
    Evaluator e2(g, 1.0);
    EXPECT_NEAR(e2.getDouble(driven, "rz"), 45 * kDeg, 1e-12);
}

TEST(Evaluator, CompoundConnectionPassesThrough) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    set3(g, a, "t", 1, 2, 3);
    link(g, linearCurve(g, "animCurveTL", "a_ty", {0, 0, 10, 20}), "o", a, "ty");
    link(g, a, "translate", b, "translate");
    Evaluator e(g, 5.0);
    expectNear(e.getDouble3(b, "t"), {1, 10, 3});
    EXPECT_NEAR(e.getDouble(b, "translateY"), 10.0, 1e-12);
    // A child fed from another node's child.
    const NodeId c = g.createNode("transform", "c");
    link(g, a, "ty", c, "tz");
    Evaluator e2(g, 5.0);
    expectNear(e2.getDouble3(c, "t"), {0, 0, 10});
}

TEST(Evaluator, ConnectionCycleTerminatesAndIsReportedOnce) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    set3(g, a, "t", 4, 0, 0);
    set3(g, b, "t", 9, 0, 0);
    link(g, a, "tx", b, "tx");
    link(g, b, "tx", a, "tx");
    Evaluator e(g, 1.0);
    // a.tx ← b.tx ← a.tx: the loop is cut at a.tx, whose stored value flows round.
    EXPECT_DOUBLE_EQ(e.getDouble(a, "tx"), 4.0);
    EXPECT_DOUBLE_EQ(e.getDouble(b, "tx"), 4.0);
    EXPECT_DOUBLE_EQ(e.getDouble(a, "tx"), 4.0);
    (void)e.worldMatrix({a});
    (void)e.worldMatrix({b});
    ASSERT_EQ(e.diagnostics().size(), 1u);
    EXPECT_NE(e.diagnostics()[0].message.find("cycle"), std::string::npos);
    EXPECT_EQ(e.diagnostics()[0].node, "a");

    // A longer loop through a unitConversion and an animCurve's input.
    Graph g2;
    const NodeId t = g2.createNode("transform", "t");
    const NodeId uc = g2.createNode("unitConversion", "uc");
    const NodeId curve = linearCurve(g2, "animCurveUL", "loop", {0, 0, 10, 10});
    link(g2, t, "tx", uc, "i");
    link(g2, uc, "o", curve, "i");
    link(g2, curve, "o", t, "tx");
    Evaluator e2(g2, 1.0);
    EXPECT_TRUE(std::isfinite(e2.getDouble(t, "tx")));
    EXPECT_FALSE(e2.diagnostics().empty());
}

TEST(Evaluator, VisibilityAlongThePath) {
    Graph g;
    const NodeId grp = g.createNode("transform", "grp");
    const NodeId t = g.createNode("transform", "t", grp);
    const NodeId shape = g.createNode("mesh", "tShape", t);
    const std::vector<NodeId> path{grp, t, shape};
    EXPECT_TRUE(Evaluator(g, 1.0).visible(path));
    EXPECT_FALSE(Evaluator(g, 1.0).visible({}));

    set(g, grp, "v", {0.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible(path));
    EXPECT_TRUE(Evaluator(g, 1.0).visible({t, shape}));
    set(g, grp, "v", {1.0});

    set(g, t, "lodv", {0.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible(path));
    set(g, t, "lodv", {1.0});

    set(g, shape, "io", {1.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible(path));
    set(g, shape, "io", {0.0});

    // overrideVisibility only counts when overrides are enabled.
    set(g, t, "ovv", {0.0});
    EXPECT_TRUE(Evaluator(g, 1.0).visible(path));
    set(g, t, "ove", {1.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible(path));
    set(g, t, "ovv", {1.0});
    EXPECT_TRUE(Evaluator(g, 1.0).visible(path));
}

TEST(Evaluator, HiddenDisplayLayerHidesItsMembers) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId layer = g.createNode("displayLayer", "layer1");
    link(g, layer, "di", t, "do");
    EXPECT_TRUE(Evaluator(g, 1.0).visible({t}));
    set(g, layer, "v", {0.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible({t}));
    set(g, layer, "e", {0.0});  // a disabled layer overrides nothing
    EXPECT_TRUE(Evaluator(g, 1.0).visible({t}));
}

// Templated objects, and the members of a template display layer, are not rendered.
TEST(Evaluator, TemplatesAreNotRendered) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    const NodeId u = g.createNode("transform", "u");
    const NodeId layer = g.createNode("displayLayer", "layer1");
    link(g, layer, "di", t, "do");
    EXPECT_TRUE(Evaluator(g, 1.0).visible({t}));
    set(g, layer, "dt", {1.0});  // template
    EXPECT_FALSE(Evaluator(g, 1.0).visible({t}));
    set(g, layer, "dt", {2.0});  // reference: drawn unselectable, still rendered
    EXPECT_TRUE(Evaluator(g, 1.0).visible({t}));
    set(g, u, "tmp", {1.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible({u}));
    set(g, u, "tmp", {0.0});
    set(g, u, "ovdt", {1.0});
    EXPECT_TRUE(Evaluator(g, 1.0).visible({u}));  // overrides only count when enabled
    set(g, u, "ove", {1.0});
    EXPECT_FALSE(Evaluator(g, 1.0).visible({u}));
}

TEST(Evaluator, OffsetParentMatrixSitsBetweenLocalAndParent) {
    Graph g;
    const NodeId parent = g.createNode("transform", "parent");
    const NodeId child = g.createNode("transform", "child", parent);
    set3(g, parent, "t", 0, 0, 1);
    set3(g, child, "t", 1, 0, 0);
    // Row-major, translation in the fourth row: z 90° then a move by (0,5,0).
    set(g, child, "offsetParentMatrix", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}, Numbers::Kind::Matrix);
    Evaluator e(g, 1.0);
    // Origin of child: (1,0,0) → opm: z 90° → (0,1,0) + (0,5,0) → (0,6,0) → parent +z → (0,6,1).
    expectNear(apply(e.worldMatrix({parent, child}), {0, 0, 0}), {0, 6, 1});
}

TEST(Evaluator, CachedValuesAreStable) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    link(g, linearCurve(g, "animCurveTL", "tx", {0, 0, 10, 10}), "o", t, "tx");
    Evaluator e(g, 2.5);
    EXPECT_EQ(e.frame(), 2.5);
    EXPECT_EQ(&e.graph(), &g);
    const double first = e.getDouble(t, "tx");
    EXPECT_EQ(e.getDouble(t, "translateX"), first);
    EXPECT_EQ(e.getDouble3(t, "t").x, first);
    EXPECT_NEAR(first, 2.5, 1e-12);
}

TEST(Evaluator, ReadSceneInMetresAndDegrees) {
    const char* text =
        "currentUnit -l meter -a degree -t pal;\n"
        "createNode transform -n \"t\";\n"
        "\tsetAttr \".t\" -type \"double3\" 1 2 3 ;\n"
        "\tsetAttr \".r\" -type \"double3\" 0 0 90 ;\n"
        "createNode animCurveTL -n \"t_translateX\";\n"
        "\tsetAttr \".tan\" 2;\n"
        "\tsetAttr \".wgt\" no;\n"
        "\tsetAttr -s 2 \".ktv[0:1]\"  0 0 10 1;\n"
        "connectAttr \"t_translateX.o\" \"t.tx\";\n";
    const Graph g = MaReader::readString(text, "units.ma");
    EXPECT_DOUBLE_EQ(g.units.framesPerSecond, 25.0);
    const NodeId t = g.find("t");
    ASSERT_NE(t, kNoNode);
    Evaluator e(g, 5.0);
    // Keys in metres become centimetres once: 0.5 m → 50 cm; the static ty, rz are already internal.
    expectNear(e.getDouble3(t, "translate"), {50, 200, 300}, 1e-9);
    EXPECT_NEAR(e.getDouble(t, "rz"), kPi / 2, 1e-12);
    expectNear(apply(e.worldMatrix({t}), {1, 0, 0}), {50, 201, 300}, 1e-9);
}

// A scene Maya wrote with clamped tangents and step-tangent visibility.
TEST(Evaluator, EvaluatesCorpusAnimation) {
    const std::filesystem::path file =
        std::filesystem::path(PUSHPIN_MA_CORPUS) / "sebastienblor__arnold-usd__test_0072_test.ma";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "corpus file not found: " << file;
    const Graph g = MaReader::readFile(file);
    const NodeId cube = g.find("pCube2");
    ASSERT_NE(cube, kNoNode);
    const double k0 = -12.715085815870783, k1 = 0.17359846489722131, k2 = 13.062283609918968;
    for (auto [frame, x] : {std::pair{1.0, k0}, std::pair{5.0, k1}, std::pair{9.0, k2}, std::pair{20.0, k2}}) {
        Evaluator e(g, frame);
        EXPECT_NEAR(e.getDouble(cube, "tx"), x, 1e-12) << frame;
        EXPECT_NEAR(e.getDouble(cube, "tz"), -3.8681319072606639, 1e-12);
        EXPECT_NEAR(e.getDouble(cube, "sy"), 4.608784903641804, 1e-12);
        EXPECT_TRUE(e.visible({cube}));
    }
    // Frame 3, between keys 0 and 1: clamped = spline here (no neighbour within 0.05); the end key's
    // slope is the chord (k1 − k0)/4 and key 1's is (k2 − k0)/8; a Hermite span at u = ½.
    const double m0 = (k1 - k0) / 4.0, m1 = (k2 - k0) / 8.0;
    const double expected = 0.5 * k0 + 0.125 * 4.0 * m0 + 0.5 * k1 - 0.125 * 4.0 * m1;
    EXPECT_NEAR(Evaluator(g, 3.0).getDouble(cube, "tx"), expected, 1e-12);
    // The persp camera's animated rotation is written in degrees.
    const NodeId persp = g.find("persp");
    ASSERT_NE(persp, kNoNode);
    EXPECT_NEAR(Evaluator(g, 4.0).getDouble(persp, "rx"), -87.338352729575305 * kDeg, 1e-12);
    EXPECT_FALSE(Evaluator(g, 4.0).visible({persp}));  // persp_visibility keys are 0
}

TEST(Evaluator, WeightedTangentLengthsAreInSeconds) {
    Graph g;  // 24 fps
    const NodeId t = g.createNode("transform", "t");
    const NodeId c = g.createNode("animCurveTL", "tx");
    set(g, c, "ktv[0:1]", {0, 0, 24, 10});
    set(g, c, "tan", {1.0});  // fixed
    set(g, c, "wgt", {1.0});
    // Flat tangents one second long: control points a third of the span in, at frames 8 and 16, so
    // time is linear in the Bézier parameter and the value is 10·(3s² − 2s³) with s = frame/24.
    set(g, c, "kox[0]", {1.0});
    set(g, c, "koy[0]", {0.0});
    set(g, c, "kix[1]", {1.0});
    set(g, c, "kiy[1]", {0.0});
    link(g, c, "o", t, "tx");
    EXPECT_NEAR(Evaluator(g, 8.0).getDouble(t, "tx"), 10.0 * (3.0 / 9.0 - 2.0 / 27.0), 1e-9);
    EXPECT_NEAR(Evaluator(g, 12.0).getDouble(t, "tx"), 5.0, 1e-9);
    EXPECT_NEAR(Evaluator(g, 18.0).getDouble(t, "tx"), 10.0 * (3 * 0.5625 - 2 * 0.421875), 1e-9);
}

TEST(Evaluator, RotateOrderAttributeIsUsed) {
    Graph g;
    const NodeId t = g.createNode("transform", "t");
    set3(g, t, "r", 90 * kDeg, 90 * kDeg, 0);
    Evaluator xyz(g, 1.0);
    // xyz: x 90° leaves +x, y 90° takes it to −z.
    expectNear(apply(xyz.worldMatrix({t}), {1, 0, 0}), {0, 0, -1});
    set(g, t, "ro", {5.0});  // zyx: y 90° takes +x to −z, x 90° takes −z to +y
    Evaluator zyx(g, 1.0);
    expectNear(apply(zyx.worldMatrix({t}), {1, 0, 0}), {0, 1, 0});
}

}  // namespace
}  // namespace pushpin::scene
