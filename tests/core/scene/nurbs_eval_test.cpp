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
#include <numbers>

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
    const NodeId rebuild = g.createNode("offsetSurface", "offsetSurface1");
    connect(g, rebuild, "os", shape, "cr");
    {
        Evaluator ev(g, 1.0);
        std::string reason;
        EXPECT_FALSE(evaluateNurbsSurface(ev, shape, &reason));
        EXPECT_EQ(reason, "history node offsetSurface (offsetSurface1) is not evaluated");
    }
    auto plane = geom::makeNurbPlane({}, nullptr);
    ASSERT_TRUE(plane.has_value());
    g.setValue(shape, *parsePlugPath(".cc"), std::shared_ptr<const NurbsSurfaceData>(toMayaData(*plane)));
    Evaluator ev(g, 1.0);
    std::string reason, note;
    auto s = evaluateNurbsSurface(ev, shape, &reason, &note);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_NE(note.find("history node offsetSurface (offsetSurface1) is not evaluated"), std::string::npos) << note;
    EXPECT_NEAR(glm::length(s->point(0.5, 0.5) - plane->point(0.5, 0.5)), 0.0, 1e-15);

    const NodeId empty = g.createNode("nurbsSurface", "emptyShape", xf);
    EXPECT_FALSE(evaluateNurbsSurface(ev, empty, &reason));
    EXPECT_NE(reason.find("no cached surface data"), std::string::npos) << reason;
}

TEST(NurbsEval, DetachSurfaceGivesTheShapeItsPiece) {
    // As in a real scene: the top of a default sphere, cut across U at 2.17, is a heater's cap.
    const char* text = R"(createNode transform -n "heater";
createNode nurbsSurface -n "heaterShape" -p "heater";
createNode makeNurbSphere -n "makeNurbSphere1";
	setAttr ".ax" -type "double3" 0 1 0 ;
createNode detachSurface -n "detachSurface1";
	setAttr ".p[0]"  2.1746218690000001;
	setAttr -s 2 ".k[0:1]" yes yes;
connectAttr "detachSurface1.os[1]" "heaterShape.cr";
connectAttr "makeNurbSphere1.os" "detachSurface1.is";
)";
    Graph g = MaReader::readString(text, "heater.ma");
    geom::NurbsSphereParams yUp;
    yUp.axis = {0.0, 1.0, 0.0};
    auto sphere = geom::makeNurbSphere(yUp, nullptr);
    ASSERT_TRUE(sphere);
    {
        Evaluator ev(g, 1.0);
        std::string reason;
        auto s = evaluateNurbsSurface(ev, g.find("heaterShape"), &reason);
        ASSERT_TRUE(s.has_value()) << reason;
        EXPECT_NEAR(s->uMin(), 2.1746218690000001, 1e-12);
        EXPECT_NEAR(s->uMax(), 4.0, 1e-12);
        for (double u : {2.2, 3.0, 3.9})
            for (double v : {0.0, 2.5, 7.0}) EXPECT_NEAR(glm::length(s->point(u, v) - sphere->point(u, v)), 0.0, 1e-9);
    }
    // A piece that is not kept, or one the cut does not make, is not rendered, with the reason.
    std::string dropped = text;
    dropped.replace(dropped.find("yes yes"), 7, "yes no");
    g = MaReader::readString(dropped, "dropped.ma");
    Evaluator ev(g, 1.0);
    std::string reason;
    EXPECT_FALSE(evaluateNurbsSurface(ev, g.find("heaterShape"), &reason));
    EXPECT_NE(reason.find("not kept"), std::string::npos) << reason;
    std::string third = text;
    third.replace(third.find("os[1]"), 5, "os[2]");
    g = MaReader::readString(third, "third.ma");
    Evaluator ev3(g, 1.0);
    EXPECT_FALSE(evaluateNurbsSurface(ev3, g.find("heaterShape"), &reason));
    EXPECT_NE(reason.find("2 pieces"), std::string::npos) << reason;
}

