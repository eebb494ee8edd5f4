// Tests of core/scene/nurbs_eval.h: decoding `.cc` data, creator nodes through the Evaluator, history
// handling, malformed data, and every NURBS shape of the public .ma corpus.
#include "core/scene/nurbs_eval.h"

#include "core/geom/nurbs_primitives.h"
#include "core/scene/ma_reader.h"

#include "tests/support/ma_corpus.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace pushpin::scene {
namespace {

namespace fs = std::filesystem;

void setNumbers(Graph& g, NodeId node, const char* plug, std::vector<double> values) {
    Numbers n;
    n.kind = values.size() > 1 ? Numbers::Kind::Tuple : Numbers::Kind::Plain;
    n.tupleSize = int(values.size());
    n.values = std::move(values);
    g.setValue(node, *parsePlugPath(plug), n);
}

void connect(Graph& g, NodeId src, const char* srcPlug, NodeId dst, const char* dstPlug) {
    g.connect(Plug{src, g.canonicalPath(src, *parsePlugPath(srcPlug))},
              Plug{dst, g.canonicalPath(dst, *parsePlugPath(dstPlug))});
}

// Maya's form of a surface: knots without the outermost two, CVs as x y z [w] (Cartesian + weight).
std::shared_ptr<NurbsSurfaceData> toMayaData(const geom::NurbsSurface& s, bool preMultiplied = false) {
    auto d = std::make_shared<NurbsSurfaceData>();
    d->degreeU = s.degreeU();
    d->degreeV = s.degreeV();
    d->formU = int(s.formU());
    d->formV = int(s.formV());
    d->rational = s.rational();
    d->knotsU = geom::mayaKnotsFromTextbook(s.knotsU());
    d->knotsV = geom::mayaKnotsFromTextbook(s.knotsV());
    d->cvCountU = s.cvCountU();
    d->cvCountV = s.cvCountV();
    for (const glm::dvec4& c : s.cvs()) {
        const glm::dvec3 p = preMultiplied ? glm::dvec3(c) : glm::dvec3(c) / c.w;
        d->cvs.insert(d->cvs.end(), {p.x, p.y, p.z});
        if (s.rational()) d->cvs.push_back(c.w);
    }
    return d;
}

double maxRadiusError(const geom::NurbsSurface& s, const glm::dvec3& center, double radius, int n) {
    double worst = 0.0;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const double u = s.uMin() + (s.uMax() - s.uMin()) * i / n;
            const double v = s.vMin() + (s.vMax() - s.vMin()) * j / n;
            worst = std::max(worst, std::abs(glm::length(s.point(u, v) - center) - radius));
        }
    return worst;
}

TEST(NurbsEval, WorkedPatchFromMaTextEvaluatesToItsPlane) {
    const char* text = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "patch";
createNode nurbsSurface -n "patchShape" -p "patch";
	setAttr ".cc" -type "nurbsSurface"
		3 3 0 0 no
		6 0 0 0 1 1 1
		6 0 0 0 1 1 1

		16
		-1.5 0 1.5  -1.5 0 0.5  -1.5 0 -0.5  -1.5 0 -1.5
		-0.5 0 1.5  -0.5 0 0.5  -0.5 0 -0.5  -0.5 0 -1.5
		 0.5 0 1.5   0.5 0 0.5   0.5 0 -0.5   0.5 0 -1.5
		 1.5 0 1.5   1.5 0 0.5   1.5 0 -0.5   1.5 0 -1.5;
)";
    Graph g = MaReader::readString(text, "patch.ma");
    Evaluator ev(g, 1.0);
    std::string reason;
    auto s = evaluateNurbsSurface(ev, g.find("patchShape"), &reason);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_EQ(s->cvCountU(), 4);
    EXPECT_EQ(s->cvCountV(), 4);
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
            const glm::dvec3 p = s->point(i / 8.0, j / 8.0);
            EXPECT_NEAR(p.y, 0.0, 1e-15);
            EXPECT_NEAR(p.x, -1.5 + 3.0 * i / 8, 1e-14);
        }
}

