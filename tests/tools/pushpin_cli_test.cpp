// Runs the built `pushpin` program the way users do and checks exit codes, stdout and stderr.
#include "tests/support/ma_corpus.h"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct CliRun {
    int exitCode = -1;
    std::string out, err;
};

fs::path tempDir() {
    fs::path dir = fs::temp_directory_path() / ("pushpin_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

CliRun runPushpin(const std::string& args) {
    fs::path errFile = tempDir() / "stderr.txt";
    std::string cmd = std::string(PUSHPIN_BINARY_DIR) + "/pushpin " + args + " 2> '" + errFile.string() + "'";
    CliRun r;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 65536> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
    int status = ::pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(errFile);
    r.err.assign(std::istreambuf_iterator<char>(in), {});
    return r;
}

fs::path writeFile(const std::string& name, const std::string& text) {
    fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
}

// A strict JSON syntax check (RFC 8259), enough to prove the report is machine-readable.
class JsonChecker {
public:
    explicit JsonChecker(const std::string& s) : m_s(s) {}
    bool valid() {
        ws();
        if (!value()) return false;
        ws();
        return m_i == m_s.size();
    }

private:
    bool value() {
        if (m_i >= m_s.size()) return false;
        char c = m_s[m_i];
        if (c == '{') return object();
        if (c == '[') return array();
        if (c == '"') return string();
        if (c == '-' || (c >= '0' && c <= '9')) return number();
        return literal("true") || literal("false") || literal("null");
    }
    bool object() {
        ++m_i;
        ws();
        if (peek('}')) return ++m_i, true;
        for (;;) {
            ws();
            if (!string()) return false;
            ws();
            if (!peek(':')) return false;
            ++m_i;
            ws();
            if (!value()) return false;
            ws();
            if (peek('}')) return ++m_i, true;
            if (!peek(',')) return false;
            ++m_i;
        }
    }
    bool array() {
        ++m_i;
        ws();
        if (peek(']')) return ++m_i, true;
        for (;;) {
            ws();
            if (!value()) return false;
            ws();
            if (peek(']')) return ++m_i, true;
            if (!peek(',')) return false;
            ++m_i;
        }
    }
    bool string() {
        if (!peek('"')) return false;
        for (++m_i; m_i < m_s.size(); ++m_i) {
            unsigned char c = static_cast<unsigned char>(m_s[m_i]);
            if (c == '"') return ++m_i, true;
            if (c < 0x20) return false;
            if (c == '\\') {
                if (++m_i >= m_s.size()) return false;
                if (std::string("\"\\/bfnrtu").find(m_s[m_i]) == std::string::npos) return false;
            }
        }
        return false;
    }
    bool number() {
        size_t start = m_i;
        if (peek('-')) ++m_i;
        while (m_i < m_s.size() && (isdigit(m_s[m_i]) || std::string(".eE+-").find(m_s[m_i]) != std::string::npos)) ++m_i;
        return m_i > start;
    }
    bool literal(const char* word) {
        std::string w(word);
        if (m_s.compare(m_i, w.size(), w) != 0) return false;
        m_i += w.size();
        return true;
    }
    bool peek(char c) const { return m_i < m_s.size() && m_s[m_i] == c; }
    void ws() {
        while (m_i < m_s.size() && std::string(" \t\r\n").find(m_s[m_i]) != std::string::npos) ++m_i;
    }
    const std::string& m_s;
    size_t m_i = 0;
};

size_t count(const std::string& hay, const std::string& needle) {
    size_t n = 0;
    for (size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + 1)) ++n;
    return n;
}

TEST(PushpinCli, DemoInfoIsValidJsonWithEveryKey) {
    CliRun r = runPushpin("--demo --info");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(JsonChecker(r.out).valid()) << r.out.substr(0, 2000);
    for (const char* key : {"\"nodeTypes\"", "\"shapes\"", "\"cameras\"", "\"lights\"", "\"shadingGroups\"",
                            "\"renderGlobals\"", "\"unsupported\"", "\"warnings\"", "\"bounds\""})
        EXPECT_NE(r.out.find(key), std::string::npos) << key;
    // The demo: a floor and seven primitives, all renderable; a spotlight and an ambient fill.
    EXPECT_NE(r.out.find("\"type\": \"spotLight\""), std::string::npos);
    EXPECT_NE(r.out.find("\"type\": \"ambientLight\""), std::string::npos);
    EXPECT_NE(r.out.find("\"renderable\": 8"), std::string::npos) << r.out.substr(0, 4000);
    EXPECT_NE(r.out.find("\"skipped\": 0"), std::string::npos);
    EXPECT_NE(r.out.find("\"surfaceShader\": \"blinn\""), std::string::npos);
    EXPECT_NE(r.out.find("\"edgeAntiAliasing\": 0"), std::string::npos);
    EXPECT_NE(r.out.find("\"width\": 640"), std::string::npos);
    EXPECT_TRUE(r.err.empty()) << r.err;
}

TEST(PushpinCli, PrintedDemoReadsBackTheSame) {
    CliRun demo = runPushpin("--print-demo");
    ASSERT_EQ(demo.exitCode, 0);
    fs::path file = writeFile("softSpotlight.ma", demo.out);
    CliRun fromFile = runPushpin("--info '" + file.string() + "'");
    CliRun builtIn = runPushpin("--demo --info");
    ASSERT_EQ(fromFile.exitCode, 0) << fromFile.err;
    // Everything but the file name agrees.
    auto strip = [](std::string s) { return s.substr(s.find('\n', s.find("\"file\""))); };
    EXPECT_EQ(strip(fromFile.out), strip(builtIn.out));
}

// JSON text is UTF-8 (RFC 8259 §8.1).
bool validUtf8(std::string_view s) {
    for (size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        const size_t n = c < 0x80 ? 1 : c >= 0xC2 && c < 0xE0 ? 2 : c >= 0xE0 && c < 0xF0 ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
        if (n == 0 || i + n > s.size()) return false;
        for (size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
        i += n;
    }
    return true;
}

// Whether every channel of every pixel of the image at `path` is finite; false if it cannot be read.
bool allPixelsFinite(const fs::path& path, std::string& why) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        why = "cannot open " + path.string();
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    const bool read = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
    in->close();
    if (!read) {
        why = "cannot read " + path.string();
        return false;
    }
    for (float v : pixels)
        if (!std::isfinite(v)) {
            why = path.string() + " holds a non-finite pixel";
            return false;
        }
    return true;
}

// Every real scene, in both folders: it loads, --info exits 0 with valid JSON, and a scene with a
// renderable camera renders one frame at 160×120 with exit 0 and only finite pixels.
TEST(PushpinCli, EveryRealSceneLoadsReportsAndRenders) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    size_t files = 0, rendered = 0, withoutCamera = 0;
    const fs::path out = tempDir() / "real-scenes";
    for (const fs::path& path : pushpin::test::realSceneFiles()) {
        ++files;
        CliRun info = runPushpin("--info '" + path.string() + "'");
        EXPECT_EQ(info.exitCode, 0) << path << ": " << info.err;
        EXPECT_TRUE(JsonChecker(info.out).valid()) << path;
        EXPECT_TRUE(validUtf8(info.out)) << path;
        EXPECT_NE(info.out.find("\"shapeCounts\""), std::string::npos) << path;

        const fs::path images = out / std::to_string(files);
        CliRun render = runPushpin("--quiet --frame 1 -x 160 -y 120 -of exr -rd '" + images.string() + "' '" + path.string() + "'");
        if (render.exitCode == 1 && render.err.find("no renderable camera") != std::string::npos) {
            ++withoutCamera;
            continue;
        }
        EXPECT_EQ(render.exitCode, 0) << path << ": " << render.err;
        size_t written = 0;
        std::error_code ec;
        for (const auto& e : fs::recursive_directory_iterator(images, ec)) {
            // Every file is an image: the scene's naming convention may omit the extension (name.#).
            if (!e.is_regular_file()) continue;
            ++written;
            std::string why;
            EXPECT_TRUE(allPixelsFinite(e.path(), why)) << path << ": " << why;
        }
        EXPECT_GT(written, 0u) << path << ": no image";
        rendered += written > 0;
    }
    fs::remove_all(out);
    std::printf("%zu real scenes: %zu rendered, %zu without a renderable camera\n", files, rendered, withoutCamera);
    EXPECT_GT(files, 0u);
    EXPECT_GT(rendered, files / 2);
}

