// Tests for core/render/render_settings.h: Maya's defaults from a silent scene, values written the
// way Maya writes them (`select -ne :defaultRenderQuality; setAttr ".eaa" 0;`), and bad values
// replaced by the default with a note naming node.attribute.
#include "core/render/render_settings.h"

#include "core/scene/ma_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

namespace pushpin::render {
namespace {

RenderSettings read(const std::string& text, std::vector<std::string>& notes) {
    const scene::Graph g = scene::MaReader::readString(text, "test.ma");
    const scene::RenderSetup setup = scene::extractRenderSetup(g);
    scene::Evaluator ev(g, 1.0);
    return readRenderSettings(ev, setup, notes);
}

bool hasNote(const std::vector<std::string>& notes, const std::string& needle) {
    return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(needle) != std::string::npos; });
}

std::string joined(const std::vector<std::string>& notes) {
    std::string s;
    for (const std::string& n : notes) s += n + "\n";
    return s;
}

TEST(RenderSettings, EmptySceneGivesMayaDefaults) {
    std::vector<std::string> notes;
    const RenderSettings s = read("", notes);
    const RenderSettings d;
    EXPECT_TRUE(notes.empty()) << joined(notes);
    EXPECT_EQ(s.width, 640);
    EXPECT_EQ(s.height, 480);
    EXPECT_DOUBLE_EQ(s.deviceAspectRatio, 4.0 / 3.0);
    EXPECT_EQ(s.edgeAntiAliasing, 3);
    EXPECT_EQ(s.shadingSamples, 1);
    EXPECT_EQ(s.maxShadingSamples, 8);
    EXPECT_FALSE(s.useMultiPixelFilter);
    EXPECT_EQ(s.pixelFilterType, 2);
    EXPECT_NEAR(s.pixelFilterWidthX, 2.2, 1e-6);
    EXPECT_NEAR(s.pixelFilterWidthY, 2.2, 1e-6);
    EXPECT_NEAR(s.redThreshold, 0.4, 1e-6);
    EXPECT_NEAR(s.greenThreshold, 0.3, 1e-6);
    EXPECT_NEAR(s.blueThreshold, 0.6, 1e-6);
    EXPECT_NEAR(s.coverageThreshold, 0.125, 1e-6);
    EXPECT_FALSE(s.animation);
    EXPECT_DOUBLE_EQ(s.startFrame, 1.0);
    EXPECT_DOUBLE_EQ(s.endFrame, 1.0);
    EXPECT_DOUBLE_EQ(s.byFrameStep, 1.0);
    EXPECT_EQ(s.extensionPadding, 1);
    EXPECT_EQ(s.imageFormat, 7);
    EXPECT_EQ(s.imfPluginKey, "");
    EXPECT_EQ(s.imageFilePrefix, "");
    EXPECT_EQ(s.outFormatControl, 0);
    EXPECT_FALSE(s.putFrameBeforeExt);
    EXPECT_EQ(s.periodInExt, 1);
    EXPECT_DOUBLE_EQ(s.gammaCorrection, 1.0);
    EXPECT_TRUE(s.clipFinalShadedColor);
    EXPECT_TRUE(s.jitterFinalColor);
    EXPECT_FALSE(s.composite);
    EXPECT_TRUE(s.enableDefaultLight);
    EXPECT_EQ(s.numCpusToUse, 0);
    EXPECT_FALSE(s.forceTileSize);
    EXPECT_EQ(s.tileWidth, 64);
    EXPECT_EQ(s.tileHeight, 64);
    EXPECT_FALSE(s.useRenderRegion);
    EXPECT_EQ(s.image, d.image);
    EXPECT_EQ(s.mask, d.mask);
    EXPECT_EQ(s.depth, d.depth);
}

TEST(RenderSettings, MissingNodesKeepDefaults) {
    const scene::Graph g;
    scene::RenderSetup setup;  // every node kNoNode
    scene::Evaluator ev(g, 1.0);
    std::vector<std::string> notes;
    const RenderSettings s = readRenderSettings(ev, setup, notes);
    EXPECT_TRUE(notes.empty());
    EXPECT_EQ(s.width, 640);
    EXPECT_EQ(s.edgeAntiAliasing, 3);
    EXPECT_EQ(s.imageFormat, 7);
}

