// Tests for core/shade/shading_network.h: materials against their closed forms (materials.cpp
// documents the formulas), connected networks, constants read at the frame, and every note the
// compiler writes for scenes it cannot evaluate fully. Scenes are .ma text read by MaReader.
#include "core/shade/shading_network.h"

#include "core/scene/ma_reader.h"

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace pushpin::shade {
namespace {

using scene::Evaluator;
using scene::Graph;
using scene::MaReader;
using scene::NodeId;

constexpr double kDeg = std::numbers::pi / 180.0;

Graph read(const std::string& text) { return MaReader::readString(text, "test.ma"); }

// A batch of `count` samples on the front half of a unit sphere centred at (0, 0, −5), seen from
// the camera at the origin: normals face the eye, rays run eye → point.
std::unique_ptr<ShadingBatch> sphereBatch(int count) {
    auto b = std::make_unique<ShadingBatch>();
    *b = ShadingBatch{};
    b->count = count;
    for (int i = 0; i < kBatchSize; ++i) {
        const double theta = (0.05 + 0.85 * double(i % 8) / 8.0) * (std::numbers::pi / 2);
        const double phi = 2.0 * std::numbers::pi * double(i) / double(kBatchSize) * 3.0;
        const glm::dvec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        const glm::dvec3 p = glm::dvec3(0, 0, -5) + n;
        const glm::dvec3 r = glm::normalize(p);
        b->px[i] = float(p.x), b->py[i] = float(p.y), b->pz[i] = float(p.z);
        b->nx[i] = b->gx[i] = float(n.x), b->ny[i] = b->gy[i] = float(n.y), b->nz[i] = b->gz[i] = float(n.z);
        b->rx[i] = float(r.x), b->ry[i] = float(r.y), b->rz[i] = float(r.z);
        b->u[i] = float(i) / kBatchSize;
        b->v[i] = 1.0f - float(i) / kBatchSize;
        b->flipped[i] = uint8_t(i % 3 == 0);
    }
    return b;
}

// One sample at the origin facing the eye straight on (N = V = +Z), for highlight tests.
std::unique_ptr<ShadingBatch> headOnBatch() {
    auto b = sphereBatch(1);
    b->px[0] = b->py[0] = 0.0f, b->pz[0] = -5.0f;
    b->nx[0] = b->ny[0] = 0.0f, b->nz[0] = 1.0f;
    b->rx[0] = b->ry[0] = 0.0f, b->rz[0] = -1.0f;
    return b;
}

Light directional(glm::dvec3 towardLight, glm::vec3 color = glm::vec3(1.0f)) {
    Light l;
    l.type = LightType::Directional;
    l.direction = -glm::normalize(towardLight);
    l.color = color;
    return l;
}

// Compiles `root` in `g` at `frame` and evaluates it over `batch`.
struct Shaded {
    std::shared_ptr<const ShadingNetwork> net;
    std::vector<std::string> notes;
    std::unique_ptr<ShadingResult> out = std::make_unique<ShadingResult>();
};

Shaded shade(const Graph& g, const char* root, const ShadingBatch& batch, std::vector<Light> lights = {},
          double frame = 1.0) {
    Shaded r;
    Evaluator ev(g, frame);
    const NodeId id = root ? g.find(root) : scene::kNoNode;
    if (root) {
        EXPECT_NE(id, scene::kNoNode) << root;
    }
    r.net = ShadingNetwork::compile(ev, id, r.notes);
    ShadingScratch scratch;
    r.net->evaluate(batch, lights, scratch, *r.out);
    return r;
}

bool hasNote(const std::vector<std::string>& notes, const std::string& part) {
    return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

int countNotes(const std::vector<std::string>& notes, const std::string& part) {
    return int(std::count_if(notes.begin(), notes.end(),
                             [&](const std::string& n) { return n.find(part) != std::string::npos; }));
}

std::string allNotes(const std::vector<std::string>& notes) {
    std::string s;
    for (const auto& n : notes) s += n + "\n";
    return s;
}

void expectColor(const ShadingResult& r, int i, glm::dvec3 want, double tol, const char* what = "") {
    EXPECT_NEAR(r.cr[i], want.x, tol) << what << " sample " << i << " r";
    EXPECT_NEAR(r.cg[i], want.y, tol) << what << " sample " << i << " g";
    EXPECT_NEAR(r.cb[i], want.z, tol) << what << " sample " << i << " b";
}

void expectTransparency(const ShadingResult& r, int i, glm::dvec3 want, double tol) {
    EXPECT_NEAR(r.tr[i], want.x, tol) << "sample " << i;
    EXPECT_NEAR(r.tg[i], want.y, tol) << "sample " << i;
    EXPECT_NEAR(r.tb[i], want.z, tol) << "sample " << i;
}

glm::dvec3 normalOf(const ShadingBatch& b, int i) { return {b.nx[i], b.ny[i], b.nz[i]}; }

const char* kLambert = R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 0.2 0.4 0.6;
	setAttr ".dc" 0.7;
)";

TEST(ShadingNetwork, LambertSphereUnderDirectionalLightMatchesClosedForm) {
    const Graph g = read(kLambert);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(1, 1, 2));
    const glm::dvec3 color(1.0, 0.8, 0.5);
    for (int count : {1, 17, kBatchSize}) {
        auto b = sphereBatch(count);
        Shaded r = shade(g, "mat", *b, {directional(toLight, color)});
        EXPECT_TRUE(r.notes.empty()) << allNotes(r.notes);
        EXPECT_EQ(r.net->nodeCount(), 1u);
        EXPECT_EQ(r.net->rootName(), "mat");
        for (int i = 0; i < count; ++i) {
            const double k = 0.7 * std::max(0.0, glm::dot(normalOf(*b, i), toLight));
            expectColor(*r.out, i, glm::dvec3(0.2, 0.4, 0.6) * color * k, 1e-5);
            expectTransparency(*r.out, i, {0, 0, 0}, 0);
        }
    }
}

TEST(ShadingNetwork, LambertSumsLightsAndIgnoresNonDiffuseOnes) {
    const Graph g = read(kLambert);
    auto b = sphereBatch(kBatchSize);
    const glm::dvec3 l1 = glm::normalize(glm::dvec3(1, 0, 1)), l2 = glm::normalize(glm::dvec3(-1, 1, 1));
    Light specularOnly = directional({0, 0, 1}, glm::vec3(5.0f));
    specularOnly.emitDiffuse = false;
    Shaded r = shade(g, "mat", *b, {directional(l1), directional(l2, glm::vec3(0.5f)), specularOnly});
    for (int i = 0; i < kBatchSize; ++i) {
        const glm::dvec3 n = normalOf(*b, i);
        const double k = 0.7 * (std::max(0.0, glm::dot(n, l1)) + 0.5 * std::max(0.0, glm::dot(n, l2)));
        expectColor(*r.out, i, glm::dvec3(0.2, 0.4, 0.6) * k, 1e-5);
    }
}

TEST(ShadingNetwork, AmbientLightAmbientColorIncandescenceAndTransparency) {
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 0.5 0.5 1;
	setAttr ".it" -type "float3" 0.25 0.5 0;
	setAttr ".ambc" -type "float3" 0.1 0.2 0.3;
	setAttr ".ic" -type "float3" 0.05 0 0.01;
)");
    auto b = sphereBatch(kBatchSize);
    Light amb;
    amb.type = LightType::Ambient;
    amb.position = {0, 0, 0};
    amb.color = {0.6f, 0.6f, 0.6f};
    amb.ambientShade = 0.45f;
    Shaded r = shade(g, "mat", *b, {amb});
    EXPECT_TRUE(r.net->mayBeTransparent());
    for (int i = 0; i < kBatchSize; ++i) {
        const glm::dvec3 p(b->px[i], b->py[i], b->pz[i]);
        const glm::dvec3 l = glm::normalize(-p);
        const double shade = 0.55 + 0.45 * std::max(0.0, glm::dot(normalOf(*b, i), l));
        const glm::dvec3 a = glm::dvec3(0.1, 0.2, 0.3) + glm::dvec3(0.6 * shade);
        const glm::dvec3 want = glm::dvec3(0.5, 0.5, 1.0) * a * glm::dvec3(0.75, 0.5, 1.0) + glm::dvec3(0.05, 0, 0.01);
        expectColor(*r.out, i, want, 1e-5);
        expectTransparency(*r.out, i, {0.25, 0.5, 0}, 1e-7);
    }
}

