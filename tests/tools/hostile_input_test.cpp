// Hostile but fair inputs, generated at test time, run through the `pushpin` program the way a
// farm runs it: each must end with its documented exit status (README "Exit status") within the
// wall-clock bound and the peak memory stated beside it, never crash, and never leave output.
// Bounds are about three times what these inputs take on a 2-core machine running the suite two
// tests at a time, so they catch a return of quadratic or unbounded work, not a slow day.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "tests/support/temp_folder.h"

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct TempDir : pushpin::test::TempFolder {
    TempDir() : TempFolder("hostile") {}
};

struct Outcome {
    int exitCode = -1;      // -1: killed (by the bound or a signal)
    bool timedOut = false;
    double seconds = 0;
    double peakMiB = 0;     // the child's peak resident set (getrusage via wait4)
    std::string output;     // stdout and stderr
};

// Runs pushpin with `args` in `dir`, killing it after `limitSeconds`.
Outcome runPushpin(const std::vector<std::string>& args, const fs::path& dir, double limitSeconds) {
    const fs::path log = dir / "pushpin-output.txt";
    const std::string exe = (fs::path(PUSHPIN_BINARY_DIR) / "pushpin").string();
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (::chdir(dir.c_str()) != 0) ::_exit(126);
        FILE* f = std::fopen(log.c_str(), "w");
        if (!f) ::_exit(126);
        ::dup2(fileno(f), 1);
        ::dup2(fileno(f), 2);
        std::vector<char*> argv{const_cast<char*>(exe.c_str())};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    Outcome o;
    int status = 0;
    struct rusage usage{};
    for (;;) {
        const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
        if (done == pid) break;
        o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.seconds > limitSeconds && !o.timedOut) {
            o.timedOut = true;
            ::kill(pid, SIGKILL);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.peakMiB = double(usage.ru_maxrss) / 1024.0;
    o.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log, std::ios::binary);
    o.output.assign(std::istreambuf_iterator<char>(in), {});
    std::error_code ec;
    fs::remove(log, ec);
    return o;
}

std::ostream& operator<<(std::ostream& os, const Outcome& o) {
    return os << "exit " << o.exitCode << (o.timedOut ? " (killed at the time bound)" : "") << ", " << o.seconds
              << " s, peak " << o.peakMiB << " MiB, output: " << o.output.substr(0, 2000);
}

// The same small scene every case builds on: a camera looking at whatever the case adds.
constexpr const char* kHeader =
    "//Maya ASCII 2018 scene\n"
    "//Name: hostile.ma\n"
    "requires maya \"2018\";\n"
    "currentUnit -l centimeter -a degree -t film;\n"
    "createNode transform -n \"cam\";\n"
    "\tsetAttr \".t\" -type \"double3\" 0 0 20 ;\n"
    "createNode camera -n \"camShape\" -p \"cam\";\n"
    "\tsetAttr \".rnd\" yes;\n";

constexpr const char* kCube =
    "createNode mesh -n \"boxShape\" -p \"%s\";\n"
    "createNode polyCube -n \"polyCube1\";\n"
    "connectAttr \"polyCube1.out\" \"boxShape.i\";\n"
    "connectAttr \"boxShape.iog\" \":initialShadingGroup.dsm\" -na;\n";

std::string cubeUnder(const std::string& parent) {
    char buf[512];
    std::snprintf(buf, sizeof buf, kCube, parent.c_str());
    return buf;
}

void writeFile(const fs::path& p, const std::string& text) { pushpin::test::writeWholeFile(p, text); }
// Writes a generated scene of hundreds of megabytes and frees the text before pushpin runs, so
// that the test process does not hold it beside the child.
void writeAndRelease(const fs::path& p, std::string& text) {
    writeFile(p, text);
    std::string().swap(text);
}

std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(e.path().lexically_relative(dir).string());
    std::sort(out.begin(), out.end());
    return out;
}