TEST(NurbsEval, CreatorSphereThroughTheGraphWithAnimatedRadius) {
    const char* text = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "nurbsSphere1";
createNode nurbsSurface -n "nurbsSphereShape1" -p "nurbsSphere1";
createNode makeNurbSphere -n "makeNurbSphere1";
	setAttr ".ax" -type "double3" 0 0 1 ;
	setAttr ".p" -type "double3" 1 2 3 ;
	setAttr ".esw" 180;
	setAttr ".d" 2;
createNode animCurveTL -n "makeNurbSphere1_radius";
	setAttr -s 2 ".ktv[0:1]"  1 2 11 5;
connectAttr "makeNurbSphere1_radius.o" "makeNurbSphere1.r";
connectAttr "makeNurbSphere1.os" "nurbsSphereShape1.cr";
)";
    Graph g = MaReader::readString(text, "sphere.ma");
    const NodeId shape = g.find("nurbsSphereShape1");
    for (auto [frame, radius] : {std::pair{1.0, 2.0}, std::pair{11.0, 5.0}}) {
        Evaluator ev(g, frame);
        std::string reason;
        auto s = evaluateNurbsSurface(ev, shape, &reason);
        ASSERT_TRUE(s.has_value()) << reason;
        EXPECT_TRUE(s->rational());
        const double worst = maxRadiusError(*s, {1, 2, 3}, radius, 200);
        std::printf("[ measure  ] makeNurbSphere d=2 r=%g through the graph: max |r' - r| = %.3g\n", radius, worst);
        EXPECT_LT(worst, 1e-6 * radius);
        // endSweep 180 degrees (converted to radians by the reader): a half sphere.
        EXPECT_EQ(s->formV(), geom::NurbsForm::Open);
        EXPECT_NEAR(glm::length(s->point(s->uMin(), 0) - glm::dvec3(1, 2, 3 - radius)), 0.0, 1e-12);
    }
}

TEST(NurbsEval, DefaultSphereNodeMatchesTheCvsMayaStores) {
    // A makeNurbSphere with only the axis set (as Maya's UI writes it) must give the 4-span, 8-section
    // surface whose .cc Maya stores for a default sphere.
    Graph g;
    const NodeId xf = g.createNode("transform", "nurbsSphere1");
    const NodeId shape = g.createNode("nurbsSurface", "nurbsSphereShape1", xf);
    const NodeId make = g.createNode("makeNurbSphere", "makeNurbSphere1");
    setNumbers(g, make, ".ax", {0, 1, 0});
    connect(g, make, "os", shape, "cr");
    Evaluator ev(g, 1.0);
    std::string reason;
    auto s = evaluateNurbsSurface(ev, shape, &reason);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_EQ(s->cvCountU(), 7);
    EXPECT_EQ(s->cvCountV(), 11);
    EXPECT_NEAR(glm::length(s->cvPoint(3, 1) - glm::dvec3(1.2264094625656803, 0, 0)), 0.0, 1e-13);
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 8; ++j) EXPECT_NEAR(glm::length(s->point(i, j)), 1.0, 1e-14);
}