TEST(ShadingNetwork, NoLightsLeaveIncandescenceAndAmbientColor) {
    const Graph g = read(R"(createNode blinn -n "mat";
	setAttr ".c" -type "float3" 0.5 0.25 1;
	setAttr ".ambc" -type "float3" 0.2 0.2 0.2;
	setAttr ".ic" -type "float3" 0 0.1 0.3;
)");
    auto b = sphereBatch(kBatchSize);
    Shaded r = shade(g, "mat", *b, {});
    for (int i = 0; i < kBatchSize; ++i) expectColor(*r.out, i, {0.1, 0.05 + 0.1, 0.2 + 0.3}, 1e-6);
    EXPECT_FALSE(r.net->mayBeTransparent());
}

TEST(ShadingNetwork, PhongPeakAndFalloffFollowCosinePower) {
    const Graph g = read(R"(createNode phong -n "mat";
	setAttr ".c" -type "float3" 0 0 0;
	setAttr ".sc" -type "float3" 1 0.5 0.25;
	setAttr ".cp" 30;
)");
    auto b = headOnBatch();
    for (double alpha : {0.0, 5.0, 10.0, 20.0, 60.0}) {
        // L at alpha from N = V: R·V = cos(alpha).
        const glm::dvec3 l(std::sin(alpha * kDeg), 0, std::cos(alpha * kDeg));
        Shaded r = shade(g, "mat", *b, {directional(l, glm::vec3(2.0f))});
        const double s = 2.0 * std::pow(std::cos(alpha * kDeg), 30.0);
        expectColor(*r.out, 0, glm::dvec3(1, 0.5, 0.25) * s, 1e-5, "phong");
    }
    // Light behind the surface: no highlight.
    Shaded back = shade(g, "mat", *b, {directional({0, 0, -1})});
    expectColor(*back.out, 0, {0, 0, 0}, 0);
}