// A million connections in a row: unitConversion i feeds unitConversion i+1, the last feeds the
// cube's translateX. The value must come through (2.5 × 1.0 a million times). About 3 s and
// 0.7 GB on two cores.
TEST(HostileScene, MillionConnectionChainEvaluatesInLinearTime) {
    TempDir dir;
    constexpr int kChain = 1000000;
    std::string text = kHeader;
    text.reserve(size_t(kChain) * 90);
    text += "createNode transform -n \"box\";\n" + cubeUnder("box");
    for (int i = 0; i < kChain; ++i) {
        text += "createNode unitConversion -n \"u" + std::to_string(i) + "\";\n";
        if (i == 0) text += "\tsetAttr \".i\" 2.5;\n";
    }
    for (int i = 1; i < kChain; ++i)
        text += "connectAttr \"u" + std::to_string(i - 1) + ".o\" \"u" + std::to_string(i) + ".i\";\n";
    text += "connectAttr \"u" + std::to_string(kChain - 1) + ".o\" \"box.tx\";\n";
    text += "// End of hostile.ma\n";
    writeAndRelease(dir.path / "chain.ma", text);

    const Outcome o = runPushpin({"--info", "chain.ma"}, dir.path, 10);
    EXPECT_EQ(o.exitCode, 0) << o;
    EXPECT_LT(o.peakMiB, 1536) << o;
    // The cube spans [-0.5, 0.5] about its translate: 2.5 → x from 2 to 3.
    EXPECT_NE(o.output.find("\"boxShape\""), std::string::npos) << o;
    const size_t bounds = o.output.find("\"bounds\"", o.output.find("\"boxShape\""));
    ASSERT_NE(bounds, std::string::npos) << o;
    // "bounds": {"min": [x, y, z], ...} pretty-printed: the first number after "min" is x.
    const size_t min = o.output.find('[', o.output.find("\"min\"", bounds));
    ASSERT_NE(min, std::string::npos) << o.output.substr(bounds, 200);
    EXPECT_DOUBLE_EQ(std::strtod(o.output.c_str() + min + 1, nullptr), 2.0) << o.output.substr(bounds, 200);
}

// A DAG a million transforms deep with a cube at the bottom; each level moves by 1e-6, so the
// cube sits at x = 1. Loading, --info and a render all stay linear: about 3.5 s and 0.9 GB each
// on two cores.
TEST(HostileScene, MillionDeepDagLoadsReportsAndRenders) {
    TempDir dir;
    constexpr int kDepth = 1000000;
    std::string text = kHeader;
    text.reserve(size_t(kDepth) * 80);
    for (int i = 0; i < kDepth; ++i) {
        text += "createNode transform -n \"t" + std::to_string(i) + "\"";
        if (i > 0) text += " -p \"t" + std::to_string(i - 1) + "\"";
        text += ";\n\tsetAttr \".tx\" 1e-06;\n";
    }
    text += cubeUnder("t" + std::to_string(kDepth - 1));
    text += "// End of hostile.ma\n";
    writeAndRelease(dir.path / "deep.ma", text);

    const Outcome info = runPushpin({"--info", "deep.ma"}, dir.path, 10);
    EXPECT_EQ(info.exitCode, 0) << info;
    EXPECT_LT(info.peakMiB, 1536) << info;
    const Outcome render = runPushpin({"-x", "32", "-y", "24", "-of", "png", "-rd", "out", "deep.ma"}, dir.path, 10);
    EXPECT_EQ(render.exitCode, 0) << render;
    EXPECT_LT(render.peakMiB, 1536) << render;
    EXPECT_TRUE(fs::exists(dir.path / "out" / "deep.png")) << render;
}

// A 400-byte file that references itself ten times: the cycle is refused, the load ends at once.
TEST(HostileScene, SelfReferenceTenTimesIsRefusedQuickly) {
    TempDir dir;
    std::string text = kHeader;
    for (int i = 0; i < 10; ++i) text += "file -r -ns \"n" + std::to_string(i) + "\" \"self.ma\";\n";
    text += "createNode transform -n \"box\";\n" + cubeUnder("box") + "// End of hostile.ma\n";
    writeFile(dir.path / "self.ma", text);
    const Outcome o = runPushpin({"--info", "self.ma"}, dir.path, 20);
    EXPECT_EQ(o.exitCode, 0) << o;
    EXPECT_LT(o.peakMiB, 1024) << o;
    EXPECT_NE(o.output.find("self.ma"), std::string::npos) << o;
}