TEST(NurbsEval, InsertKnotThenRebuildAsInARealScene) {
    // A cigarette: a cylinder with two knots inserted near its top, rebuilt uniformly to 4 × 4
    // spans over 0 to 1 (7 × 7 CVs), then a tweak on one CV of the shape.
    const char* text = R"(createNode transform -n "cig";
createNode nurbsSurface -n "cigShape" -p "cig";
	setAttr ".tw" yes;
	setAttr ".cp[24]" -type "double3" 0 0.5 0;
createNode rebuildSurface -n "rebuildSurface1";
	setAttr ".end" 1;
	setAttr ".kc" no;
	setAttr ".kr" 0;
createNode insertKnotSurface -n "insertKnotSurface1";
	setAttr -s 2 ".p[0:1]"  1.9602509296549 1.9792133934038001;
	setAttr -s 2 ".nk[0:1]"  1 1;
createNode makeNurbCylinder -n "makeNurbCylinder1";
	setAttr ".ax" -type "double3" 0 1 0 ;
	setAttr ".s" 11;
	setAttr ".nsp" 4;
connectAttr "rebuildSurface1.os" "cigShape.cr";
connectAttr "insertKnotSurface1.os" "rebuildSurface1.is";
connectAttr "makeNurbCylinder1.os" "insertKnotSurface1.is";
)";
    Graph g = MaReader::readString(text, "cig.ma");
    Evaluator ev(g, 1.0);
    std::string reason, note;
    auto s = evaluateNurbsSurface(ev, g.find("cigShape"), &reason, &note);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_EQ(s->cvCountU(), 7);
    EXPECT_EQ(s->cvCountV(), 7);
    EXPECT_EQ(s->formV(), geom::NurbsForm::Periodic);
    EXPECT_NEAR(s->uMin(), 0.0, 1e-12);
    EXPECT_NEAR(s->uMax(), 1.0, 1e-12);
    EXPECT_NE(note.find("interpolation"), std::string::npos) << note;
    // Still a cylinder of radius 1 from y = -1 to 1 (up to the fit), apart from near the tweaked CV.
    double worst = 0.0;
    for (int i = 0; i <= 10; ++i) {
        const glm::dvec3 q = s->point(0.05 * i, 0.0);
        worst = std::max(worst, std::abs(std::hypot(q.x, q.z) - 1.0));
    }
    EXPECT_LT(worst, 0.02);
    EXPECT_NEAR(s->point(0.0, 0.0).y, -1.0, 1e-6);
    EXPECT_NEAR(s->point(1.0, 0.0).y, 1.0, 1e-6);
    // The shape's relative tweak moves CV (3, 3) (controlPoints[3 · 7 + 3]) and no other.
    std::string untweaked = text;
    untweaked.replace(untweaked.find("\tsetAttr \".tw\" yes;\n"), 21, "");
    Graph plain = MaReader::readString(untweaked, "plain.ma");
    Evaluator ev2(plain, 1.0);
    auto base = evaluateNurbsSurface(ev2, plain.find("cigShape"), &reason);
    ASSERT_TRUE(base.has_value()) << reason;
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 7; ++j) {
            const glm::dvec3 d = s->cvPoint(i, j) - base->cvPoint(i, j);
            EXPECT_NEAR(glm::length(d - (i == 3 && j == 3 ? glm::dvec3(0, 0.5, 0) : glm::dvec3(0.0))), 0.0, 1e-12) << i << " " << j;
        }
}