// The Blinn 1977 highlight (materials.cpp) computed independently in double precision.
double blinnSpec(glm::dvec3 n, glm::dvec3 v, glm::dvec3 l, double c, double sro) {
    const glm::dvec3 h = glm::normalize(l + v);
    const double nh = glm::dot(n, h), nv = glm::dot(n, v), nl = glm::dot(n, l), vh = glm::dot(v, h);
    const double c2 = c * c;
    const double d = std::pow(c2 / (nh * nh * (c2 - 1.0) + 1.0), 2.0);
    const double gterm = std::min({1.0, 2 * nh * nv / vh, 2 * nh * nl / vh});
    const double f = sro + (1.0 - sro) * std::pow(1.0 - vh, 5.0);
    return d * gterm * f / std::max(nv, 1e-4);
}

TEST(ShadingNetwork, BlinnPeakAndFalloffFollowTheMicrofacetModel) {
    const Graph g = read(R"(createNode blinn -n "mat";
	setAttr ".c" -type "float3" 0 0 0;
)");  // eccentricity 0.3, specularRollOff 0.7, specularColor 0.5 (defaults)
    auto b = headOnBatch();
    const glm::dvec3 n(0, 0, 1), v(0, 0, 1);
    Shaded peak = shade(g, "mat", *b, {directional(v)});
    expectColor(*peak.out, 0, glm::dvec3(0.5 * 0.7), 1e-5, "peak: D = G = 1, F = sro");
    double previous = 1e9;
    for (double alpha : {10.0, 20.0, 40.0, 70.0}) {
        const glm::dvec3 l(std::sin(alpha * kDeg), 0, std::cos(alpha * kDeg));
        Shaded r = shade(g, "mat", *b, {directional(l)});
        const double s = 0.5 * blinnSpec(n, v, l, 0.3, 0.7);
        expectColor(*r.out, 0, glm::dvec3(s), 1e-5, "blinn");
        EXPECT_LT(r.out->cr[0], previous) << "falls off with angle";
        previous = r.out->cr[0];
    }
    // An oblique view, so G and F are not trivial.
    auto ob = headOnBatch();
    const glm::dvec3 view = glm::normalize(glm::dvec3(0, 0.6, 0.8));
    ob->rx[0] = float(-view.x), ob->ry[0] = float(-view.y), ob->rz[0] = float(-view.z);
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    Shaded r = shade(g, "mat", *ob, {directional(l)});
    expectColor(*r.out, 0, glm::dvec3(0.5 * blinnSpec(n, view, l, 0.3, 0.7)), 1e-5, "oblique");

    const Graph none = read(R"(createNode blinn -n "mat";
	setAttr ".c" -type "float3" 0 0 0;
	setAttr ".ec" 0;
)");
    Shaded flat = shade(none, "mat", *b, {directional(v)});
    expectColor(*flat.out, 0, {0, 0, 0}, 0, "eccentricity 0: no highlight");
}

TEST(ShadingNetwork, PhongEUsesRoughnessHighlightSizeAndWhiteness) {
    const Graph g = read(R"(createNode phongE -n "mat";
	setAttr ".c" -type "float3" 0 0 0;
	setAttr ".wn" -type "float3" 1 0.5 0.5;
)");  // roughness 0.5, highlightSize 0.5: exponent 1 / (0.25 · 0.5) = 8
    auto b = headOnBatch();
    for (double alpha : {0.0, 30.0}) {
        const glm::dvec3 l(std::sin(alpha * kDeg), 0, std::cos(alpha * kDeg));
        const double nh = glm::normalize(l + glm::dvec3(0, 0, 1)).z;
        Shaded r = shade(g, "mat", *b, {directional(l)});
        const double s = std::pow(nh, 8.0);
        expectColor(*r.out, 0, glm::dvec3(0.5, 0.25, 0.25) * s, 1e-5, "phongE");
    }
}