// Ten references to the next level, six levels deep: a million files' worth of loading. The
// reference budget ends it with an input error naming a file.
TEST(HostileScene, ReferenceFanOutHitsTheBudget) {
    TempDir dir;
    constexpr int kLevels = 6;
    for (int level = 0; level < kLevels; ++level) {
        std::string text = kHeader;
        if (level + 1 < kLevels)
            for (int i = 0; i < 10; ++i)
                text += "file -r -ns \"r" + std::to_string(i) + "\" \"level" + std::to_string(level + 1) + ".ma\";\n";
        text += "createNode transform -n \"box\";\n" + cubeUnder("box") + "// End of hostile.ma\n";
        writeFile(dir.path / ("level" + std::to_string(level) + ".ma"), text);
    }
    const Outcome o = runPushpin({"--info", "level0.ma"}, dir.path, 60);
    EXPECT_EQ(o.exitCode, 1) << o;
    EXPECT_LT(o.peakMiB, 3072) << o;
    EXPECT_NE(o.output.find("level"), std::string::npos) << o;
    EXPECT_LT(o.output.size(), 4096u) << o;
}

// Repeated createNode lines with one name: Maya renames each to the next free number. 200 MB of
// them (7.2 million nodes) load in linear time: about 4.5 s and 0.95 GB on two cores through
// --info, where renaming by search took 54 s for 20,000 lines.
TEST(HostileScene, DuplicateNamesRenameInConstantTime) {
    TempDir dir;
    const std::string line = "createNode transform -n \"x\";\n";
    std::string text = kHeader;
    const size_t count = (size_t(200) << 20) / line.size();
    text.reserve(count * line.size() + 4096);
    for (size_t i = 0; i < count; ++i) text += line;
    text += "// End of hostile.ma\n";
    writeAndRelease(dir.path / "dupes.ma", text);
    const Outcome o = runPushpin({"--info", "dupes.ma"}, dir.path, 15);
    EXPECT_EQ(o.exitCode, 0) << o;
    EXPECT_LT(o.peakMiB, 1536) << o;
    // Every line made a transform (the camera's is the one more); the first keeps "x", the next
    // hundred renames are listed, and the rest, count - 101 of them, are counted.
    EXPECT_NE(o.output.find("\"transform\": " + std::to_string(count + 1)), std::string::npos) << o.output.substr(0, 600);
    EXPECT_NE(o.output.find("is renamed 'x100'"), std::string::npos) << o.output.substr(0, 600);
    EXPECT_NE(o.output.find(std::to_string(count - 101) + " more nodes were renamed"), std::string::npos)
        << o.output.substr(0, 600);
}

// A frame the memory cap cannot hold stops at once with exit 33 and writes nothing.
TEST(HostileScene, FrameOverTheMemoryCapExits33) {
    TempDir dir;
    writeFile(dir.path / "box.ma", std::string(kHeader) + "createNode transform -n \"box\";\n" + cubeUnder("box") +
                                       "// End of hostile.ma\n");
    fs::create_directories(dir.path / "out");
    const Outcome o = runPushpin({"-x", "32768", "-y", "32768", "-mm", "2048", "-rd", "out", "box.ma"}, dir.path, 20);
    EXPECT_EQ(o.exitCode, 33) << o;
    EXPECT_LT(o.peakMiB, 1024) << o;
    EXPECT_TRUE(filesIn(dir.path / "out").empty()) << o;
}