TEST(NurbsEval, ExtrudeAlongAPathOrByADistance) {
    // A unit circle in the XZ plane extruded as a tube along a stored straight path up to y = 5.
    const char* text = R"(createNode transform -n "path";
createNode nurbsCurve -n "pathShape" -p "path";
	setAttr ".cc" -type "nurbsCurve"
		1 1 0 no 3
		2 0 1
		2
		0 0 0
		0 5 0;
createNode makeNurbCircle -n "makeNurbCircle1";
	setAttr ".nr" -type "double3" 0 1 0 ;
createNode extrude -n "extrude1";
	setAttr ".fpt" yes;
createNode transform -n "pipe";
createNode nurbsSurface -n "pipeShape" -p "pipe";
connectAttr "makeNurbCircle1.oc" "extrude1.pr";
connectAttr "pathShape.ws" "extrude1.pt";
connectAttr "extrude1.os" "pipeShape.cr";
)";
    Graph g = MaReader::readString(text, "pipe.ma");
    {
        Evaluator ev(g, 1.0);
        std::string reason, note;
        auto s = evaluateNurbsSurface(ev, g.find("pipeShape"), &reason, &note);
        ASSERT_TRUE(s.has_value()) << reason;
        EXPECT_NE(note.find("approximated"), std::string::npos) << note;
        for (double f : {0.0, 0.3, 1.0}) {
            const glm::dvec3 q = s->point(s->uMin() + f * (s->uMax() - s->uMin()), s->vMin());
            EXPECT_NEAR(q.y, 5.0 * f, 1e-6);
            EXPECT_NEAR(std::hypot(q.x, q.z), 1.0, 1e-6);  // the circle's CV 1 point, on the circle
        }
    }
    // By a distance: 3 along -Z, with a rotation that is reported as not applied.
    std::string distance = text;
    distance.replace(distance.find("\tsetAttr \".fpt\" yes;"), 20,
                     "\tsetAttr \".et\" 0;\n\tsetAttr \".d\" -type \"double3\" 0 0 -1 ;\n\tsetAttr \".l\" 3;\n\tsetAttr \".ro\" 45;");
    g = MaReader::readString(distance, "distance.ma");
    Evaluator ev(g, 1.0);
    std::string reason, note;
    auto s = evaluateNurbsSurface(ev, g.find("pipeShape"), &reason, &note);
    ASSERT_TRUE(s.has_value()) << reason;
    EXPECT_NE(note.find("rotation not applied"), std::string::npos) << note;
    EXPECT_NEAR(s->point(1.0, s->vMin()).z - s->point(0.0, s->vMin()).z, -3.0, 1e-9);
}

TEST(NurbsEval, ACircleShapeTakesItsRelativeControlPointTweaks) {
    const char* text = R"(createNode transform -n "ring";
createNode nurbsCurve -n "ringShape" -p "ring";
	setAttr ".tw" yes;
	setAttr ".cp[4]" -type "double3" 0 0 2 ;
createNode makeNurbCircle -n "makeNurbCircle1";
connectAttr "makeNurbCircle1.oc" "ringShape.cr";
)";
    Graph g = MaReader::readString(text, "ring.ma");
    Evaluator ev(g, 1.0);
    std::string reason;
    auto c = evaluateNurbsCurve(ev, g.find("ringShape"), &reason);
    ASSERT_TRUE(c.has_value()) << reason;
    auto plain = geom::makeNurbCircle({}, nullptr);
    ASSERT_TRUE(plain);
    for (int i = 0; i < c->cvCount(); ++i) {
        const glm::dvec3 d = glm::dvec3(c->cvs()[size_t(i)]) - glm::dvec3(plain->cvs()[size_t(i)]);
        EXPECT_NEAR(glm::length(d - (i == 4 ? glm::dvec3(0, 0, 2) : glm::dvec3(0.0))), 0.0, 1e-12) << i;
    }
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

const char* kRevolveScene = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "curve1";
	setAttr ".t" -type "double3" 0 1 0 ;
createNode nurbsCurve -n "curveShape1" -p "curve1";
	setAttr ".cc" -type "nurbsCurve"
		1 1 0 no 3
		2 0 1
		2
		2 0 0
		2 3 0
		;