TEST(ShadingNetwork, SurfaceShaderPassesColourThroughUnlit) {
    const Graph g = read(R"(createNode surfaceShader -n "ss";
	setAttr ".oc" -type "float3" 0.3 0.6 0.9;
	setAttr ".ot" -type "float3" 0.1 0.2 0.3;
)");
    auto b = sphereBatch(kBatchSize);
    Shaded r = shade(g, "ss", *b, {directional({0, 0, 1}, glm::vec3(10.0f))});
    for (int i = 0; i < kBatchSize; ++i) {
        expectColor(*r.out, i, {0.3, 0.6, 0.9}, 1e-7);
        expectTransparency(*r.out, i, {0.1, 0.2, 0.3}, 1e-7);
    }
    EXPECT_TRUE(r.net->mayBeTransparent());
    const Graph opaque = read("createNode surfaceShader -n \"ss\";\n");
    EXPECT_FALSE(shade(opaque, "ss", *b).net->mayBeTransparent());
}

TEST(ShadingNetwork, NoShaderIsBlackAndOpaque) {
    const Graph g = read(kLambert);
    auto b = sphereBatch(kBatchSize);
    Shaded r = shade(g, nullptr, *b, {directional({0, 0, 1})});
    EXPECT_EQ(r.net->nodeCount(), 0u);
    EXPECT_FALSE(r.net->mayBeTransparent());
    for (int i = 0; i < kBatchSize; ++i) {
        expectColor(*r.out, i, {0, 0, 0}, 0);
        expectTransparency(*r.out, i, {0, 0, 0}, 0);
    }
}

TEST(ShadingNetwork, FacingRatioThroughReverseDrivesLambertColor) {
    // Short names on reverse (a type without a schema) as Maya writes them.
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".dc" 1;
createNode samplerInfo -n "info";
createNode reverse -n "rev";
connectAttr "info.fr" "rev.ix";
connectAttr "info.fr" "rev.iy";
connectAttr "info.fr" "rev.iz";
connectAttr "rev.o" "mat.c";
)");
    auto b = sphereBatch(kBatchSize);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.2, 0.1, 1));
    Shaded r = shade(g, "mat", *b, {directional(toLight)});
    EXPECT_TRUE(r.notes.empty()) << allNotes(r.notes);
    EXPECT_EQ(r.net->nodeCount(), 3u);
    for (int i = 0; i < kBatchSize; ++i) {
        const glm::dvec3 n = normalOf(*b, i), ray(b->rx[i], b->ry[i], b->rz[i]);
        const double facing = std::max(0.0, -glm::dot(n, ray));
        const double want = (1.0 - facing) * std::max(0.0, glm::dot(n, toLight));
        expectColor(*r.out, i, glm::dvec3(want), 1e-5);
    }
}

TEST(ShadingNetwork, ColourComponentFeedsFloatInputAndFloatBroadcastsToColour) {
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 1 1 1;
createNode multiplyDivide -n "md";
	setAttr ".i1" -type "float3" 0.1 0.4 0.9;
	setAttr ".i2" -type "float3" 2 0.5 1;
createNode luminance -n "lum";
createNode blendColors -n "bc";
connectAttr "md.oy" "mat.dc";
connectAttr "bc.op" "lum.v";
connectAttr "lum.o" "mat.ambc";
)");  // blendColors defaults: red·0.5 + blue·0.5 → luminance 0.3·0.5 + 0.11·0.5 = 0.205
    auto b = sphereBatch(8);
    Shaded r = shade(g, "mat", *b, {directional({0, 0, 1})});
    EXPECT_TRUE(r.notes.empty()) << allNotes(r.notes);
    for (int i = 0; i < 8; ++i) {
        const double k = 0.2 * std::max(0.0, normalOf(*b, i).z) + 0.205;
        expectColor(*r.out, i, glm::dvec3(k), 1e-5);
    }
}

TEST(ShadingNetwork, SamplerInfoOutputsCarryRendererValues) {
    const Graph g = read(R"(createNode surfaceShader -n "ss";
createNode samplerInfo -n "info";
connectAttr "info.u" "ss.ocr";
connectAttr "info.v" "ss.ocg";
connectAttr "info.fn" "ss.ocb";
connectAttr "info.n" "ss.ot";
)");
    auto b = sphereBatch(kBatchSize);
    Shaded r = shade(g, "ss", *b);
    EXPECT_TRUE(r.net->mayBeTransparent());
    for (int i = 0; i < kBatchSize; ++i) {
        expectColor(*r.out, i, {b->u[i], b->v[i], b->flipped[i] ? 1.0 : 0.0}, 0);
        expectTransparency(*r.out, i, normalOf(*b, i), 0);
    }
}

