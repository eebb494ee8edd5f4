// Tests for core/render/command_line.h: every flag parses and lands on the right render-globals
// field; keywords; bad values and unknown flags throw naming the flag.
#include "core/render/command_line.h"

#include "cache/error.h"

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace pushpin::render {
namespace {

CommandLine parse(std::vector<std::string_view> args) { return parseCommandLine(args); }

RenderSettings applied(std::vector<std::string_view> args, RenderSettings s = {}) {
    applyOverrides(parse(std::move(args)), s);
    return s;
}

// Expects parsing to throw an Error whose message contains every one of `needles`.
void expectError(std::vector<std::string_view> args, std::vector<std::string> needles) {
    try {
        (void)parseCommandLine(args);
        std::string line;
        for (auto a : args) line += std::string(a) + " ";
        ADD_FAILURE() << "no error for: " << line;
    } catch (const Error& e) {
        const std::string what = e.what();
        for (const std::string& n : needles) EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    }
}

TEST(CommandLine, PushpinOptions) {
    const CommandLine cl = parse({"--info", "--no-references", "--frame", "12.5", "--stats", "out.json", "--quiet",
                                  "--version", "--print-demo", "scene.ma"});
    EXPECT_TRUE(cl.info);
    EXPECT_FALSE(cl.loadReferences);
    ASSERT_TRUE(cl.frame.has_value());
    EXPECT_DOUBLE_EQ(*cl.frame, 12.5);
    EXPECT_EQ(cl.statsPath, "out.json");
    EXPECT_TRUE(cl.quiet);
    EXPECT_TRUE(cl.version);
    EXPECT_TRUE(cl.printDemo);
    EXPECT_EQ(cl.scene, "scene.ma");
    EXPECT_FALSE(cl.demo);
    EXPECT_FALSE(cl.help);

    EXPECT_TRUE(parse({"--demo"}).demo);
    for (std::string_view h : {"-h", "--help", "-help"}) EXPECT_TRUE(parse({h}).help) << h;
    const CommandLine empty = parse({});
    EXPECT_TRUE(empty.scene.empty());
    EXPECT_TRUE(empty.loadReferences);
    EXPECT_TRUE(empty.overrides.empty());
}

TEST(CommandLine, CamerasOutputDirAndRenderer) {
    const CommandLine cl = parse({"-r", "sw", "-cam", "persp", "-cam", "|shot|camA", "-rd", "out/images", "s.ma"});
    EXPECT_EQ(cl.cameras, (std::vector<std::string>{"persp", "|shot|camA"}));
    EXPECT_EQ(cl.outputDir, "out/images");
    expectError({"-r", "mr", "s.ma"}, {"-r", "'mr'"});
    expectError({"-r", "file"}, {"-r", "'file'"});
}

TEST(CommandLine, ResolutionAndRegion) {
    const RenderSettings s = applied({"-x", "320", "-y", "200", "-reg", "10", "300", "0", "150"});
    EXPECT_EQ(s.width, 320);
    EXPECT_EQ(s.height, 200);
    EXPECT_TRUE(s.useRenderRegion);
    EXPECT_EQ(s.left, 10);
    EXPECT_EQ(s.rght, 300);
    EXPECT_EQ(s.bot, 0);
    EXPECT_EQ(s.top, 150);
    // Square pixels stay square: the device aspect follows the new size.
    EXPECT_DOUBLE_EQ(s.deviceAspectRatio, 1.6);
    // -ard wins over the derived aspect.
    const RenderSettings a = applied({"-x", "320", "-y", "200", "-ard", "2"});
    EXPECT_DOUBLE_EQ(a.deviceAspectRatio, 2.0);
    // A scene with non-square pixels (pixel aspect 2) keeps them.
    RenderSettings wide;
    wide.width = 100;
    wide.height = 100;
    wide.deviceAspectRatio = 2.0;
    EXPECT_DOUBLE_EQ(applied({"-x", "200"}, wide).deviceAspectRatio, 4.0);
}

TEST(CommandLine, QualityFlags) {
    const RenderSettings s = applied({"-eaa", "0", "-ss", "2", "-mss", "12", "-ufil", "on", "-pft", "5", "-pfx", "3",
                                      "-pfy", "1.5", "-rct", "0.2", "-gct", "0.15", "-bct", "0.3", "-cct", "0.5"});
    EXPECT_EQ(s.edgeAntiAliasing, 0);
    EXPECT_EQ(s.shadingSamples, 2);
    EXPECT_EQ(s.maxShadingSamples, 12);
    EXPECT_TRUE(s.useMultiPixelFilter);
    EXPECT_EQ(s.pixelFilterType, 5);
    EXPECT_DOUBLE_EQ(s.pixelFilterWidthX, 3.0);
    EXPECT_DOUBLE_EQ(s.pixelFilterWidthY, 1.5);
    EXPECT_DOUBLE_EQ(s.redThreshold, 0.2);
    EXPECT_DOUBLE_EQ(s.greenThreshold, 0.15);
    EXPECT_DOUBLE_EQ(s.blueThreshold, 0.3);
    EXPECT_DOUBLE_EQ(s.coverageThreshold, 0.5);
    // -ss above the scene's maxShadingSamples raises it.
    EXPECT_EQ(applied({"-ss", "16"}).maxShadingSamples, 16);
}

TEST(CommandLine, EaaAndPftKeywords) {
    const char* eaa[] = {"highest", "high", "medium", "low"};
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(applied({"-eaa", eaa[i]}).edgeAntiAliasing, i) << eaa[i];
        EXPECT_EQ(applied({"-eaa", std::to_string(i)}).edgeAntiAliasing, i);
    }
    EXPECT_EQ(applied({"-eaa", "HIGHEST"}).edgeAntiAliasing, 0);
    const std::pair<const char*, int> pft[] = {
        {"box", 0}, {"triangle", 2}, {"gaussian", 4}, {"quadraticbspline", 5}, {"cubicbspline", 6}, {"6", 6}, {"0", 0}};
    for (const auto& [word, code] : pft) EXPECT_EQ(applied({"-pft", word}).pixelFilterType, code) << word;
    expectError({"-eaa", "4"}, {"-eaa", "'4'"});
    expectError({"-eaa", "best"}, {"-eaa", "'best'"});
    expectError({"-pft", "1"}, {"-pft", "'1'"});
    expectError({"-pft", "plugin"}, {"-pft", "'plugin'"});
    expectError({"-pft", "mitchell"}, {"-pft", "'mitchell'"});
}

TEST(CommandLine, FramesAndNaming) {
    RenderSettings s = applied({"-s", "5", "-e", "24", "-b", "0.5", "-pad", "4", "-im", "<Scene>_<Camera>"});
    EXPECT_TRUE(s.animation);
    EXPECT_DOUBLE_EQ(s.startFrame, 5.0);
    EXPECT_DOUBLE_EQ(s.endFrame, 24.0);
    EXPECT_DOUBLE_EQ(s.byFrameStep, 0.5);
    EXPECT_EQ(s.extensionPadding, 4);
    EXPECT_EQ(s.imageFilePrefix, "<Scene>_<Camera>");
    EXPECT_EQ(applied({"-p", "beauty"}).imageFilePrefix, "beauty");
    // Only -s given past the scene's end: the end follows.
    RenderSettings scene;
    scene.endFrame = 10;
    s = applied({"-s", "20"}, scene);
    EXPECT_DOUBLE_EQ(s.startFrame, 20.0);
    EXPECT_DOUBLE_EQ(s.endFrame, 20.0);
    EXPECT_TRUE(applied({"-b", "2"}).animation);
    // Negative frames are values, not flags.
    EXPECT_DOUBLE_EQ(applied({"-s", "-5", "-e", "-1"}).startFrame, -5.0);
    expectError({"-s", "10", "-e", "2"}, {"-e", "'2'"});
    expectError({"-b", "0"}, {"-b", "'0'"});
    expectError({"-s", "nan"}, {"-s", "'nan'"});
    expectError({"-e", "inf"}, {"-e", "'inf'"});
}

TEST(CommandLine, FileNameConventionsFollowTheTable) {
    struct Row {
        const char* fnc;
        bool an;
        int ofc;
        bool pff;
        int peie;
    } rows[] = {
        {"name", false, 1, false, 1},      {"name.ext", false, 0, false, 1}, {"name.#.ext", true, 0, true, 1},
        {"name.ext.#", true, 0, false, 1}, {"name.#", true, 1, false, 1},    {"name#.ext", true, 0, true, 0},
        {"name_#.ext", true, 0, true, 2},
    };
    for (int i = 0; i < 7; ++i) {
        for (const std::string& arg : {std::string(rows[i].fnc), std::to_string(i + 1)}) {
            const RenderSettings s = applied({"-fnc", arg});
            EXPECT_EQ(s.animation, rows[i].an) << arg;
            EXPECT_EQ(s.outFormatControl, rows[i].ofc) << arg;
            if (rows[i].ofc == 0 && rows[i].an) {
                EXPECT_EQ(s.putFrameBeforeExt, rows[i].pff) << arg;
            }
            if (rows[i].an) {
                EXPECT_EQ(s.periodInExt, rows[i].peie) << arg;
            }
        }
    }
    expectError({"-fnc", "namec"}, {"-fnc", "'namec'", "movie"});
    expectError({"-fnc", "9"}, {"-fnc", "'9'"});
    expectError({"-fnc", "0"}, {"-fnc", "'0'"});
    expectError({"-fnc", "name.png"}, {"-fnc", "'name.png'"});
}

TEST(CommandLine, OutputFormatSetsImageFormat) {
    const std::pair<const char*, int> codes[] = {{"iff", 7}, {"tif", 3}, {"tiff16", 4}, {"sgi", 5}, {"jpg", 8},
                                                 {"maya16", 10}, {"sgi16", 13}, {"tga", 19}, {"bmp", 20}, {"png", 32}};
    for (const auto& [name, code] : codes) {
        const RenderSettings s = applied({"-of", name});
        EXPECT_EQ(s.imageFormat, code) << name;
    }
    RenderSettings s = applied({"-of", "exr"});
    EXPECT_EQ(s.imageFormat, 40);
    EXPECT_EQ(s.imfPluginKey, "exr");
    s = applied({"-of", "PNG"});
    EXPECT_EQ(s.imageFormat, 32);
    expectError({"-of", "avi"}, {"-of", "avi"});
    expectError({"-of", "cineon"}, {"-of", "cineon"});
    expectError({"-of", "xyz"}, {"-of", "xyz"});
}

TEST(CommandLine, OutputColourAndPerformanceFlags) {
    const RenderSettings s = applied({"-g", "2.2", "-n", "4", "-tw", "32", "-th", "128", "-premul", "off", "-rgb", "yes",
                                      "-alpha", "false", "-depth", "1", "-mm", "512"});
    EXPECT_DOUBLE_EQ(s.gammaCorrection, 2.2);
    EXPECT_EQ(s.numCpusToUse, 4);
    EXPECT_TRUE(s.forceTileSize);
    EXPECT_EQ(s.tileWidth, 32);
    EXPECT_EQ(s.tileHeight, 128);
    EXPECT_TRUE(s.composite);
    ASSERT_TRUE(s.image && s.mask && s.depth);
    EXPECT_TRUE(*s.image);
    EXPECT_FALSE(*s.mask);
    EXPECT_TRUE(*s.depth);
    RenderSettings composite;
    composite.composite = true;
    EXPECT_FALSE(applied({"-premul", "on"}, composite).composite);
    // -mm is kept for the memory stage.
    const CommandLine cl = parse({"-mm", "512"});
    ASSERT_EQ(cl.overrides.size(), 1u);
    EXPECT_EQ(cl.overrides[0].flag, "-mm");
    EXPECT_EQ(cl.overrides[0].value, "512");
}

TEST(CommandLine, BooleanSpellings) {
    for (std::string_view on : {"on", "yes", "true", "1", "ON", "Yes"}) EXPECT_TRUE(applied({"-ufil", on}).useMultiPixelFilter) << on;
    RenderSettings s;
    s.useMultiPixelFilter = true;
    for (std::string_view off : {"off", "no", "false", "0"}) EXPECT_FALSE(applied({"-ufil", off}, s).useMultiPixelFilter) << off;
    expectError({"-ufil", "maybe"}, {"-ufil", "'maybe'"});
    expectError({"-depth", "2"}, {"-depth", "'2'"});
}

TEST(CommandLine, OverridesApplyInOrder) {
    const CommandLine cl = parse({"-x", "100", "-eaa", "low", "-x", "200"});
    ASSERT_EQ(cl.overrides.size(), 3u);
    EXPECT_EQ(cl.overrides[1].value, "3");  // keywords are stored as Maya's numbers
    RenderSettings s;
    applyOverrides(cl, s);
    EXPECT_EQ(s.width, 200);
}

TEST(CommandLine, BadValuesNameTheFlagAndValue) {
    expectError({"-x", "abc"}, {"-x", "'abc'", "not an integer"});
    expectError({"-x", "0"}, {"-x", "'0'", "range"});
    expectError({"-y", "40000"}, {"-y", "'40000'"});
    expectError({"-x", "12.5"}, {"-x", "'12.5'"});
    expectError({"-ss", "0"}, {"-ss", "'0'"});
    expectError({"-mss", "33"}, {"-mss", "'33'"});
    expectError({"-ss", "8", "-mss", "4"}, {"-mss", "'4'"});
    expectError({"-pfx", "0.5"}, {"-pfx", "'0.5'"});
    expectError({"-rct", "1.5"}, {"-rct", "'1.5'"});
    expectError({"-cct", "-0.1"}, {"-cct", "'-0.1'"});
    expectError({"-g", "0"}, {"-g", "'0'"});
    expectError({"-g", "1e400"}, {"-g", "'1e400'"});
    expectError({"-tw", "8"}, {"-tw", "'8'"});
    expectError({"-th", "512"}, {"-th", "'512'"});
    expectError({"-n", "-1"}, {"-n", "'-1'"});
    expectError({"-pad", "x"}, {"-pad", "'x'"});
    expectError({"-ard", "-1"}, {"-ard", "'-1'"});
    expectError({"-mm", "0"}, {"-mm", "'0'"});
    expectError({"--frame", "abc"}, {"--frame", "'abc'"});
    expectError({"-im", ""}, {"-im"});
}

TEST(CommandLine, MissingValuesAndRegionShape) {
    expectError({"-x"}, {"-x needs a value"});
    expectError({"-cam"}, {"-cam needs a value"});
    expectError({"--stats"}, {"--stats"});
    expectError({"-reg", "0", "10", "0"}, {"-reg needs 4 values"});
    expectError({"-reg", "0", "10", "a", "5"}, {"-reg", "'a'"});
    expectError({"-reg", "50", "10", "0", "5"}, {"-reg", "left"});
    expectError({"-reg", "0", "10", "9", "5"}, {"-reg", "bottom"});
}

TEST(CommandLine, UnknownOptionsAndSecondSceneThrow) {
    expectError({"-zz"}, {"unknown option '-zz' (see pushpin --help)"});
    expectError({"--render"}, {"unknown option '--render'"});
    expectError({"-"}, {"unknown option '-'"});
    expectError({"a.ma", "b.ma"}, {"more than one scene", "a.ma", "b.ma"});
}

TEST(CommandLine, HelpListsEveryFlag) {
    const std::string help = commandLineHelp();
    for (const char* flag : {"--help", "--version", "--info", "--demo", "--print-demo", "--no-references", "--frame",
                             "--stats", "--quiet", "-cam", "-rd", "-im", "-p ", "-of", "-fnc", "-pad", "-s F", "-e F",
                             "-b F", "-x N", "-y N", "-reg", "-eaa", "-ss", "-mss", "-ufil", "-pft", "-pfx", "-pfy",
                             "-rct", "-gct", "-bct", "-cct", "-g ", "-n N", "-tw", "-th", "-premul", "-rgb", "-alpha",
                             "-depth", "-ard", "-mm", "-r sw", "--allow-scene-output-paths"})
        EXPECT_NE(help.find(flag), std::string::npos) << flag;
    // The exit status table of farm.md §6.
    for (const char* code : {"0 ", "1 ", "2 ", "33 ", "75 ", "130, 143"}) EXPECT_NE(help.find(code), std::string::npos) << code;
}

// Command-line mistakes are UsageError (exit 2 in the tools), told apart from scene errors.
TEST(CommandLine, MistakesAreUsageErrors) {
    for (const std::vector<std::string_view>& args :
         std::vector<std::vector<std::string_view>>{{"-x", "abc"}, {"-zz"}, {"a.ma", "b.ma"}, {"-reg", "1"},
                                                    {"-of", "avi"}, {"-r", "mayaHardware"}, {"-s", "5", "-e", "1"},
                                                    {"-ss", "8", "-mss", "4"}, {"--stats"}}) {
        std::string line;
        for (auto a : args) line += std::string(a) + " ";
        EXPECT_THROW((void)parseCommandLine(args), UsageError) << line;
    }
}

TEST(CommandLine, HugeValuesAreQuotedShort) {
    const std::string huge(1 << 20, 'x');
    const std::string flag = "-" + huge;
    for (const std::vector<std::string_view>& args :
         std::vector<std::vector<std::string_view>>{{"-x", huge}, {flag}, {"a.ma", huge}, {"-cam", "c", "-pad", huge}}) {
        try {
            (void)parseCommandLine(args);
            ADD_FAILURE() << "no error";
        } catch (const UsageError& e) {
            EXPECT_LT(std::string(e.what()).size(), 600u);
            EXPECT_NE(std::string(e.what()).find("bytes)"), std::string::npos) << std::string(e.what()).substr(0, 300);
        }
    }
}

TEST(CommandLine, SceneOutputPathsAndMemoryCap) {
    EXPECT_FALSE(parse({"s.ma"}).allowSceneOutputPaths);
    EXPECT_TRUE(parse({"--allow-scene-output-paths", "s.ma"}).allowSceneOutputPaths);
    // -mm MB is the render's cap in bytes (MiB); without it there is none from the command line.
    EXPECT_EQ(applied({"-mm", "512"}).maximumMemoryBytes, uint64_t(512) << 20);
    EXPECT_EQ(applied({}).maximumMemoryBytes, 0u);
    EXPECT_EQ(memoryCap(applied({"-mm", "64"}), "4096").bytes, uint64_t(64) << 20);
}

// A sample command line for every flag of reference/render-cli.md.
struct FlagSample {
    std::vector<std::string_view> args;
};
const std::vector<FlagSample>& flagSamples() {
    static const std::vector<FlagSample> samples = {
        {{"-help"}}, {{"-r", "sw"}}, {{"-renderer", "sw"}}, {{"-proj", "/p"}}, {{"-log", "r.log"}}, {{"-verb"}},
        {{"-test"}}, {{"-keepMel"}}, {{"-listRenderers"}}, {{"-rst", "t.json"}}, {{"-rsp", "p.json"}},
        {{"-rsa", "a.json"}}, {{"-rd", "out"}}, {{"-im", "img"}}, {{"-p", "img"}}, {{"-of", "png"}},
        {{"-fnc", "3"}}, {{"-pad", "4"}}, {{"-s", "1"}}, {{"-e", "2"}}, {{"-b", "1"}},
        {{"-skipExistingFrames", "true"}}, {{"-rfs", "10"}}, {{"-rfb", "2"}}, {{"-se", "10"}}, {{"-be", "2"}},
        {{"-me", "on"}}, {{"-mf", "on"}}, {{"-cam", "persp"}}, {{"-rgb", "on"}}, {{"-alpha", "on"}},
        {{"-depth", "on"}}, {{"-iip"}}, {{"-x", "64"}}, {{"-y", "48"}}, {{"-iw", "64"}}, {{"-ih", "48"}},
        {{"-percentRes", "50"}}, {{"-ard", "1.333"}}, {{"-par", "1"}}, {{"-ar", "1.5"}},
        {{"-reg", "0", "10", "0", "10"}}, {{"-xl", "0"}}, {{"-xr", "10"}}, {{"-yl", "0"}}, {{"-yh", "10"}},
        {{"-ifg", "on"}}, {{"-eaa", "1"}}, {{"-ss", "2"}}, {{"-mss", "8"}}, {{"-mvs", "4"}}, {{"-mvm", "8"}},
        {{"-pss", "2"}}, {{"-vs", "2"}}, {{"-ufil", "on"}}, {{"-pft", "2"}}, {{"-pfx", "2"}}, {{"-pfy", "2"}},
        {{"-rct", "0.4"}}, {{"-gct", "0.3"}}, {{"-bct", "0.6"}}, {{"-cct", "0.125"}}, {{"-ert", "on"}},
        {{"-rfl", "2"}}, {{"-rfr", "4"}}, {{"-sl", "2"}}, {{"-mb", "on"}}, {{"-mbf", "1"}}, {{"-sa", "144"}},
        {{"-mb2d", "on"}}, {{"-bll", "1"}}, {{"-bls", "1"}}, {{"-smv", "2"}}, {{"-smc", "on"}}, {{"-kmv", "on"}},
        {{"-field", "on"}}, {{"-pal"}}, {{"-ntsc"}}, {{"-edm", "on"}}, {{"-g", "2.2"}}, {{"-premul", "on"}},
        {{"-premulthr", "0.5"}}, {{"-uf", "on"}}, {{"-oi", "on"}}, {{"-rut", "on"}}, {{"-udb", "on"}},
        {{"-mm", "2048"}}, {{"-n", "2"}}, {{"-tw", "64"}}, {{"-th", "64"}}, {{"-sp", "on"}}, {{"-amt"}},
        {{"-rep", "true"}}, {{"-ipr"}}, {{"-keepPreImage"}}, {{"-cont"}}, {{"-verbose", "on"}}, {{"-rl", "true"}},
        {{"-rp", "true"}}, {{"-rs", "on"}}, {{"-l", "layer1"}}, {{"-sel", "pCube1"}}, {{"-preRender", "foo"}},
        {{"-pre", "foo"}}, {{"-post", "foo"}}, {{"-postRender", "foo"}}, {{"-preLayer", "foo"}},
        {{"-postLayer", "foo"}}, {{"-preFrame", "foo"}}, {{"-postFrame", "foo"}},
    };
    return samples;
}

// Every flag of reference/render-cli.md is accepted, with a sample argument. Each either applies
// (it becomes a render-globals override, or sets a field of the command line) or is reported
// under notRendered with its feature: nothing is accepted and silently dropped.
TEST(CommandLine, EveryRenderFlagIsAcceptedAndAppliesOrIsReported) {
    for (const FlagSample& c : flagSamples()) {
        std::vector<std::string_view> args = c.args;
        args.push_back("scene.ma");
        CommandLine cl;
        ASSERT_NO_THROW(cl = parse(args)) << c.args[0];
        const CommandLine plain = parse({"scene.ma"});
        const bool applies =
            cl.help || !cl.cameras.empty() || !cl.outputDir.empty() || !cl.project.empty() || !cl.overrides.empty();
        const bool reported = !cl.notApplied.empty() || !cl.featureSwitches.empty();
        EXPECT_TRUE(applies || reported || std::string_view(c.args[0]) == "-r" || std::string_view(c.args[0]) == "-renderer")
            << c.args[0] << " is accepted but neither applies nor is reported";
        EXPECT_FALSE(applies && reported) << c.args[0];
        EXPECT_TRUE(plain.notApplied.empty() && plain.featureSwitches.empty());
    }
}

// The list above covers the reference's table: a flag added there fails here until it is handled.
TEST(CommandLine, TheSamplesCoverEveryFlagOfTheReference) {
    const std::filesystem::path doc = std::filesystem::path(PUSHPIN_MA_CORPUS) / ".." / ".." / "reference" / "render-cli.md";
    std::ifstream in(doc);
    if (!in) GTEST_SKIP() << doc << " is not here";
    std::set<std::string> sampled;
    for (const FlagSample& s : flagSamples()) sampled.insert(std::string(s.args[0]));
    size_t rows = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| `-", 0) != 0) continue;  // a table row naming flags in its first cell
        ++rows;
        const std::string cell = line.substr(1, line.find('|', 1) - 1);
        for (size_t at = cell.find('-'); at != std::string::npos; at = cell.find('-', at + 1)) {
            if (at > 0 && cell[at - 1] != '`' && cell[at - 1] != ' ') continue;
            size_t end = at + 1;
            while (end < cell.size() && std::isalnum(static_cast<unsigned char>(cell[end]))) ++end;
            if (end == at + 1) continue;
            const std::string flag = cell.substr(at, end - at);
            EXPECT_TRUE(sampled.count(flag)) << flag << " of " << doc << " has no sample";
        }
    }
    EXPECT_GT(rows, 80u);
}