TEST(PushpinCli, MissingFileExitsOneNamingThePath) {
    CliRun r = runPushpin("--info /nonexistent/dir/scene.ma");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err.rfind("Error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("/nonexistent/dir/scene.ma"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty());
}

TEST(PushpinCli, MalformedFileGivesOneLineWithFileLineAndColumn) {
    fs::path file = writeFile("bad.ma", "//Maya ASCII 2018 scene\ncreateNode transform -n \"a\";\n\tsetAttr \".n\" -type \"string\" \"1 2;\n");
    CliRun r = runPushpin("--info '" + file.string() + "'");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err.rfind("Error: " + file.string() + ":3:", 0), 0u) << r.err;
    EXPECT_EQ(count(r.err, "\n"), 1u) << r.err;
    EXPECT_TRUE(r.out.empty());
}

TEST(PushpinCli, BadOptionsAreNamed) {
    CliRun unknown = runPushpin("--demo --info --bogus");
    EXPECT_EQ(unknown.exitCode, 2);
    EXPECT_NE(unknown.err.find("--bogus"), std::string::npos);
    CliRun frame = runPushpin("--demo --info --frame abc");
    EXPECT_EQ(frame.exitCode, 2);
    EXPECT_NE(frame.err.find("--frame"), std::string::npos);
    CliRun nan = runPushpin("--demo --info --frame nan");
    EXPECT_EQ(nan.exitCode, 2);
    CliRun missing = runPushpin("--demo --info --frame");
    EXPECT_EQ(missing.exitCode, 2);
    CliRun none = runPushpin("");
    EXPECT_EQ(none.exitCode, 2);
    EXPECT_NE(none.err.find("usage"), std::string::npos);
    EXPECT_EQ(none.err.rfind("Error: ", 0), 0u) << none.err;
    CliRun both = runPushpin("--demo --info scene.ma");
    EXPECT_EQ(both.exitCode, 2);
    EXPECT_NE(both.err.find("--demo"), std::string::npos) << both.err;
}