TEST(ShadingNetwork, ConnectedNormalIsRenormalised) {
    // multiplyDivide scales the renderer normal by 3 (pointing the same way).
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 1 1 1;
	setAttr ".dc" 1;
createNode samplerInfo -n "info";
createNode multiplyDivide -n "md";
	setAttr ".i2" -type "float3" 3 3 3;
connectAttr "info.n" "md.i1";
connectAttr "md.o" "mat.n";
)");
    auto b = sphereBatch(kBatchSize);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(1, 1, 1));
    Shaded r = shade(g, "mat", *b, {directional(toLight)});
    for (int i = 0; i < kBatchSize; ++i)
        expectColor(*r.out, i, glm::dvec3(std::max(0.0, glm::dot(normalOf(*b, i), toLight))), 1e-5);
}

TEST(ShadingNetwork, AnimatedAttributeIsReadAtTheFrame) {
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 1 1 1;
createNode animCurveTU -n "mat_diffuse";
	setAttr ".tan" 2;
	setAttr ".wgt" no;
	setAttr -s 2 ".ktv[0:1]"  1 0.2 11 0.7;
createNode animCurveTU -n "mat_colorG";
	setAttr ".tan" 2;
	setAttr ".wgt" no;
	setAttr -s 2 ".ktv[0:1]"  1 1 11 0;
connectAttr "mat_diffuse.o" "mat.dc";
connectAttr "mat_colorG.o" "mat.cg";
)");
    auto b = headOnBatch();
    for (double frame : {1.0, 6.0, 11.0}) {
        Shaded r = shade(g, "mat", *b, {directional({0, 0, 1})}, frame);
        EXPECT_TRUE(r.notes.empty()) << allNotes(r.notes);
        const double t = (frame - 1.0) / 10.0;
        const double diffuse = 0.2 + 0.5 * t;
        expectColor(*r.out, 0, {diffuse, diffuse * (1.0 - t), diffuse}, 1e-5);
    }
}

TEST(ShadingNetwork, UnitConversionOfAFrameValueIsAConstant) {
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".c" -type "float3" 1 1 1;
createNode animCurveTU -n "curve";
	setAttr ".tan" 2;
	setAttr ".wgt" no;
	setAttr -s 2 ".ktv[0:1]"  1 2 11 4;
createNode unitConversion -n "uc";
	setAttr ".cf" 0.25;
createNode samplerInfo -n "info";
createNode unitConversion -n "uc2";
connectAttr "curve.o" "uc.i";
connectAttr "uc.o" "mat.dc";
connectAttr "info.fr" "uc2.i";
connectAttr "uc2.o" "mat.ic";
)");
    auto b = headOnBatch();
    Shaded r = shade(g, "mat", *b, {directional({0, 0, 1})}, 1.0);
    expectColor(*r.out, 0, glm::dvec3(0.5), 1e-5);
    EXPECT_EQ(countNotes(r.notes, "unitConversion 'uc2' converts a per-sample"), 1) << allNotes(r.notes);
    EXPECT_FALSE(hasNote(r.notes, "'uc'")) << allNotes(r.notes);
}

TEST(ShadingNetwork, OtherLambertDerivedMaterialsAreShadedAsLambert) {
    const Graph g = read(R"(createNode anisotropic -n "mat";
	setAttr ".c" -type "float3" 0.2 0.4 0.6;
	setAttr ".dc" 0.7;
)");
    auto b = sphereBatch(kBatchSize);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(-1, 1, 2));
    Shaded r = shade(g, "mat", *b, {directional(toLight)});
    EXPECT_EQ(countNotes(r.notes, "material 'mat' (type anisotropic) is not supported"), 1) << allNotes(r.notes);
    for (int i = 0; i < kBatchSize; ++i)
        expectColor(*r.out, i, glm::dvec3(0.2, 0.4, 0.6) * 0.7 * std::max(0.0, glm::dot(normalOf(*b, i), toLight)), 1e-5);
}

TEST(ShadingNetwork, NonFiniteConstantIsReplacedByTheDefaultAndNoted) {
    Graph g = read(kLambert);
    const NodeId mat = g.find("mat");
    g.setValue(mat, *scene::parsePlugPath("dc"),
               scene::Numbers{scene::Numbers::Kind::Plain, 1, {std::numeric_limits<double>::quiet_NaN()}});
    g.setValue(mat, *scene::parsePlugPath("ic"),
               scene::Numbers{scene::Numbers::Kind::Tuple, 3, {0.0, std::numeric_limits<double>::infinity(), 0.0}});
    auto b = headOnBatch();
    Shaded r = shade(g, "mat", *b, {directional({0, 0, 1})});
    EXPECT_TRUE(hasNote(r.notes, "'mat.diffuse' is NaN")) << allNotes(r.notes);
    EXPECT_TRUE(hasNote(r.notes, "'mat.incandescenceG' is infinite")) << allNotes(r.notes);
    expectColor(*r.out, 0, glm::dvec3(0.2, 0.4, 0.6) * 0.8, 1e-5);  // default diffuse, incandescence 0
}