TEST(CommandLine, FeatureSwitchesAndNotAppliedFlagsNameTheirFeature) {
    const CommandLine cl = parse({"-mb", "off", "-ert", "yes", "-iip", "-mbf", "0.5", "-rep", "scene.ma"});
    ASSERT_EQ(cl.featureSwitches.size(), 3u);
    EXPECT_EQ(cl.featureSwitches[0].feature, "motion blur");
    EXPECT_FALSE(cl.featureSwitches[0].on);
    EXPECT_EQ(cl.featureSwitches[1].flag, "-ert on");
    EXPECT_TRUE(cl.featureSwitches[1].on);
    EXPECT_EQ(cl.featureSwitches[2].feature, "image planes");
    EXPECT_FALSE(cl.featureSwitches[2].on);
    ASSERT_EQ(cl.notApplied.size(), 2u);
    EXPECT_EQ(cl.notApplied[0].flag, "-mbf 0.5");
    EXPECT_EQ(cl.notApplied[0].feature, "motion blur");
    EXPECT_EQ(cl.notApplied[1].flag, "-rep");  // an optional boolean left out; the scene stays the scene
    EXPECT_EQ(cl.scene, "scene.ma");
    EXPECT_THROW(parse({"-mb", "maybe", "scene.ma"}), UsageError);
    EXPECT_THROW(parse({"-rfl", "two", "scene.ma"}), UsageError);
    EXPECT_THROW(parse({"-zz", "scene.ma"}), UsageError);  // unknown flags stay errors
}

}  // namespace
}  // namespace pushpin::render