// The exit status of farm.md §6 for each kind of failure: the command line (2), the scene (1).
TEST(PushpinCli, ExitCodesSeparateUsageFromInput) {
    fs::path dir = tempDir() / "codes";
    fs::remove_all(dir);
    fs::create_directories(dir / "scene-folder.ma");
    CliRun folder = runPushpin("--info '" + (dir / "scene-folder.ma").string() + "'");
    EXPECT_EQ(folder.exitCode, 1);
    EXPECT_NE(folder.err.find("scene-folder.ma"), std::string::npos) << folder.err;
    EXPECT_NE(folder.err.find("folder"), std::string::npos) << folder.err;
    CliRun ok = runPushpin("--demo --info");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    CliRun renderer = runPushpin("--demo --info -r mayaHardware");
    EXPECT_EQ(renderer.exitCode, 2);
    CliRun range = runPushpin("--demo -s 5 -e 1");
    EXPECT_EQ(range.exitCode, 2);
    EXPECT_NE(range.err.find("-e"), std::string::npos) << range.err;
    CliRun format = runPushpin("--demo -of avi");
    EXPECT_EQ(format.exitCode, 2);
    EXPECT_NE(format.err.find("-of"), std::string::npos) << format.err;
}

TEST(PushpinCli, FrameOptionEvaluatesAnimation) {
    fs::path file = writeFile("anim.ma",
                              "//Maya ASCII 2018 scene\n"
                              "currentUnit -l centimeter -a degree -t film;\n"
                              "createNode transform -n \"box\";\n"
                              "createNode mesh -n \"boxShape\" -p \"box\";\n"
                              "createNode polyCube -n \"polyCube1\";\n"
                              "createNode animCurveTL -n \"box_translateX\";\n"
                              "\tsetAttr -s 2 \".kit[0:1]\" 2 2;\n"
                              "\tsetAttr -s 2 \".kot[0:1]\" 2 2;\n"
                              "\tsetAttr -s 2 \".ktv[0:1]\"  1 0 11 10;\n"
                              "connectAttr \"box_translateX.o\" \"box.tx\";\n"
                              "connectAttr \"polyCube1.out\" \"boxShape.i\";\n"
                              "connectAttr \"boxShape.iog\" \":initialShadingGroup.dsm\" -na;\n");
    CliRun at1 = runPushpin("--info --frame 1 '" + file.string() + "'");
    CliRun at6 = runPushpin("--info --frame 6 '" + file.string() + "'");
    ASSERT_EQ(at1.exitCode, 0) << at1.err;
    ASSERT_EQ(at6.exitCode, 0) << at6.err;
    EXPECT_NE(at1.out.find("\"min\": [\n"), std::string::npos);
    // Linear tangents: x goes 0 → 10 over frames 1 → 11, so at frame 6 the unit cube spans 4.5..5.5.
    EXPECT_NE(at1.out.find("-0.5"), std::string::npos);
    EXPECT_NE(at6.out.find("4.5"), std::string::npos) << at6.out;
    EXPECT_NE(at6.out.find("5.5"), std::string::npos);
}