TEST(ShadingNetwork, UnknownNodeIsNotedOnceAndReadsItsStoredValue) {
    const Graph g = read(R"(createNode lambert -n "mat";
	setAttr ".dc" 1;
createNode aiNoise -n "tex";
	setAttr ".outColor" -type "float3" 0.1 0.2 0.3;
connectAttr "tex.outColor" "mat.c";
connectAttr "tex.outColor" "mat.ic";
)");
    auto b = headOnBatch();
    Shaded r = shade(g, "mat", *b, {directional({0, 0, 1})});
    EXPECT_EQ(countNotes(r.notes, "unsupported shading node 'tex' (type aiNoise)"), 1) << allNotes(r.notes);
    expectColor(*r.out, 0, glm::dvec3(0.1, 0.2, 0.3) * 2.0, 1e-5);
    EXPECT_EQ(r.net->nodeCount(), 1u);
}

TEST(ShadingNetwork, UnsupportedBumpKeepsTheRendererNormal) {
    // A stored normal on a node pushpin does not evaluate would be the same for every sample.
    const Graph g = read(std::string(kLambert) + R"(createNode bump2d -n "bump";
	setAttr ".o" -type "float3" 1 0 0;
connectAttr "bump.o" "mat.n";
)");
    auto b = sphereBatch(kBatchSize);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(1, -1, 1));
    Shaded r = shade(g, "mat", *b, {directional(toLight)});
    EXPECT_EQ(countNotes(r.notes, "unsupported shading node 'bump' (type bump2d)"), 1) << allNotes(r.notes);
    for (int i = 0; i < kBatchSize; ++i)
        expectColor(*r.out, i, glm::dvec3(0.2, 0.4, 0.6) * 0.7 * std::max(0.0, glm::dot(normalOf(*b, i), toLight)), 1e-5);
}

TEST(ShadingNetwork, UnknownRootIsNotedAndReadsItsStoredOutputs) {
    const Graph g = read(R"(createNode aiStandardSurface -n "ai";
	setAttr ".outColor" -type "float3" 0.5 0.25 0;
)");
    auto b = sphereBatch(4);
    Shaded r = shade(g, "ai", *b, {directional({0, 0, 1})});
    EXPECT_TRUE(hasNote(r.notes, "unsupported shading node 'ai' (type aiStandardSurface)")) << allNotes(r.notes);
    for (int i = 0; i < 4; ++i) expectColor(*r.out, i, {0.5, 0.25, 0}, 1e-7);
    EXPECT_FALSE(r.net->mayBeTransparent());
}

TEST(ShadingNetwork, CycleIsBrokenAndNoted) {
    const Graph g = read(R"(createNode surfaceShader -n "ss";
createNode reverse -n "a";
createNode reverse -n "b";
connectAttr "a.o" "b.i";
connectAttr "b.o" "a.i";
connectAttr "a.o" "ss.oc";
)");
    auto b = sphereBatch(4);
    Shaded r = shade(g, "ss", *b);
    EXPECT_TRUE(hasNote(r.notes, "connection cycle")) << allNotes(r.notes);
    EXPECT_EQ(r.net->nodeCount(), 3u);
    // a reads b, whose input (the cycle) reads its stored value 0: b = 1, a = 1 − 1 = 0.
    for (int i = 0; i < 4; ++i) expectColor(*r.out, i, {0, 0, 0}, 1e-7);
}

TEST(ShadingNetwork, UnmodelledInputAndOutputConnectionsAreNoted) {
    const Graph g = read(R"(createNode lambert -n "mat";
createNode lambert -n "other";
createNode samplerInfo -n "info";
connectAttr "info.fr" "mat.tc";
connectAttr "other.ogc" "mat.c";
)");
    auto b = headOnBatch();
    Shaded r = shade(g, "mat", *b);
    EXPECT_TRUE(hasNote(r.notes, "'mat.translucence' is not evaluated")) << allNotes(r.notes);
    EXPECT_TRUE(hasNote(r.notes, "output 'other.outGlowColor'")) << allNotes(r.notes);
}

TEST(ShadingNetwork, MayBeTransparentWhenTransparencyIsConnectedOrNonZero) {
    auto b = headOnBatch();
    EXPECT_FALSE(shade(read(kLambert), "mat", *b).net->mayBeTransparent());
    const Graph constant = read("createNode phong -n \"mat\";\n\tsetAttr \".itg\" 0.5;\n");
    EXPECT_TRUE(shade(constant, "mat", *b).net->mayBeTransparent());
    const Graph connected = read(R"(createNode lambert -n "mat";
createNode reverse -n "rev";
	setAttr ".i" -type "float3" 1 1 1;
connectAttr "rev.o" "mat.it";
)");
    Shaded r = shade(connected, "mat", *b);
    EXPECT_TRUE(r.net->mayBeTransparent());
    expectTransparency(*r.out, 0, {0, 0, 0}, 0);  // connected, even though it evaluates to 0
}