// A scene whose tessellations need several times the cap renders under it: the peak resident
// size stays near an empty render's plus the cap, the image is the same as without a cap, and a
// cap too small for any tile stops with exit 33 and no image.
TEST(HostileScene, MemoryCapHoldsAndKeepsTheImage) {
    TempDir dir;
    std::string spheres = kHeader;
    const int count = 40;
    for (int i = 0; i < count; ++i) {
        const std::string id = std::to_string(i);
        spheres += "createNode transform -n \"s" + id + "\";\n\tsetAttr \".t\" -type \"double3\" " +
                   std::to_string((i % 8) * 2.2 - 7.7) + " " + std::to_string((i / 8) * 2.2 - 4.4) + " 0 ;\n";
        spheres += "createNode mesh -n \"s" + id + "Shape\" -p \"s" + id + "\";\n";
        spheres += "createNode polySphere -n \"ps" + id + "\";\n\tsetAttr \".sa\" 150;\n\tsetAttr \".sh\" 150;\n";
        spheres += "connectAttr \"ps" + id + ".out\" \"s" + id + "Shape.i\";\n";
        spheres += "connectAttr \"s" + id + "Shape.iog\" \":initialShadingGroup.dsm\" -na;\n";
    }
    writeFile(dir.path / "spheres.ma", spheres + "// End of hostile.ma\n");
    writeFile(dir.path / "empty.ma", std::string(kHeader) + "// End of hostile.ma\n");
    const std::vector<std::string> size = {"-x", "320", "-y", "240", "-of", "exr"};
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), size.begin(), size.end());
        return runPushpin(args, dir.path, 60);
    };
    const Outcome empty = run({"-rd", "empty", "empty.ma"});
    const Outcome free = run({"-rd", "free", "--stats", "free.json", "spheres.ma"});
    // 16x16 tiles: each holds few spheres and few fragments (tiles sized by the cap are not there yet).
    const Outcome capped =
        run({"-mm", "48", "-tw", "16", "-th", "16", "-rd", "capped", "--stats", "capped.json", "spheres.ma"});
    ASSERT_EQ(empty.exitCode, 0) << empty;
    ASSERT_EQ(free.exitCode, 0) << free;
    ASSERT_EQ(capped.exitCode, 0) << capped;
    // 1.8M triangles: about 100 MB of tessellations, twice the cap.
    EXPECT_GT(free.peakMiB, empty.peakMiB + 2 * 48) << free;
    EXPECT_LT(capped.peakMiB, empty.peakMiB + 48 + 64) << capped << "\nempty: " << empty;
    const std::string stats = pushpin::test::readWholeFile(dir.path / "capped.json");
    EXPECT_EQ(stats.find("\"evicted\": 0,"), std::string::npos) << stats.substr(0, 2000);
    EXPECT_NE(stats.find("\"cap\": 50331648"), std::string::npos) << stats.substr(0, 2000);
    // The same pixels.
    auto pixels = [](const fs::path& p) {
        std::vector<float> out;
        auto in = OIIO::ImageInput::open(p.string());
        if (!in) return out;
        const OIIO::ImageSpec& spec = in->spec();
        out.resize(size_t(spec.width) * spec.height * spec.nchannels);
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.data())) out.clear();
        return out;
    };
    const std::vector<float> a = pixels(dir.path / "free" / "spheres.exr"), b = pixels(dir.path / "capped" / "spheres.exr");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b);

    const Outcome tiny = run({"-mm", "2", "-rd", "tiny", "spheres.ma"});
    EXPECT_EQ(tiny.exitCode, 33) << tiny;
    EXPECT_NE(tiny.output.find("memory cap of 2 MB (-mm)"), std::string::npos) << tiny;
    EXPECT_TRUE(!fs::exists(dir.path / "tiny") || filesIn(dir.path / "tiny").empty()) << tiny;
}