TEST(NurbsEval, CubeFacesFollowTheOutputPlugNames) {
    Graph g;
    const NodeId make = g.createNode("makeNurbCube", "makeNurbCube1");
    setNumbers(g, make, ".ax", {0, 1, 0});
    setNumbers(g, make, ".w", {4});
    const char* names[6] = {"top", "bottom", "left", "right", "front", "back"};
    const char* plugs[6] = {"os", "os1", "os2", "os3", "os4", "os5"};
    const glm::dvec3 centers[6] = {{0, 2, 0}, {0, -2, 0}, {-2, 0, 0}, {2, 0, 0}, {0, 0, 2}, {0, 0, -2}};
    for (int f = 0; f < 6; ++f) {
        const NodeId xf = g.createNode("transform", std::string(names[f]) + "nurbsCube1");
        const NodeId shape = g.createNode("nurbsSurface", std::string(names[f]) + "nurbsCubeShape1", xf);
        connect(g, make, plugs[f], shape, "cr");
    }
    Evaluator ev(g, 1.0);
    for (int f = 0; f < 6; ++f) {
        std::string reason;
        auto s = evaluateNurbsSurface(ev, g.find(std::string(names[f]) + "nurbsCubeShape1"), &reason);
        ASSERT_TRUE(s.has_value()) << reason;
        const glm::dvec3 c = s->point(0.5 * (s->uMin() + s->uMax()), 0.5 * (s->vMin() + s->vMax()));
        EXPECT_NEAR(glm::length(c - centers[f]), 0.0, 1e-12) << names[f];
    }
}

TEST(NurbsEval, OtherHistoryIsSkippedUnlessTheShapeStoresItsSurface) {
    Graph g;
    const NodeId xf = g.createNode("transform", "surf");
    const NodeId shape = g.createNode("nurbsSurface", "surfShape", xf);
    const NodeId rebuild = g.createNode("rebuildSurface", "rebuildSurface1");
    connect(g, rebuild, "os", shape, "cr");
    {
        Evaluator ev(g, 1.0);
        std::string reason;
        EXPECT_FALSE(evaluateNurbsSurface(ev, shape, &reason));
        EXPECT_EQ(reason, "history node rebuildSurface (rebuildSurface1) is not evaluated");
    }
    auto plane = geom::makeNurbPlane({}, nullptr);
    ASSERT_TRUE(plane.has_value());
    g.setValue(shape, *parsePlugPath(".cc"), std::shared_ptr<const NurbsSurfaceData>(toMayaData(*plane)));
    Evaluator ev(g, 1.0);
    std::string reason, note;
    auto s = evaluateNurbsSurface(ev, shape, &reason, &note);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_NE(note.find("history node rebuildSurface (rebuildSurface1) is not evaluated"), std::string::npos) << note;
    EXPECT_NEAR(glm::length(s->point(0.5, 0.5) - plane->point(0.5, 0.5)), 0.0, 1e-15);

    const NodeId empty = g.createNode("nurbsSurface", "emptyShape", xf);
    EXPECT_FALSE(evaluateNurbsSurface(ev, empty, &reason));
    EXPECT_NE(reason.find("no cached surface data"), std::string::npos) << reason;
}

TEST(NurbsEval, RationalCvInterpretationsDifferAndCartesianIsTheDefault) {
    // Exact rational sphere written as (x, y, z, w) with Cartesian xyz, and as pre-multiplied
    // (x·w, y·w, z·w, w). Each decodes onto the sphere only with its own interpretation.
    auto sphere = geom::makeRationalSphere({}, nullptr);
    ASSERT_TRUE(sphere.has_value());
    std::string err;
    auto cart = decodeNurbsSurface(*toMayaData(*sphere, false), &err);
    ASSERT_TRUE(cart.has_value()) << err;
    auto pre = decodeNurbsSurface(*toMayaData(*sphere, true), &err, RationalCvLayout::PreMultiplied);
    ASSERT_TRUE(pre.has_value()) << err;
    auto crossed = decodeNurbsSurface(*toMayaData(*sphere, true), &err);
    ASSERT_TRUE(crossed.has_value()) << err;
    const double eCart = maxRadiusError(*cart, glm::dvec3(0.0), 1.0, 100);
    const double ePre = maxRadiusError(*pre, glm::dvec3(0.0), 1.0, 100);
    const double eCrossed = maxRadiusError(*crossed, glm::dvec3(0.0), 1.0, 100);
    std::printf("[ measure  ] rational sphere radius error: cartesian %.3g, pre-multiplied %.3g, "
                "pre-multiplied data read as cartesian %.3g\n", eCart, ePre, eCrossed);
    EXPECT_LT(eCart, 1e-12);
    EXPECT_LT(ePre, 1e-12);
    EXPECT_GT(eCrossed, 1e-2);
}