createNode transform -n "revolvedSurface1";
createNode nurbsSurface -n "revolvedSurfaceShape1" -p "revolvedSurface1";
createNode revolve -n "revolve1";
	setAttr ".ax" -type "double3" 0 1 0 ;
	setAttr ".esw" 180;
createNode nurbsTessellate -n "nurbsTessellate1";
	setAttr ".f" 2;
	setAttr ".pt" 1;
	setAttr ".un" 1;
	setAttr ".ucr" no;
connectAttr "curveShape1.ws" "revolve1.ic";
connectAttr "revolve1.os" "nurbsTessellate1.is";
connectAttr "revolve1.os" "revolvedSurfaceShape1.cr";
)";

TEST(NurbsEval, RevolveOfAWorldSpaceCurveTessellatesToAHalfCylinder) {
    Graph g = MaReader::readString(kRevolveScene, "revolve.ma");
    Evaluator ev(g, 1.0);
    std::string reason;
    std::vector<std::string> notes;
    auto mesh = evaluateNurbsTessellate(ev, g.find("nurbsTessellate1"), &reason, &notes);
    ASSERT_TRUE(mesh.has_value()) << reason;
    EXPECT_TRUE(mesh->validate().ok());
    // One linear span with uNumber 1: 2 segments; the default 8 sections with the default vNumber 3:
    // 4 segments each. A half sweep is open: both end rows stay.
    EXPECT_EQ(mesh->points.size(), size_t(3 * 33));
    EXPECT_EQ(mesh->faceCount(), size_t(2 * 32));
    for (const glm::vec3& p : mesh->points) {
        EXPECT_NEAR(std::hypot(p.x, p.z), 2.0, 0.006);
        EXPECT_GE(p.z, -1e-6);  // +X turns towards +Z
        EXPECT_GE(p.y, 1.0 - 1e-6);  // worldSpace: the curve's translation applies
        EXPECT_LE(p.y, 4.0 + 1e-6);
    }
    EXPECT_NEAR(mesh->points.front().y, 1.0, 1e-6);
    EXPECT_NEAR(mesh->points[2].y, 4.0, 1e-6);  // u varies fastest

    auto surface = evaluateNurbsSurface(ev, g.find("revolvedSurfaceShape1"), &reason);
    ASSERT_TRUE(surface.has_value()) << reason;
    EXPECT_NEAR(glm::length(surface->point(0.0, surface->vMax()) - glm::dvec3(-2, 1, 0)), 0.0, 1e-12);

    // Through `local` the curve stays in object space.
    Graph local = MaReader::readString(kRevolveScene, "revolve.ma");
    const NodeId rev = local.find("revolve1");
    const NodeId curve = local.find("curveShape1");
    for (const Connection* c : local.inputs(rev)) local.disconnect(c->src, c->dst);
    connect(local, curve, "l", rev, "ic");
    Evaluator ev2(local, 1.0);
    auto objectSpace = evaluateNurbsTessellate(ev2, local.find("nurbsTessellate1"), &reason, nullptr);
    ASSERT_TRUE(objectSpace.has_value()) << reason;
    EXPECT_NEAR(objectSpace->points.front().y, 0.0, 1e-6);
    EXPECT_NEAR(objectSpace->points[2].y, 3.0, 1e-6);
}

