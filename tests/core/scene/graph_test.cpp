#include "core/scene/graph.h"

#include "cache/error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pushpin::scene {
namespace {

std::vector<PlugSegment> path(std::string_view text) {
    auto p = parsePlugPath(text);
    EXPECT_TRUE(p.has_value()) << text;
    return p.value_or(std::vector<PlugSegment>{});
}

Numbers nums(std::vector<double> v, Numbers::Kind kind = Numbers::Kind::Plain, int tuple = 1) {
    return Numbers{kind, tuple, std::move(v)};
}

TEST(PlugPath, ParsesIndicesRangesAndNesting) {
    auto p = path(".iog[0].og[3].gcl");
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[0].name, "iog");
    EXPECT_EQ(p[0].first, 0);
    EXPECT_EQ(p[1].first, 3);
    EXPECT_FALSE(p[2].indexed());
    auto r = path("vt[0:7]");
    EXPECT_EQ(r[0].first, 0);
    EXPECT_EQ(r[0].last, 7);
    EXPECT_EQ(formatPlugPath(r), "vt[0:7]");
}

TEST(PlugPath, RejectsMalformedPaths) {
    for (const char* bad : {"", ".", "vt[3:1]", "a[", "a[]", "a[-1]", "a..b", "a.", "1abc", "a[x]", "a[1]b", "a[99999999999]"})
        EXPECT_FALSE(parsePlugPath(bad).has_value()) << bad;
}

TEST(Graph, HasMayaDefaultNodes) {
    Graph g;
    for (const char* n : {"time1", "defaultRenderGlobals", "defaultRenderQuality", "defaultResolution",
                          "lambert1", "initialShadingGroup", "defaultLightSet", "lightLinker1"})
        EXPECT_NE(g.find(n), kNoNode) << n;
    EXPECT_NE(g.find(":defaultRenderGlobals"), kNoNode);
    auto src = g.source(g.find("initialShadingGroup"), "ss");
    ASSERT_TRUE(src.has_value());
    EXPECT_EQ(src->node, g.find("lambert1"));
    EXPECT_EQ(src->path, "outColor");
    EXPECT_TRUE(g.unsupportedTypes().empty());
}

TEST(Graph, ResolvesLongAndShortNamesWithDefaults) {
    Graph g;
    NodeId t = g.createNode("transform", "pCube1");
    EXPECT_EQ(g.canonicalPath(t, path("t")), "translate");
    EXPECT_EQ(g.canonicalPath(t, path("iog[0].og[3].gcl")), "instObjGroups[0].objectGroups[3].objectGrpCompList");
    std::vector<double> v;
    ASSERT_TRUE(g.numbers(t, "s", v));
    EXPECT_EQ(v, (std::vector<double>{1, 1, 1}));
    EXPECT_DOUBLE_EQ(g.getDouble(t, "scaleY"), 1.0);
    g.setValue(t, path("t"), nums({1, 2, 3}, Numbers::Kind::Tuple, 3));
    EXPECT_DOUBLE_EQ(g.getDouble(t, "translateY"), 2.0);
    EXPECT_DOUBLE_EQ(g.getDouble(t, "ty"), 2.0);
    g.setValue(t, path("tx"), nums({5}));
    ASSERT_TRUE(g.numbers(t, "translate", v));
    EXPECT_EQ(v, (std::vector<double>{5, 2, 3}));
    // A child set before its parent starts from the parent's defaults.
    g.setValue(t, path("sz"), nums({4}));
    ASSERT_TRUE(g.numbers(t, "scale", v));
    EXPECT_EQ(v, (std::vector<double>{1, 1, 4}));
    EXPECT_TRUE(g.getBool(t, "v"));
    EXPECT_FALSE(g.numbers(t, "noSuchAttr", v));
}