TEST(NurbsEval, MalformedCachedDataGivesClearErrors) {
    auto plane = geom::makeNurbPlane({}, nullptr);
    ASSERT_TRUE(plane.has_value());
    std::string err;

    auto d = toMayaData(*plane);
    d->cvs.resize(d->cvs.size() - 3);
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_EQ(err, "nurbsSurface data: 45 CV numbers, expected 4 x 4 CVs x 3 = 48");

    d = toMayaData(*plane);
    d->knotsV = {0, 0, 1, 0.5, 1, 1};
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_NE(err.find("V: knots decrease"), std::string::npos) << err;

    d = toMayaData(*plane);
    d->cvs[7] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_NE(err.find("CV [0][2] is not finite"), std::string::npos) << err;

    d = toMayaData(*plane);
    d->knotsU = {0, 0, 1, 1};
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_NE(err.find("U knot count 4 does not match 4 CVs + degree 3 - 1"), std::string::npos) << err;

    d = toMayaData(*plane);
    d->formV = 7;
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_NE(err.find("formV 7"), std::string::npos) << err;

    d = toMayaData(*plane);
    d->degreeU = 0;
    EXPECT_FALSE(decodeNurbsSurface(*d, &err));
    EXPECT_NE(err.find("degreeU 0"), std::string::npos) << err;

    // Through a shape: the reason names the shape.
    Graph g;
    const NodeId shape = g.createNode("nurbsSurface", "badShape", g.createNode("transform", "bad"));
    d = toMayaData(*plane);
    d->cvs.pop_back();
    g.setValue(shape, *parsePlugPath(".cc"), std::shared_ptr<const NurbsSurfaceData>(d));
    Evaluator ev(g, 1.0);
    std::string reason;
    EXPECT_FALSE(evaluateNurbsSurface(ev, shape, &reason));
    EXPECT_EQ(reason.rfind("badShape: nurbsSurface data: ", 0), 0u) << reason;

    // Creator attributes Maya would refuse.
    Graph g2;
    const NodeId s2 = g2.createNode("nurbsSurface", "s2", g2.createNode("transform", "t2"));
    const NodeId make = g2.createNode("makeNurbSphere", "makeNurbSphere1");
    setNumbers(g2, make, ".r", {-1});
    connect(g2, make, "os", s2, "cr");
    Evaluator ev2(g2, 1.0);
    EXPECT_FALSE(evaluateNurbsSurface(ev2, s2, &reason));
    EXPECT_NE(reason.find("makeNurbSphere (makeNurbSphere1): radius must be > 0"), std::string::npos) << reason;
}