TEST(ShadingNetwork, UtilityNodesMatchTheirFormulas) {
    struct Case {
        const char* name;
        const char* nodes;   // creates "u" and wires its output into ss.oc
        glm::dvec3 want;
    };
    const Case cases[] = {
        {"multiply", "createNode multiplyDivide -n \"u\";\n\tsetAttr \".i1\" -type \"float3\" 1 2 3;\n"
                     "\tsetAttr \".i2\" -type \"float3\" 0.5 0.5 2;\nconnectAttr \"u.o\" \"ss.oc\";\n", {0.5, 1, 6}},
        {"divide", "createNode multiplyDivide -n \"u\";\n\tsetAttr \".op\" 2;\n\tsetAttr \".i1\" -type \"float3\" 1 2 3;\n"
                   "\tsetAttr \".i2\" -type \"float3\" 4 0 2;\nconnectAttr \"u.o\" \"ss.oc\";\n", {0.25, 0, 1.5}},
        {"power", "createNode multiplyDivide -n \"u\";\n\tsetAttr \".op\" 3;\n\tsetAttr \".i1\" -type \"float3\" 2 -1 9;\n"
                  "\tsetAttr \".i2\" -type \"float3\" 3 0.5 0.5;\nconnectAttr \"u.o\" \"ss.oc\";\n", {8, 0, 3}},
        {"clamp", "createNode clamp -n \"u\";\n\tsetAttr \".ip\" -type \"float3\" -1 0.5 3;\n"
                  "\tsetAttr \".mx\" -type \"float3\" 1 1 1;\nconnectAttr \"u.op\" \"ss.oc\";\n", {0, 0.5, 1}},
        {"condition", "createNode condition -n \"u\";\n\tsetAttr \".op\" 2;\n\tsetAttr \".ft\" 2;\n\tsetAttr \".st\" 1;\n"
                      "\tsetAttr \".ct\" -type \"float3\" 0.1 0.2 0.3;\nconnectAttr \"u.oc\" \"ss.oc\";\n", {0.1, 0.2, 0.3}},
        {"conditionFalse", "createNode condition -n \"u\";\n\tsetAttr \".op\" 4;\n\tsetAttr \".ft\" 2;\n\tsetAttr \".st\" 1;\n"
                           "connectAttr \"u.oc\" \"ss.oc\";\n", {1, 1, 1}},
        {"blendColors", "createNode blendColors -n \"u\";\n\tsetAttr \".b\" 0.25;\nconnectAttr \"u.op\" \"ss.oc\";\n",
         {0.25, 0, 0.75}},
        {"setRange", "createNode setRange -n \"u\";\n\tsetAttr \".v\" -type \"float3\" 5 0 10;\n"
                     "\tsetAttr \".n\" -type \"float3\" 0 1 0;\n\tsetAttr \".m\" -type \"float3\" 1 2 1;\n"
                     "\tsetAttr \".om\" -type \"float3\" 10 0 20;\nconnectAttr \"u.o\" \"ss.oc\";\n", {0.5, 1, 0.5}},
        {"gammaCorrect", "createNode gammaCorrect -n \"u\";\n\tsetAttr \".v\" -type \"float3\" 0.25 0.5 -1;\n"
                         "\tsetAttr \".g\" -type \"float3\" 2 1 2;\nconnectAttr \"u.o\" \"ss.oc\";\n", {0.5, 0.5, 0}},
        {"luminance", "createNode luminance -n \"u\";\n\tsetAttr \".v\" -type \"float3\" 1 0.5 0;\n"
                      "connectAttr \"u.o\" \"ss.oc\";\n", {0.595, 0.595, 0.595}},
        {"plusMinusSum", "createNode plusMinusAverage -n \"u\";\n\tsetAttr -s 2 \".i3\";\n"
                         "\tsetAttr \".i3[0]\" -type \"float3\" 1 2 3;\n\tsetAttr \".i3[2]\" -type \"float3\" 0.5 0.5 0.5;\n"
                         "connectAttr \"u.o3\" \"ss.oc\";\n", {1.5, 2.5, 3.5}},
        {"plusMinusSubtract", "createNode plusMinusAverage -n \"u\";\n\tsetAttr \".op\" 2;\n"
                              "\tsetAttr \".i3[0]\" -type \"float3\" 1 2 3;\n\tsetAttr \".i3[1]\" -type \"float3\" 0.5 0.5 0.5;\n"
                              "\tsetAttr \".i3[4].i3z\" 1;\nconnectAttr \"u.o3\" \"ss.oc\";\n", {0.5, 1.5, 1.5}},
        {"plusMinusAverage1D", "createNode plusMinusAverage -n \"u\";\n\tsetAttr \".op\" 3;\n"
                               "\tsetAttr -s 3 \".i1[0:2]\" 1 2 6;\nconnectAttr \"u.o1\" \"ss.oc\";\n", {3, 3, 3}},
    };
    auto b = sphereBatch(3);
    for (const Case& c : cases) {
        const Graph g = read(std::string("createNode surfaceShader -n \"ss\";\n") + c.nodes);
        Shaded r = shade(g, "ss", *b);
        EXPECT_TRUE(r.notes.empty()) << c.name << ": " << allNotes(r.notes);
        for (int i = 0; i < 3; ++i) expectColor(*r.out, i, c.want, 1e-5, c.name);
    }
}