TEST(Graph, StoresMultiRangesSparselyAndOverwritesElements) {
    Graph g;
    NodeId m = g.createNode("mesh", "shape");
    g.setValue(m, path("vt[0:3]"), nums({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
    g.setValue(m, path("vt[10]"), nums({9, 9, 9}, Numbers::Kind::Tuple, 3));
    const AttrData* a = g.findAttr(m, "vrts");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->multi.indices(), (std::vector<uint32_t>{0, 1, 2, 3, 10}));
    EXPECT_EQ(a->multi.runs().size(), 2u);
    std::vector<double> v;
    ASSERT_TRUE(g.numbers(m, "vt[2]", v));
    EXPECT_EQ(v, (std::vector<double>{1, 1, 0}));
    // Overwrite the middle of a run: the run splits, the rest keeps its values.
    g.setValue(m, path("vt[1:2]"), nums({7, 7, 7, 8, 8, 8}));
    ASSERT_TRUE(g.numbers(m, "vt[0]", v));
    EXPECT_EQ(v, (std::vector<double>{0, 0, 0}));
    ASSERT_TRUE(g.numbers(m, "vt[2]", v));
    EXPECT_EQ(v, (std::vector<double>{8, 8, 8}));
    ASSERT_TRUE(g.numbers(m, "vt[3]", v));
    EXPECT_EQ(v, (std::vector<double>{0, 1, 0}));
    // A component of an element.
    g.setValue(m, path("pt[5].pz"), nums({0.5}));
    ASSERT_TRUE(g.numbers(m, "pt[5]", v));
    EXPECT_EQ(v, (std::vector<double>{0, 0, 0.5}));
    // Consecutive single-element writes grow one run.
    for (uint32_t i = 0; i < 100; ++i) {
        std::vector<PlugSegment> seg{PlugSegment{"uvpt", int64_t(i), int64_t(i)}};
        g.setValue(m, seg, nums({double(i), 0}, Numbers::Kind::Tuple, 2));
    }
    EXPECT_EQ(g.findAttr(m, "uvpt")->multi.runs().size(), 1u);
}

// What a memory cap charges for a loaded scene: the heap bytes of its stored values, arrays in
// multi runs and plain values alike, a payload two plugs share counted once.
TEST(Graph, StoredBytesCountTheValuesPayloads) {
    Graph g;
    const uint64_t base = g.storedBytes();
    NodeId m = g.createNode("mesh", "shape");
    std::vector<double> points(3 * 10000, 0.5);
    Numbers big = nums(points);
    big.values.shrink_to_fit();
    g.setValue(m, path("vt[0:9999]"), big);
    // Mesh points are kept in single precision (Numbers::floats).
    EXPECT_EQ(g.storedBytes(), base + 10000 * 3 * sizeof(float));
    auto surface = std::make_shared<NurbsSurfaceData>();
    surface->knotsU.assign(10, 0.0);
    surface->knotsV.assign(10, 0.0);
    surface->cvs.assign(300, 1.0);
    surface->knotsU.shrink_to_fit();
    surface->knotsV.shrink_to_fit();
    surface->cvs.shrink_to_fit();
    NodeId s = g.createNode("nurbsSurface", "surface");
    g.setValue(s, path("cc"), Value(std::shared_ptr<const NurbsSurfaceData>(surface)));
    NodeId t = g.createNode("nurbsSurface", "again");
    g.setValue(t, path("cc"), Value(std::shared_ptr<const NurbsSurfaceData>(surface)));
    EXPECT_EQ(g.storedBytes(), base + 10000 * 3 * sizeof(float) + 320 * sizeof(double));
}

TEST(Graph, LongRunsKeepMayasOwnPrecision) {
    Graph g;
    NodeId m = g.createNode("mesh", "shape");
    // 100 points (float3): kept as floats, read back as the float nearest each value.
    std::vector<double> points;
    for (int i = 0; i < 300; ++i) points.push_back(0.1 * i - 7.3);
    g.setValue(m, path("vt[0:99]"), nums(points));
    // 100 edges (long3): kept as 32-bit integers.
    std::vector<double> edges;
    for (int i = 0; i < 100; ++i) edges.insert(edges.end(), {double(i), double(i + 1), double(i % 2)});
    g.setValue(m, path("ed[0:99]"), nums(edges));
    const uint64_t bytes = g.storedBytes();
    std::vector<double> v;
    ASSERT_TRUE(g.numbers(m, "vt[42]", v));
    ASSERT_EQ(v.size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(v[size_t(k)], double(float(points[size_t(126 + k)]))) << k;
    ASSERT_TRUE(g.numbers(m, "ed[99]", v));
    EXPECT_EQ(v, (std::vector<double>{99, 100, 1}));

    // One element written again splits its run; both parts keep their storage and values.
    g.setValue(m, path("vt[50]"), nums({1.0, 2.0, 3.0}));
    ASSERT_TRUE(g.numbers(m, "vt[50]", v));
    EXPECT_EQ(v, (std::vector<double>{1, 2, 3}));
    ASSERT_TRUE(g.numbers(m, "vt[51]", v));
    EXPECT_EQ(v[0], double(float(points[153])));
    ASSERT_TRUE(g.numbers(m, "vt[49]", v));
    EXPECT_EQ(v[2], double(float(points[149])));
    // A short run appended after a long one joins it only in the same storage; values stay right.
    g.setValue(m, path("vt[100]"), nums({4.0, 5.0, 6.0}));
    ASSERT_TRUE(g.numbers(m, "vt[100]", v));
    EXPECT_EQ(v, (std::vector<double>{4, 5, 6}));
    EXPECT_LT(g.storedBytes(), bytes + 200);  // the split runs are still floats

    // Edges that are not all integers, points beyond float range and NaN stay doubles, exactly.
    std::vector<double> halves(edges);
    halves[7] = 2.5;
    g.setValue(m, path("ed[200:299]"), nums(halves));
    ASSERT_TRUE(g.numbers(m, "ed[202]", v));
    EXPECT_EQ(v[1], 2.5);
    std::vector<double> huge(points);
    huge[5] = 1e300;
    huge[6] = std::nan("");
    g.setValue(m, path("vt[300:399]"), nums(huge));
    ASSERT_TRUE(g.numbers(m, "vt[301]", v));
    EXPECT_EQ(v[1], points[4]);
    EXPECT_EQ(v[2], 1e300);
    // A double attribute is never rounded; short runs are not either.
    NodeId c = g.createNode("animCurveTL", "curve");
    std::vector<double> keys;
    for (int i = 0; i < 100; ++i) keys.insert(keys.end(), {double(i), 0.1 * i});
    g.setValue(c, path("ktv[0:99]"), nums(keys));
    ASSERT_TRUE(g.numbers(c, "ktv[33]", v));
    EXPECT_EQ(v[1], keys[67]);
    g.setValue(m, path("vt[500:501]"), nums({0.1, 0.2, 0.3, 0.4, 0.5, 0.6}));
    ASSERT_TRUE(g.numbers(m, "vt[501]", v));
    EXPECT_EQ(v[0], 0.4);
}

TEST(Graph, DagPathsAndInstancing) {
    Graph g;
    NodeId a = g.createNode("transform", "a");
    NodeId b = g.createNode("transform", "b");
    NodeId shape = g.createNode("mesh", "shape", a);
    g.setParent(shape, b, true);
    auto paths = g.dagPaths(shape);
    ASSERT_EQ(paths.size(), 2u);
    EXPECT_EQ(g.dagPathName(paths[0]), "|a|shape");
    EXPECT_EQ(g.dagPathName(paths[1]), "|b|shape");
    EXPECT_EQ(g.find("|a|shape"), shape);
    EXPECT_EQ(g.find("b|shape"), shape);
    EXPECT_EQ(g.find("|shape"), kNoNode);
    // Same short name under different parents is legal for DAG nodes.
    NodeId c1 = g.createNode("transform", "child", a);
    NodeId c2 = g.createNode("transform", "child", b);
    EXPECT_EQ(g.find("|b|child"), c2);
    EXPECT_EQ(g.find("child"), c1);
    EXPECT_THROW(g.createNode("transform", "child", a), Error);
    EXPECT_THROW(g.createNode("lambert", "a"), Error);
    EXPECT_THROW(g.setParent(a, shape, true), Error);  // would make a cycle
    g.setParent(c1, kNoNode, false);
    EXPECT_EQ(g.find("|child"), c1);
}

TEST(Graph, InstancingAWorldLevelNodeKeepsTheWorldInstance) {
    Graph g;
    NodeId cube = g.createNode("transform", "pCube1");
    NodeId grp = g.createNode("transform", "grp");
    g.setParent(cube, grp, true);  // parent -add "pCube1" "grp"
    auto paths = g.dagPaths(cube);
    ASSERT_EQ(paths.size(), 2u);
    EXPECT_EQ(g.dagPathName(paths[0]), "|pCube1");
    EXPECT_EQ(g.dagPathName(paths[1]), "|grp|pCube1");
    EXPECT_EQ(g.find("|pCube1"), cube);
    EXPECT_EQ(g.find("|grp|pCube1"), cube);
    // Plain reparenting (no -add) leaves the world.
    g.setParent(cube, grp, false);
    ASSERT_EQ(g.dagPaths(cube).size(), 1u);
    EXPECT_EQ(g.find("|pCube1"), kNoNode);
}

TEST(Graph, ConnectionsNextAvailableAndReplacement) {
    Graph g;
    NodeId sg = g.createNode("shadingEngine", "sg");
    NodeId s1 = g.createNode("mesh", "s1");
    NodeId s2 = g.createNode("mesh", "s2");
    g.connect({s1, "iog"}, {sg, "dsm"}, true);
    g.connect({s2, "iog"}, {sg, "dsm"}, true);
    auto src = g.source(sg, "dagSetMembers[1]");
    ASSERT_TRUE(src.has_value());
    EXPECT_EQ(src->node, s2);
    EXPECT_EQ(src->path, "instObjGroups");
    EXPECT_EQ(g.outputs(s1).size(), 1u);
    // A second connection into the same plug replaces the first.
    NodeId l1 = g.createNode("lambert", "l1");
    NodeId l2 = g.createNode("lambert", "l2");
    g.connect({l1, "oc"}, {sg, "ss"});
    g.connect({l2, "outColor"}, {sg, "surfaceShader"});
    EXPECT_EQ(g.source(sg, "ss")->node, l2);
    EXPECT_TRUE(g.disconnect({l2, "oc"}, {sg, "ss"}));
    EXPECT_FALSE(g.source(sg, "ss").has_value());
    EXPECT_FALSE(g.disconnect({l2, "oc"}, {sg, "ss"}));
}

TEST(Graph, UnknownTypesAndAttributesAreKeptAndCounted) {
    Graph g;
    NodeId n = g.createNode("aiStandardSurface", "ai1");
    g.setValue(n, path("base"), nums({0.8}));
    EXPECT_DOUBLE_EQ(g.getDouble(n, "base"), 0.8);
    EXPECT_EQ(g.unsupportedTypes().at("aiStandardSurface"), 1);
    NodeId t = g.createNode("transform", "t1");
    g.setValue(t, path("myCustom"), nums({1}));
    EXPECT_EQ(g.unsupportedAttributes().at("transform.myCustom"), 1);
    // addAttr'ed attributes resolve by both names.
    AttrSpec dyn;
    dyn.longName = "myCustomAttr";
    dyn.shortName = "mca";
    g.node(t).mutableLinks().dynamicAttrs.push_back(dyn);
    g.setValue(t, path("mca"), nums({3}));
    EXPECT_DOUBLE_EQ(g.getDouble(t, "myCustomAttr"), 3.0);
}

TEST(Schema, InheritanceAndDefaults) {
    const NodeSchema* blinn = findSchema("blinn");
    ASSERT_NE(blinn, nullptr);
    EXPECT_TRUE(blinn->isA("lambert"));
    EXPECT_FALSE(blinn->isA("dagNode"));
    EXPECT_EQ(blinn->find("c")->longName, "color");
    EXPECT_FLOAT_EQ(float(blinn->find("ec")->defaults[0]), 0.3f);
    const NodeSchema* spot = findSchema("spotLight");
    ASSERT_NE(spot, nullptr);
    EXPECT_TRUE(spot->isA("dagNode"));
    EXPECT_NEAR(spot->find("coneAngle")->defaults[0], 40.0 * 3.14159265358979 / 180.0, 1e-12);
    EXPECT_EQ(spot->find("ca")->unit, UnitKind::Angle);
    const NodeSchema* cam = findSchema("camera");
    EXPECT_EQ(cam->find("hfa")->parent, "cameraAperture");
    EXPECT_EQ(cam->find("ncp")->unit, UnitKind::Distance);
    EXPECT_EQ(findSchema("renderQuality")->find("eaa")->defaults[0], 3.0);
    EXPECT_EQ(findSchema("aiStandardSurface"), nullptr);
    // No type declares the same name twice (a long name shadowing another attribute's short name
    // within one type would make lookups ambiguous).
    for (const std::string& type : schemaTypes()) {
        const NodeSchema* s = findSchema(type);
        for (const AttrSpec& a : s->ownAttributes()) {
            EXPECT_EQ(s->find(a.longName), &a) << type << "." << a.longName;
            if (!a.shortName.empty()) {
                EXPECT_EQ(s->find(a.shortName), &a) << type << "." << a.shortName;
            }
        }
    }
}

// The name index: same-named DAG nodes under different parents, renames in and out of a shared
// name, and lookups that must return the first created node of a name.
TEST(Graph, NameIndexFollowsRenamesAndSharedNames) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    const NodeId xa = g.createNode("transform", "x", a);
    const NodeId xb = g.createNode("transform", "x", b);
    const NodeId xc = g.createNode("transform", "x", g.createNode("transform", "c"));
    EXPECT_EQ(g.find("x"), xa);
    EXPECT_EQ(g.find("b|x"), xb);
    EXPECT_EQ(g.find("|c|x"), xc);
    // Renaming the first of the name away leaves the others findable, the next oldest first.
    g.rename(xa, "y");
    EXPECT_EQ(g.find("x"), xb);
    EXPECT_EQ(g.find("y"), xa);
    EXPECT_EQ(g.find("a|y"), xa);
    EXPECT_EQ(g.find("a|x"), kNoNode);
    // A node from the middle of the chain, then the rest.
    g.rename(xc, "z");
    EXPECT_EQ(g.find("x"), xb);
    g.rename(xb, "w");
    EXPECT_EQ(g.find("x"), kNoNode);
    // Back into the name: the oldest is found whatever the order of renames.
    g.rename(xc, "x");
    g.rename(xa, "x");
    EXPECT_EQ(g.find("x"), xa);
    EXPECT_EQ(g.find("c|x"), xc);
    EXPECT_EQ(g.find("w"), xb);
    // The same name again is a no-op for the index.
    g.rename(xa, "x");
    EXPECT_EQ(g.find("x"), xa);
    EXPECT_EQ(g.clashingNode("transform", "x", a)->id, xa);
    EXPECT_EQ(g.clashingNode("transform", "x", b), nullptr);
    // Moving a node of a shared name moves its place in the sibling index with it.
    EXPECT_EQ(g.find("|x"), kNoNode);
    g.setParent(xc, kNoNode, false);  // parent -w
    EXPECT_EQ(g.find("|x"), xc);
    EXPECT_EQ(g.find("c|x"), kNoNode);
    EXPECT_EQ(g.clashingNode("transform", "x", kNoNode)->id, xc);
    EXPECT_EQ(g.clashingNode("transform", "x", g.find("c")), nullptr);
    g.setParent(xc, b, false);
    EXPECT_EQ(g.find("|x"), kNoNode);
    EXPECT_EQ(g.find("b|x"), xc);
    // A name down to one node again: lookups still find it under its parent.
    g.rename(xa, "solo");
    g.rename(xc, "other");
    EXPECT_EQ(g.find("x"), kNoNode);
    EXPECT_EQ(g.childNamed(a, "solo"), xa);
    EXPECT_EQ(g.find("a|solo"), xa);
    EXPECT_EQ(g.clashingNode("transform", "solo", a)->id, xa);
    EXPECT_EQ(g.clashingNode("lambert", "solo", kNoNode)->id, xa);  // outside the DAG: any node of the name
}

// Nodes stay where they are while the graph grows: a reference taken early is still the node.
TEST(Graph, NodeReferencesSurviveGrowth) {
    Graph g;
    const NodeId first = g.createNode("transform", "first");
    const Node& ref = g.node(first);
    for (int i = 0; i < 20000; ++i) g.createNode("transform", "n" + std::to_string(i));
    EXPECT_EQ(&ref, &g.node(first));
    EXPECT_EQ(ref.name, "first");
    size_t count = 0;
    for (const Node& n : g.nodes()) count += n.id == count ? 1 : 0;
    EXPECT_EQ(count, g.size());
    EXPECT_THROW((void)g.nodes().at(g.size()), std::out_of_range);
}

}  // namespace
}  // namespace pushpin::scene