TEST(RenderSettings, ReadsValuesSetWithSelectNe) {
    std::vector<std::string> notes;
    const RenderSettings s = read(R"(
select -ne :defaultRenderQuality;
	setAttr ".eaa" 0;
	setAttr ".ss" 2;
	setAttr ".mss" 16;
	setAttr ".ufil" yes;
	setAttr ".pft" 4;
	setAttr ".pfwx" 3;
	setAttr ".pfwy" 1.5;
	setAttr ".rct" 0.2;
	setAttr ".gct" 0.15;
	setAttr ".bct" 0.3;
	setAttr ".cct" 0.25;
select -ne :defaultRenderGlobals;
	setAttr ".an" yes;
	setAttr ".fs" 5;
	setAttr ".ef" 24;
	setAttr ".bfs" 2;
	setAttr ".ep" 4;
	setAttr ".outf" 51;
	setAttr ".imfkey" -type "string" "exr";
	setAttr ".ifp" -type "string" "shots/<Scene>_<Camera>";
	setAttr ".ofc" 2;
	setAttr ".oft" -type "string" "pic";
	setAttr ".pff" yes;
	setAttr ".peie" 2;
	setAttr ".gama" 2.2;
	setAttr ".clip" no;
	setAttr ".jfc" no;
	setAttr ".comp" yes;
	setAttr ".edl" no;
	setAttr ".npu" 3;
	setAttr ".frts" yes;
	setAttr ".tlwd" 32;
	setAttr ".tlht" 128;
	setAttr ".urr" yes;
	setAttr ".left" 10;
	setAttr ".rght" 200;
	setAttr ".bot" 20;
	setAttr ".top" 300;
select -ne :defaultResolution;
	setAttr ".w" 1920;
	setAttr ".h" 1080;
	setAttr ".dar" 1.7777777910232544;
)",
                                  notes);
    EXPECT_TRUE(notes.empty()) << joined(notes);
    EXPECT_EQ(s.width, 1920);
    EXPECT_EQ(s.height, 1080);
    EXPECT_NEAR(s.deviceAspectRatio, 16.0 / 9.0, 1e-6);
    EXPECT_EQ(s.edgeAntiAliasing, 0);
    EXPECT_EQ(s.shadingSamples, 2);
    EXPECT_EQ(s.maxShadingSamples, 16);
    EXPECT_TRUE(s.useMultiPixelFilter);
    EXPECT_EQ(s.pixelFilterType, 4);
    EXPECT_NEAR(s.pixelFilterWidthX, 3.0, 1e-9);
    EXPECT_NEAR(s.pixelFilterWidthY, 1.5, 1e-9);
    EXPECT_NEAR(s.redThreshold, 0.2, 1e-6);
    EXPECT_NEAR(s.greenThreshold, 0.15, 1e-6);
    EXPECT_NEAR(s.blueThreshold, 0.3, 1e-6);
    EXPECT_NEAR(s.coverageThreshold, 0.25, 1e-6);
    EXPECT_TRUE(s.animation);
    EXPECT_DOUBLE_EQ(s.startFrame, 5.0);
    EXPECT_DOUBLE_EQ(s.endFrame, 24.0);
    EXPECT_DOUBLE_EQ(s.byFrameStep, 2.0);
    EXPECT_EQ(s.extensionPadding, 4);
    EXPECT_EQ(s.imageFormat, 51);
    EXPECT_EQ(s.imfPluginKey, "exr");
    EXPECT_EQ(s.imageFilePrefix, "shots/<Scene>_<Camera>");
    EXPECT_EQ(s.outFormatControl, 2);
    EXPECT_EQ(s.outFormatExt, "pic");
    EXPECT_TRUE(s.putFrameBeforeExt);
    EXPECT_EQ(s.periodInExt, 2);
    EXPECT_NEAR(s.gammaCorrection, 2.2, 1e-6);
    EXPECT_FALSE(s.clipFinalShadedColor);
    EXPECT_FALSE(s.jitterFinalColor);
    EXPECT_TRUE(s.composite);
    EXPECT_FALSE(s.enableDefaultLight);
    EXPECT_EQ(s.numCpusToUse, 3);
    EXPECT_TRUE(s.forceTileSize);
    EXPECT_EQ(s.tileWidth, 32);
    EXPECT_EQ(s.tileHeight, 128);
    EXPECT_TRUE(s.useRenderRegion);
    EXPECT_EQ(s.left, 10);
    EXPECT_EQ(s.rght, 200);
    EXPECT_EQ(s.bot, 20);
    EXPECT_EQ(s.top, 300);
}