TEST(ShadingNetwork, PlusMinusAverageReadsConnectedElementsPerSample) {
    const Graph g = read(R"(createNode surfaceShader -n "ss";
createNode samplerInfo -n "info";
createNode plusMinusAverage -n "pma";
	setAttr ".op" 3;
	setAttr ".i3[1]" -type "float3" 1 1 1;
connectAttr "info.p" "pma.i3[0]";
connectAttr "info.u" "pma.i3[3].i3y";
connectAttr "pma.o3" "ss.oc";
)");
    auto b = sphereBatch(kBatchSize);
    Shaded r = shade(g, "ss", *b);
    EXPECT_TRUE(r.notes.empty()) << allNotes(r.notes);
    for (int i = 0; i < kBatchSize; ++i)
        expectColor(*r.out, i, {(b->px[i] + 1.0) / 3.0, (b->py[i] + 1.0 + b->u[i]) / 3.0, (b->pz[i] + 1.0) / 3.0}, 1e-5);
}

TEST(ShadingNetwork, ScratchIsSharedAcrossNetworksOfDifferentSizes) {
    const Graph small = read(kLambert);
    const Graph big = read(R"(createNode surfaceShader -n "ss";
createNode reverse -n "a";
createNode reverse -n "b";
createNode reverse -n "c";
connectAttr "a.o" "b.i";
connectAttr "b.o" "c.i";
connectAttr "c.o" "ss.oc";
)");
    std::vector<std::string> notes;
    Evaluator e1(small, 1.0), e2(big, 1.0);
    auto n1 = ShadingNetwork::compile(e1, small.find("mat"), notes);
    auto n2 = ShadingNetwork::compile(e2, big.find("ss"), notes);
    auto b = sphereBatch(kBatchSize);
    ShadingScratch scratch;
    auto out = std::make_unique<ShadingResult>();
    const Light light = directional({0, 0, 1});
    n1->evaluate(*b, std::span(&light, 1), scratch, *out);
    n2->evaluate(*b, std::span(&light, 1), scratch, *out);
    for (int i = 0; i < kBatchSize; ++i) expectColor(*out, i, {1, 1, 1}, 0);  // 1 − (1 − (1 − 0))
    n1->evaluate(*b, std::span(&light, 1), scratch, *out);
    for (int i = 0; i < kBatchSize; ++i)
        expectColor(*out, i, glm::dvec3(0.2, 0.4, 0.6) * 0.7 * std::max(0.0, normalOf(*b, i).z), 1e-5);
}

TEST(ShadingNetwork, NonFiniteBatchValuesDoNotReachTheResult) {
    const Graph g = read(R"(createNode surfaceShader -n "ss";
createNode samplerInfo -n "info";
connectAttr "info.p" "ss.oc";
)");
    auto b = sphereBatch(2);
    b->px[1] = std::numeric_limits<float>::quiet_NaN();
    b->py[1] = std::numeric_limits<float>::infinity();
    Shaded r = shade(g, "ss", *b);
    EXPECT_EQ(r.out->cr[1], 0.0f);
    EXPECT_EQ(r.out->cg[1], 0.0f);
    EXPECT_NEAR(r.out->cb[1], b->pz[1], 1e-7);
    EXPECT_NEAR(r.out->cr[0], b->px[0], 1e-7);
}

TEST(ShadingNetwork, EmptyBatchWritesNothing) {
    const Graph g = read(kLambert);
    auto b = sphereBatch(0);
    Shaded r;
    Evaluator ev(g, 1.0);
    r.net = ShadingNetwork::compile(ev, g.find("mat"), r.notes);
    ShadingScratch scratch;
    r.out->cr[0] = -3.0f;
    r.net->evaluate(*b, {}, scratch, *r.out);
    EXPECT_EQ(r.out->cr[0], -3.0f);
}

}  // namespace
}  // namespace pushpin::shade