// Under a cap the scene's stored values count too: a file whose arrays alone pass the cap stops
// with exit 33 before any frame, naming them, and writes nothing.
TEST(HostileScene, StoredValuesOverTheMemoryCapExit33) {
    TempDir dir;
    std::string text = std::string(kHeader) + "createNode transform -n \"cloud\";\n" + cubeUnder("cloud");
    text += "createNode mesh -n \"storedShape\" -p \"cloud\";\n\tsetAttr -s 200000 \".vt[0:199999]\"";
    for (int i = 0; i < 200000; ++i) text += " " + std::to_string(i % 97) + " 0 1";
    text += ";\n// End of hostile.ma\n";
    writeFile(dir.path / "cloud.ma", text);
    fs::create_directories(dir.path / "out");
    const Outcome o = runPushpin({"-x", "32", "-y", "24", "-mm", "2", "-rd", "out", "cloud.ma"}, dir.path, 30);
    EXPECT_EQ(o.exitCode, 33) << o;
    EXPECT_NE(o.output.find("the loaded scene holds "), std::string::npos) << o;
    EXPECT_NE(o.output.find("over the memory cap of 2 MB (-mm)"), std::string::npos) << o;
    EXPECT_TRUE(filesIn(dir.path / "out").empty()) << o;
    const Outcome free = runPushpin({"-x", "32", "-y", "24", "-rd", "out", "cloud.ma"}, dir.path, 30);
    EXPECT_EQ(free.exitCode, 0) << free;
}

// Numbers that overflow: the camera and the object are reported, not rendered into NaN, and
// the process is clean (the tests also run under UBSan in the sanitizer build).
TEST(HostileScene, OverflowingNumbersAreNotedNotRendered) {
    TempDir dir;
    std::string text = kHeader;
    text += "createNode transform -n \"far\";\n\tsetAttr \".t\" -type \"double3\" 1e308 0 0 ;\n" + cubeUnder("far");
    text += "// End of hostile.ma\n";
    writeFile(dir.path / "far.ma", text);
    const Outcome far = runPushpin({"-x", "16", "-y", "12", "-rd", "out", "far.ma"}, dir.path, 20);
    EXPECT_EQ(far.exitCode, 0) << far;
    EXPECT_NE(far.output.find("far"), std::string::npos) << far;

    std::string cam = kHeader;
    cam += "\tsetAttr \".fl\" 1e308;\ncreateNode transform -n \"box\";\n" + cubeUnder("box") + "// End of hostile.ma\n";
    writeFile(dir.path / "focal.ma", cam);
    const Outcome focal = runPushpin({"-x", "16", "-y", "12", "-rd", "out2", "focal.ma"}, dir.path, 20);
    EXPECT_EQ(focal.exitCode, 1) << focal;
    EXPECT_NE(focal.output.find("camShape"), std::string::npos) << focal;
    EXPECT_FALSE(fs::exists(dir.path / "out2" / "focal.iff")) << focal;
}

// A folder given as the scene is an input error, not an empty scene.
TEST(HostileScene, DirectoryIsNotAScene) {
    TempDir dir;
    fs::create_directories(dir.path / "scene.ma");
    const Outcome o = runPushpin({"scene.ma"}, dir.path, 20);
    EXPECT_EQ(o.exitCode, 1) << o;
    EXPECT_NE(o.output.find("scene.ma"), std::string::npos) << o;
}

// A 50 MB token is quoted, not echoed: the error stays one short line.
TEST(HostileScene, HugeTokenIsQuotedShort) {
    TempDir dir;
    std::string text = kHeader;
    text += "createNode transform -n \"" + std::string(size_t(50) << 20, 'q') + "\" -p \"nowhere\";\n";
    text += "// End of hostile.ma\n";
    writeFile(dir.path / "token.ma", text);
    // The node cannot be made (its parent does not exist): the scene loads without it, and the
    // warning names the parent, not the 50 MB name.
    const Outcome o = runPushpin({"--info", "token.ma"}, dir.path, 30);
    EXPECT_EQ(o.exitCode, 0) << o.exitCode;
    EXPECT_LT(o.output.size(), 8192u) << o.output.size() << " bytes of output";
    EXPECT_EQ(o.output.find(std::string(201, 'q')), std::string::npos);
    EXPECT_NE(o.output.find("no node named 'nowhere'"), std::string::npos) << o.output.substr(0, 2000);

    const Outcome prefix =
        runPushpin({"--demo", "-x", "8", "-y", "6", "-rd", "out", "-im", std::string(120000, 'p')}, dir.path, 30);
    EXPECT_TRUE(prefix.exitCode == 1 || prefix.exitCode == 2) << prefix;
    EXPECT_LT(prefix.output.size(), 2048u) << prefix.output.size() << " bytes of output";
}

}  // namespace