TEST(RenderSettings, AnimatedValueIsEvaluatedAtTheFrame) {
    const std::string text = R"(
createNode animCurveTU -n "gammaCurve";
	setAttr ".tan" 2;
	setAttr ".wgt" no;
	setAttr -s 2 ".ktv[0:1]"  1 1 11 2;
connectAttr "gammaCurve.o" ":defaultRenderGlobals.gama";
)";
    const scene::Graph g = scene::MaReader::readString(text, "test.ma");
    const scene::RenderSetup setup = scene::extractRenderSetup(g);
    std::vector<std::string> notes;
    scene::Evaluator ev(g, 6.0);
    const RenderSettings s = readRenderSettings(ev, setup, notes);
    EXPECT_NEAR(s.gammaCorrection, 1.5, 1e-9);
}

TEST(RenderSettings, OutOfRangeValuesFallBackWithNotes) {
    std::vector<std::string> notes;
    const RenderSettings s = read(R"(
select -ne :defaultRenderQuality;
	setAttr ".eaa" 7;
	setAttr ".ss" 0;
	setAttr ".mss" 40;
	setAttr ".pft" 1000;
	setAttr ".pfwx" 5;
	setAttr ".rct" 1.5;
	setAttr ".cct" -0.5;
select -ne :defaultRenderGlobals;
	setAttr ".bfs" 0;
	setAttr ".ofc" 5;
	setAttr ".peie" 3;
	setAttr ".gama" 0;
	setAttr ".tlwd" 4;
	setAttr ".npu" -2;
select -ne :defaultResolution;
	setAttr ".w" 0;
	setAttr ".h" 40000;
	setAttr ".dar" -1;
)",
                                  notes);
    EXPECT_EQ(s.edgeAntiAliasing, 3);
    EXPECT_EQ(s.shadingSamples, 1);
    EXPECT_EQ(s.maxShadingSamples, 8);
    EXPECT_EQ(s.pixelFilterType, 2);
    EXPECT_NEAR(s.pixelFilterWidthX, 2.2, 1e-9);
    EXPECT_NEAR(s.redThreshold, 0.4, 1e-9);
    EXPECT_NEAR(s.coverageThreshold, 0.125, 1e-9);
    EXPECT_DOUBLE_EQ(s.byFrameStep, 1.0);
    EXPECT_EQ(s.outFormatControl, 0);
    EXPECT_EQ(s.periodInExt, 1);
    EXPECT_DOUBLE_EQ(s.gammaCorrection, 1.0);
    EXPECT_EQ(s.tileWidth, 64);
    EXPECT_EQ(s.numCpusToUse, 0);
    EXPECT_EQ(s.width, 640);
    EXPECT_EQ(s.height, 480);
    EXPECT_DOUBLE_EQ(s.deviceAspectRatio, 4.0 / 3.0);
    for (const char* attr :
         {"defaultRenderQuality.edgeAntiAliasing", "defaultRenderQuality.shadingSamples",
          "defaultRenderQuality.maxShadingSamples", "defaultRenderQuality.pixelFilterType",
          "defaultRenderQuality.pixelFilterWidthX", "defaultRenderQuality.redThreshold",
          "defaultRenderQuality.coverageThreshold", "defaultRenderGlobals.byFrameStep",
          "defaultRenderGlobals.outFormatControl", "defaultRenderGlobals.periodInExt",
          "defaultRenderGlobals.gammaCorrection", "defaultRenderGlobals.tileWidth",
          "defaultRenderGlobals.numCpusToUse", "defaultResolution.width", "defaultResolution.height",
          "defaultResolution.deviceAspectRatio"})
        EXPECT_TRUE(hasNote(notes, attr)) << attr << " not noted in:\n" << joined(notes);
}