TEST(NurbsEval, CurvesDecodeAndCircleCreatorEvaluates) {
    // A Maya circle as stored in .cc (normal +Y, radius 0.8247): 3 8 2 no 3 / 13 knots / 11 CVs.
    const double a = 0.64625904433323544, b = 0.91394830530233606;
    const double cv[11][3] = {{a, 0, -a}, {0, 0, -b}, {-a, 0, -a}, {-b, 0, 0}, {-a, 0, a}, {0, 0, b},
                              {a, 0, a},  {b, 0, 0},  {a, 0, -a},  {0, 0, -b}, {-a, 0, -a}};
    NurbsCurveData d;
    d.degree = 3;
    d.spans = 8;
    d.form = 2;
    d.dimension = 3;
    for (int k = -2; k <= 10; ++k) d.knots.push_back(k);
    for (auto& c : cv) d.cvs.insert(d.cvs.end(), {c[0], c[1], c[2]});
    std::string err;
    auto curve = decodeNurbsCurve(d, &err);
    ASSERT_TRUE(curve.has_value()) << err;
    const double r = b / (3.0 / (2.0 + std::sqrt(0.5)));
    for (int k = 0; k <= 8; ++k) EXPECT_NEAR(glm::length(curve->point(k)), r, 1e-12);

    d.cvs.pop_back();
    EXPECT_FALSE(decodeNurbsCurve(d, &err));
    EXPECT_EQ(err, "nurbsCurve data: 32 CV numbers, expected 11 CVs x 3 = 33");

    Graph g;
    const NodeId shape = g.createNode("nurbsCurve", "nurbsCircleShape1", g.createNode("transform", "nurbsCircle1"));
    const NodeId make = g.createNode("makeNurbCircle", "makeNurbCircle1");
    setNumbers(g, make, ".nr", {0, 1, 0});
    setNumbers(g, make, ".r", {r});
    connect(g, make, "oc", shape, "cr");
    Evaluator ev(g, 1.0);
    std::string reason;
    auto made = evaluateNurbsCurve(ev, shape, &reason);
    ASSERT_TRUE(made.has_value()) << reason;
    for (int k = 0; k < 11; ++k) {
        EXPECT_NEAR(glm::length(glm::dvec3(made->cvs()[size_t(k)]) - glm::dvec3(cv[k][0], cv[k][1], cv[k][2])), 0.0,
                    1e-12) << k;
    }
}

TEST(NurbsEval, EveryCorpusNurbsShapeDecodesOrIsSkippedWithAReason) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const std::vector<fs::path> files = test::maCorpusFiles();
    int totalCached = 0, totalCreated = 0, totalCurves = 0;
    for (const fs::path& file : files) {
        SCOPED_TRACE(file.filename().string());
        Graph g;
        try {
            g = MaReader::readFile(file);
        } catch (const Error& e) {
            ADD_FAILURE() << e.what();
            continue;
        }
        Evaluator ev(g, 1.0);
        int cached = 0, created = 0, skipped = 0, curves = 0;
        for (NodeId id : g.nodesOfType("nurbsSurface")) {
            std::string reason, note;
            const bool hasCache = g.value(id, "cc") != nullptr;
            const auto src = g.source(id, "cr");
            auto s = evaluateNurbsSurface(ev, id, &reason, &note);
            if (!s) {
                ++skipped;
                EXPECT_FALSE(reason.empty());
                std::printf("[ corpus   ]   skipped %s: %s\n", g.node(id).name.c_str(), reason.c_str());
                EXPECT_FALSE(hasCache) << g.node(id).name << ": stored surface failed: " << reason;
                continue;
            }
            (src && !hasCache) ? ++created : ++cached;
            for (int i = 0; i <= 10; ++i)
                for (int j = 0; j <= 10; ++j) {
                    const glm::dvec3 p = s->point(s->uMin() + (s->uMax() - s->uMin()) * i / 10,
                                                  s->vMin() + (s->vMax() - s->vMin()) * j / 10);
                    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << g.node(id).name;
                }
        }
        for (NodeId id : g.nodesOfType("nurbsCurve")) {
            if (!g.value(id, "cc")) continue;
            std::string reason;
            auto c = evaluateNurbsCurve(ev, id, &reason);
            EXPECT_TRUE(c.has_value()) << g.node(id).name << ": " << reason;
            if (c) ++curves;
        }
        if (cached + created + skipped + curves > 0) {
            std::printf("[ corpus   ] %-55s surfaces: %d from cc, %d from creators, %d skipped; curves from cc: %d\n",
                        file.filename().string().c_str(), cached, created, skipped, curves);
        }
        totalCached += cached;
        totalCreated += created;
        totalCurves += curves;
    }
    EXPECT_GT(totalCached + totalCreated, 0);
    std::printf("[ corpus   ] total: %d surfaces from cc, %d from creators, %d curves\n", totalCached, totalCreated,
                totalCurves);
}

}  // namespace
}  // namespace pushpin::scene