// -proj names the project whose images folder the images go to (without -rd).
TEST(PushpinCli, ProjectFlagSendsImagesToItsImagesFolder) {
    const fs::path project = tempDir() / "proj-flag";
    fs::remove_all(project);
    fs::create_directories(project);
    std::ofstream(project / "workspace.mel") << "workspace -fr \"images\" \"frames\";\n";
    CliRun r = runPushpin("--demo -x 16 -y 12 -of png -proj '" + project.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(project / "frames" / "softSpotlight.png")) << r.err;
}

// A render flag for a feature pushpin does not render is accepted and reported: switched on it
// joins notRendered with the flag; switched off it removes what the scene asked for.
TEST(PushpinCli, RenderFlagsForMissingFeaturesAreReported) {
    fs::path dir = tempDir() / "flags";
    fs::remove_all(dir);
    fs::path stats = tempDir() / "flags-stats.json";
    CliRun r = runPushpin("--demo -x 16 -y 12 -rd '" + dir.string() + "' -edm off -mb on -mbf 0.5 --stats '" +
                          stats.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::ifstream in(stats);
    const std::string json((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(json.find("depth-map shadows"), std::string::npos) << json;
    EXPECT_NE(json.find("\"feature\": \"motion blur\""), std::string::npos) << json;
    EXPECT_NE(json.find("\"-mbf 0.5\""), std::string::npos) << json;
    EXPECT_NE(r.err.find("not rendered: motion blur (-mb on, -mbf 0.5)"), std::string::npos) << r.err;
}

}  // namespace

// ---------------------------------------------------------------- rendering

std::vector<float> readPixels(const fs::path& path, int* channels = nullptr) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    if (channels) *channels = spec.nchannels;
    return px;
}

// --tile-pattern draws the plan of the first image at its size; under a cap the plan is the
// memory-driven one and --stats says its maxTileCost; a bad path is a usage error.
TEST(PushpinCli, TilePatternDrawsThePlanAndStatsNameIt) {
    fs::path dir = tempDir() / "tile-pattern";
    fs::remove_all(dir);
    const fs::path pattern = dir / "plan.png", stats = dir / "stats.json";
    CliRun r = runPushpin("--demo -x 160 -y 120 -mm 64 -rd '" + dir.string() + "' --tile-pattern '" + pattern.string() +
                          "' --stats '" + stats.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto in = OIIO::ImageInput::open(pattern.string());
    ASSERT_TRUE(in) << pattern;
    EXPECT_EQ(in->spec().width, 160);
    EXPECT_EQ(in->spec().height, 120);
    std::ifstream file(stats);
    const std::string json((std::istreambuf_iterator<char>(file)), {});
    EXPECT_TRUE(JsonChecker(json).valid()) << json.substr(0, 2000);
    for (const char* key : {"\"maxTileCost\"", "\"minSize\"", "\"tessellation\"", "\"skippedOccluded\"", "\"peakCharged\"",
                            "\"peakRss\"", "\"byCategory\"", "\"recomputed\""})
        EXPECT_NE(json.find(key), std::string::npos) << key;
    EXPECT_EQ(json.find("\"maxTileCost\": 0,"), std::string::npos) << "a cap plans by cost";
    CliRun bad = runPushpin("--demo -x 16 -y 12 -rd '" + dir.string() + "' --tile-pattern ''");
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
}

TEST(PushpinCli, DemoRendersAnImageAndSaysWhere) {
    fs::path dir = tempDir() / "demo";
    fs::remove_all(dir);
    fs::path stats = tempDir() / "demo-stats.json";
    CliRun r = runPushpin("--demo -x 160 -y 120 -rd '" + dir.string() + "' --stats '" + stats.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    fs::path image = dir / "softSpotlight.png";
    EXPECT_TRUE(fs::exists(image));
    EXPECT_NE(r.err.find(image.string()), std::string::npos) << r.err;
    std::ifstream in(stats);
    std::string json((std::istreambuf_iterator<char>(in)), {});
    EXPECT_TRUE(JsonChecker(json).valid()) << json.substr(0, 2000);
    for (const char* key : {"\"fragments\"", "\"mergedFragments\"", "\"shadingSamplesBase\"", "\"shadingSamplesAdaptive\"",
                            "\"trianglesRasterized\"", "\"pixels\"", "\"seconds\""})
        EXPECT_NE(json.find(key), std::string::npos) << key;
    // The demo's spotlight asks for depth-map shadows, which are not rendered: said on stderr
    // once and listed under notRendered.
    EXPECT_NE(json.find("\"notRendered\": [\n    {\n      \"feature\": \"depth-map shadows\",\n      \"nodes\": [\n        \"keySpotShape\""),
              std::string::npos)
        << json.substr(json.find("notRendered"), 300);
    EXPECT_NE(r.err.find("not rendered: depth-map shadows (keySpotShape)"), std::string::npos) << r.err;
    std::vector<float> px = readPixels(image);
    ASSERT_EQ(px.size(), size_t(160) * 120 * 4);
    double alpha = 0.0;
    for (size_t i = 3; i < px.size(); i += 4) alpha += px[i];
    EXPECT_GT(alpha, 0.5 * 160 * 120);  // the floor fills most of the frame
    // Nothing but the image (no temporary files) is left in the folder.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST(PushpinCli, ThreadCountAndTileSizeDoNotChangeTheImage) {
    fs::path dir = tempDir() / "threads";
    fs::remove_all(dir);
    CliRun one = runPushpin("--demo -x 96 -y 72 -of exr -n 1 -tw 64 -th 64 -rd '" + (dir / "a").string() + "'");
    CliRun two = runPushpin("--demo -x 96 -y 72 -of exr -n 2 -tw 16 -th 16 -rd '" + (dir / "b").string() + "'");
    ASSERT_EQ(one.exitCode, 0) << one.err;
    ASSERT_EQ(two.exitCode, 0) << two.err;
    std::vector<float> a = readPixels(dir / "a" / "softSpotlight.exr");
    std::vector<float> b = readPixels(dir / "b" / "softSpotlight.exr");
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(a, b);
}

TEST(PushpinCli, BadRenderFlagsAreNamedAndWriteNothing) {
    fs::path dir = tempDir() / "bad";
    fs::remove_all(dir);
    CliRun x = runPushpin("--demo -x abc -rd '" + dir.string() + "'");
    EXPECT_EQ(x.exitCode, 2);  // usage
    EXPECT_NE(x.err.find("-x"), std::string::npos) << x.err;
    CliRun unknown = runPushpin("--demo -zz 3 -rd '" + dir.string() + "'");
    EXPECT_EQ(unknown.exitCode, 2);
    EXPECT_NE(unknown.err.find("-zz"), std::string::npos) << unknown.err;
    CliRun cam = runPushpin("--demo -cam nosuchcamera -rd '" + dir.string() + "'");
    EXPECT_EQ(cam.exitCode, 1);  // the scene has no such camera
    EXPECT_NE(cam.err.find("nosuchcamera"), std::string::npos) << cam.err;
    // A statement cut off by the end of the file: the scene is broken, nothing is rendered.
    fs::path bad = writeFile("broken.ma", "//Maya ASCII 2018 scene\ncreateNode mesh -n \"m\";\n\tsetAttr \".vt[0]\" -type \"float3\" 1 2");
    CliRun malformed = runPushpin("-rd '" + dir.string() + "' '" + bad.string() + "'");
    EXPECT_EQ(malformed.exitCode, 1);
    EXPECT_NE(malformed.err.find("broken.ma:3:"), std::string::npos) << malformed.err;
    EXPECT_FALSE(fs::exists(dir) && !fs::is_empty(dir));
}