TEST(RenderSettings, NaNAndInfAreReplacedAndNoted) {
    scene::Graph g;
    const scene::RenderSetup setup = scene::extractRenderSetup(g);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    auto set = [&](scene::NodeId n, const char* attr, double v) {
        g.setValue(n, *scene::parsePlugPath(attr), scene::Numbers{scene::Numbers::Kind::Plain, 1, {v}});
    };
    set(setup.renderQuality, "redThreshold", nan);
    set(setup.renderQuality, "shadingSamples", inf);
    set(setup.renderGlobals, "gammaCorrection", nan);
    set(setup.renderGlobals, "startFrame", -inf);
    set(setup.renderGlobals, "animation", nan);
    set(setup.resolution, "deviceAspectRatio", nan);
    set(setup.resolution, "width", nan);
    std::vector<std::string> notes;
    scene::Evaluator ev(g, 1.0);
    const RenderSettings s = readRenderSettings(ev, setup, notes);
    EXPECT_NEAR(s.redThreshold, 0.4, 1e-9);
    EXPECT_EQ(s.shadingSamples, 1);
    EXPECT_DOUBLE_EQ(s.gammaCorrection, 1.0);
    EXPECT_DOUBLE_EQ(s.startFrame, 1.0);
    EXPECT_FALSE(s.animation);
    EXPECT_DOUBLE_EQ(s.deviceAspectRatio, 4.0 / 3.0);
    EXPECT_EQ(s.width, 640);
    EXPECT_EQ(notes.size(), 7u) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultRenderQuality.redThreshold: nan")) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultRenderGlobals.gammaCorrection")) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultRenderGlobals.startFrame")) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultResolution.deviceAspectRatio")) << joined(notes);
}

TEST(RenderSettings, InconsistentValuesAreRepairedWithNotes) {
    std::vector<std::string> notes;
    const RenderSettings s = read(R"(
select -ne :defaultRenderQuality;
	setAttr ".ss" 6;
	setAttr ".mss" 3;
select -ne :defaultRenderGlobals;
	setAttr ".fs" 10;
	setAttr ".ef" 4;
	setAttr ".urr" yes;
	setAttr ".left" 300;
	setAttr ".rght" 100;
)",
                                  notes);
    EXPECT_EQ(s.shadingSamples, 6);
    EXPECT_EQ(s.maxShadingSamples, 6);
    EXPECT_DOUBLE_EQ(s.startFrame, 10.0);
    EXPECT_DOUBLE_EQ(s.endFrame, 10.0);
    EXPECT_FALSE(s.useRenderRegion);
    EXPECT_TRUE(hasNote(notes, "defaultRenderQuality.maxShadingSamples")) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultRenderGlobals.endFrame")) << joined(notes);
    EXPECT_TRUE(hasNote(notes, "defaultRenderGlobals.useRenderRegion")) << joined(notes);
}

TEST(RenderSettings, CubicBSplineFilterIsAccepted) {
    std::vector<std::string> notes;
    const RenderSettings s = read("select -ne :defaultRenderQuality;\nsetAttr \".pft\" 6;\n", notes);
    EXPECT_EQ(s.pixelFilterType, 6);
    EXPECT_TRUE(notes.empty()) << joined(notes);
}

TEST(RenderSettings, SceneMaximumMemoryIsNoCap) {
    // Maya's maximumMemory is a tiling hint (render-globals.md); only -mm or the scheduler caps.
    std::vector<std::string> notes;
    const RenderSettings s = read("select -ne :defaultRenderGlobals;\n\tsetAttr \".mm\" 4;\n", notes);
    EXPECT_EQ(s.maximumMemoryBytes, 0u);
    EXPECT_EQ(memoryCap(s, nullptr).bytes, 0u);
}

TEST(RenderSettings, MemoryCapComesFromTheCommandLineElseFromSlurm) {
    RenderSettings s;
    EXPECT_EQ(memoryCap(s, nullptr).bytes, 0u);
    EXPECT_EQ(memoryCap(s, nullptr).source, "");
    EXPECT_EQ(memoryCap(s, "2048").bytes, 2048ull << 20);
    EXPECT_EQ(memoryCap(s, "2048").source, "$SLURM_MEM_PER_NODE");
    // Not a plain positive count of MiB: no cap.
    for (const char* bad : {"", "0", "-5", "2G", "12abc", " 7", "99999999999999999999999"})
        EXPECT_EQ(memoryCap(s, bad).bytes, 0u) << "'" << bad << "'";
    // The command line wins over the scheduler.
    s.maximumMemoryBytes = 512ull << 20;
    EXPECT_EQ(memoryCap(s, "2048").bytes, 512ull << 20);
    EXPECT_EQ(memoryCap(s, "2048").source, "-mm");
    EXPECT_EQ(memoryCap(s, nullptr).bytes, 512ull << 20);
}

}  // namespace
}  // namespace pushpin::render