TEST(NurbsEval, LoftOfThreeCurvesTessellatesInMayasGrid) {
    const char* text = R"(//Maya ASCII 2018 scene
requires maya "2018";
currentUnit -l centimeter -a degree -t film;
createNode transform -n "c0";
createNode nurbsCurve -n "cs0" -p "c0";
	setAttr ".cc" -type "nurbsCurve"
		3 2 0 no 3
		7 0 0 0 1 2 2 2
		5
		0 0 0  0.5 0.2 0  1 0 0  1.5 -0.2 0  2 0 0
		;
createNode transform -n "c1";
	setAttr ".t" -type "double3" 0 0 1 ;
createNode nurbsCurve -n "cs1" -p "c1";
	setAttr ".cc" -type "nurbsCurve"
		3 2 0 no 3
		7 0 0 0 1 2 2 2
		5
		0 0 0  0.5 0.5 0  1 0.3 0  1.5 0.1 0  2 0 0
		;
createNode transform -n "c2";
	setAttr ".t" -type "double3" 0 0 3 ;
createNode nurbsCurve -n "cs2" -p "c2";
	setAttr ".cc" -type "nurbsCurve"
		3 2 0 no 3
		7 0 0 0 1 2 2 2
		5
		0 0 0  0.5 0 0  1 0 0  1.5 0 0  2 0 0
		;
createNode loft -n "loft1";
	setAttr -s 3 ".ic";
	setAttr ".u" yes;
	setAttr ".rsn" yes;
createNode nurbsTessellate -n "nurbsTessellate1";
	setAttr ".f" 2;
	setAttr ".pt" 1;
	setAttr ".un" 5;
	setAttr ".ucr" no;
connectAttr "cs0.ws" "loft1.ic[0]";
connectAttr "cs2.ws" "loft1.ic[2]";
connectAttr "cs1.ws" "loft1.ic[1]";
connectAttr "loft1.os" "nurbsTessellate1.is";
)";
    Graph g = MaReader::readString(text, "loft.ma");
    Evaluator ev(g, 1.0);
    std::string reason;
    auto mesh = evaluateNurbsTessellate(ev, g.find("nurbsTessellate1"), &reason, nullptr);
    ASSERT_TRUE(mesh.has_value()) << reason;
    EXPECT_TRUE(mesh->validate().ok());
    // reverseSurfaceNormals: U runs along the curves (2 spans x 6 segments), V across them (2 spans x
    // 4 segments), u fastest.
    const size_t m = 13, n = 9;
    ASSERT_EQ(mesh->points.size(), m * n);
    EXPECT_EQ(mesh->faceCount(), (m - 1) * (n - 1));
    // Row 4 (v = 1) is the middle curve, in world space; rows 0 and 8 the outer curves.
    std::string err;
    for (int k = 0; k < 3; ++k) {
        auto c = evaluateNurbsCurve(ev, g.find("cs" + std::to_string(k)), &err);
        ASSERT_TRUE(c.has_value()) << err;
        const double z[3] = {0, 1, 3};
        for (size_t i = 0; i < m; ++i) {
            const glm::dvec3 expected = c->point(2.0 * double(i) / double(m - 1)) + glm::dvec3(0, 0, z[k]);
            EXPECT_NEAR(glm::length(glm::dvec3(mesh->points[size_t(4 * k) * m + i]) - expected), 0.0, 1e-6) << k << " " << i;
        }
    }
}

TEST(NurbsEval, TessellateInputsThatCannotBeEvaluatedGiveAReason) {
    Graph g = MaReader::readString(kRevolveScene, "revolve.ma");
    const NodeId rev = g.find("revolve1");
    const NodeId tess = g.find("nurbsTessellate1");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    {
        setNumbers(g, rev, ".esw", {nan});
        Evaluator ev(g, 1.0);
        std::string reason;
        EXPECT_FALSE(evaluateNurbsTessellate(ev, tess, &reason, nullptr).has_value());
        EXPECT_NE(reason.find("revolve"), std::string::npos) << reason;
        // The shape has no cached surface to fall back on.
        EXPECT_FALSE(evaluateNurbsSurface(ev, g.find("revolvedSurfaceShape1"), &reason).has_value());
        EXPECT_FALSE(reason.empty());
        setNumbers(g, rev, ".esw", {std::numbers::pi});
    }
    {
        setNumbers(g, tess, ".un", {nan});
        Evaluator ev(g, 1.0);
        std::string reason;
        EXPECT_FALSE(evaluateNurbsTessellate(ev, tess, &reason, nullptr).has_value());
        EXPECT_NE(reason.find("uNumber"), std::string::npos) << reason;
        setNumbers(g, tess, ".un", {1});
        Evaluator ok(g, 1.0);
        EXPECT_TRUE(evaluateNurbsTessellate(ok, tess, &reason, nullptr).has_value()) << reason;
    }
    {
        const NodeId lonely = g.createNode("nurbsTessellate", "nurbsTessellate9");
        Evaluator ev(g, 1.0);
        std::string reason;
        EXPECT_FALSE(evaluateNurbsTessellate(ev, lonely, &reason, nullptr).has_value());
        EXPECT_NE(reason.find("no input surface"), std::string::npos) << reason;
        const NodeId iso = g.createNode("curveFromSurfaceIso", "curveFromSurfaceIso1");
        for (const Connection* c : g.inputs(rev)) g.disconnect(c->src, c->dst);
        connect(g, iso, "oc", rev, "ic");
        Evaluator ev2(g, 1.0);
        EXPECT_FALSE(evaluateNurbsTessellate(ev2, tess, &reason, nullptr).has_value());
        EXPECT_NE(reason.find("curveFromSurfaceIso"), std::string::npos) << reason;
    }
}

TEST(NurbsEval, PotSceneTessellatesItsRevolveAndLoft) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const fs::path file = test::maCorpusDir() / "Logna-Logo__Essentials__pot.ma";
    ASSERT_TRUE(fs::exists(file)) << file;
    Graph g = MaReader::readFile(file);
    Evaluator ev(g, 1.0);
    for (const char* name : {"nurbsTessellate1", "nurbsTessellate2"}) {
        std::string reason;
        std::vector<std::string> notes;
        auto mesh = evaluateNurbsTessellate(ev, g.find(name), &reason, &notes);
        ASSERT_TRUE(mesh.has_value()) << name << ": " << reason;
        EXPECT_TRUE(mesh->validate().ok()) << name;
        std::printf("[ measure  ] pot %s: %zu vertices, %zu faces, %zu notes\n", name, mesh->points.size(),
                    mesh->faceCount(), notes.size());
        for (const glm::vec3& p : mesh->points) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    }
    // The loft's mesh (2 x 2 spans, uNumber 5): the polyTweak after it moves vertices 54..57 and the
    // deleteComponents remove faces 38..40, one row of three quads and the four vertices on its far
    // side in a 13-vertex-wide grid.
    std::string reason;
    auto loft = evaluateNurbsTessellate(ev, g.find("nurbsTessellate2"), &reason, nullptr);
    ASSERT_TRUE(loft.has_value()) << reason;
    ASSERT_EQ(loft->points.size(), size_t(13 * 9));
    for (uint32_t f = 38; f <= 40; ++f) {
        const auto loop = loft->faceOuterLoop(f);
        ASSERT_EQ(loop.size(), 4u);
        EXPECT_EQ(loop[2], f + 17);  // the far corners of faces 38..40 are vertices 55..57
        EXPECT_EQ(loop[3], f + 16);
    }
    // The revolve: every vertex keeps the distance from the axis (+Y through the pivot) that the
    // profile has at the same height, and the first vertex row is the world-space profile.
    auto revolved = evaluateNurbsTessellate(ev, g.find("nurbsTessellate1"), &reason, nullptr);
    ASSERT_TRUE(revolved.has_value()) << reason;
    auto profile = evaluateNurbsCurve(ev, g.find("curveShape1"), &reason);
    ASSERT_TRUE(profile.has_value()) << reason;
    const glm::dvec3 p0 = profile->point(profile->tMin()) + glm::dvec3(0, 0.11710513427848745, 0);
    EXPECT_NEAR(glm::length(glm::dvec3(revolved->points[0]) - p0), 0.0, 1e-5);
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
