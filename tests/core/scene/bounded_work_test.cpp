// Hostile scene shapes that must cost work and memory in proportion to their size: million-long
// connection chains, million-deep and diamond-shaped DAGs, self-referencing and fanning-out
// references, thousands of identical names, huge tokens, directories and truncated files.
// Every input is generated at test time. The heavy cases run in a forked child so that the time
// and the peak memory (getrusage of the child) of the work alone are measured; each bound is about
// ten times what the work took on the 2-core build machine, and is stated next to the case.
#include "cache/error.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"

#include <gtest/gtest.h>

#include "tests/support/temp_folder.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>

namespace pushpin::scene {
namespace {

namespace fs = std::filesystem;

struct ChildRun {
    int exitCode = -1;      // the work's return value; 100+ for an exception, -1 for a signal
    double seconds = 0.0;   // wall-clock time of the child
    double peakMiB = 0.0;   // the child's peak resident memory above what it inherited at fork
};

// A line of /proc/self/status ("VmRSS", "VmHWM") in MiB.
double statusMiB(const char* field) {
    double kib = 0.0;
    if (FILE* f = std::fopen("/proc/self/status", "r")) {
        char line[256];
        const size_t n = std::strlen(field);
        while (std::fgets(line, sizeof line, f))
            if (std::strncmp(line, field, n) == 0 && line[n] == ':') kib = std::atof(line + n + 1);
        std::fclose(f);
    }
    return kib / 1024.0;
}

// Runs `work` in a forked child; it returns 0 when its own checks pass (it prints why otherwise).
// The child resets its peak-RSS mark (/proc/self/clear_refs, "5") so that the peak it reports is
// that of the work, above what it inherited.
ChildRun runInChild(const std::function<int()>& work) {
    std::fflush(nullptr);
    int pipeFds[2];
    if (pipe(pipeFds) != 0) return {};
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        close(pipeFds[0]);
        if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
            std::fputs("5", f);
            std::fclose(f);
        }
        const double before = statusMiB("VmRSS");
        int code = 100;
        try {
            code = work();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child threw: %.300s\n", e.what());
        }
        const double peak = statusMiB("VmHWM") - before;
        if (write(pipeFds[1], &peak, sizeof peak) != ssize_t(sizeof peak)) code = 101;
        std::fflush(nullptr);
        _exit(code);
    }
    close(pipeFds[1]);
    ChildRun run;
    if (pid < 0) {
        close(pipeFds[0]);
        return run;
    }
    if (read(pipeFds[0], &run.peakMiB, sizeof run.peakMiB) != ssize_t(sizeof run.peakMiB)) run.peakMiB = 1e9;
    close(pipeFds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

// Fails the test unless the child passed within `maxSeconds` and `maxMiB`.
void expectBounded(const char* what, const ChildRun& run, double maxSeconds, double maxMiB) {
    EXPECT_EQ(run.exitCode, 0) << what << ": the child's checks failed (see its stderr)";
    EXPECT_LT(run.seconds, maxSeconds) << what;
    EXPECT_LT(run.peakMiB, maxMiB) << what;
    std::printf("[ bounded  ] %s: %.2f s, %.0f MiB peak above the parent\n", what, run.seconds, run.peakMiB);
}

void set(Graph& g, NodeId n, const char* path, std::vector<double> v, Numbers::Kind kind = Numbers::Kind::Plain) {
    const int width = kind == Numbers::Kind::Tuple ? int(v.size()) : 1;
    g.setValue(n, *parsePlugPath(path), Numbers{kind, width, std::move(v)});
}

// `levels` levels of two transforms ("a<i>", "b<i>"), each a child of both transforms of the
// level above, and a mesh "shape" under both of the last: 2^levels DAG paths to the shape.
NodeId addDiamondDag(Graph& g, int levels) {
    NodeId above[2] = {g.createNode("transform", "a0"), g.createNode("transform", "b0")};
    for (int level = 1; level < levels; ++level) {
        NodeId here[2];
        for (int k = 0; k < 2; ++k) {
            here[k] = g.createNode("transform", std::string(k ? "b" : "a") + std::to_string(level), above[0]);
            g.setParent(here[k], above[1], true);
        }
        above[0] = here[0];
        above[1] = here[1];
    }
    const NodeId shape = g.createNode("mesh", "shape", above[0]);
    g.setParent(shape, above[1], true);
    return shape;
}

// A temporary folder removed at the end of a test.
struct TempDir : pushpin::test::TempFolder {
    TempDir() : TempFolder("bounded") {}
    fs::path write(const std::string& name, const std::string& text) const {
        fs::path p = path / name;
        pushpin::test::writeWholeFile(p, text);
        return p;
    }
};

// ------------------------------------------------------------------ connection chains

TEST(BoundedWork, LongConnectionChainEvaluatesWithoutRecursion) {
    // u0 → u1 → … → u149999 (unitConversion, output → input) → t.translateX, 7 times as long as
    // the chain that overflowed the stack of a recursive evaluator. Every 15,000th node doubles;
    // the end of the chain is 3 · 2^10. Measured on 2 shared cores: 3 s, 120 MiB (graph included).
    constexpr int kChain = 150000;
    const ChildRun run = runInChild([] {
        Graph g;
        std::vector<NodeId> u(kChain);
        for (int i = 0; i < kChain; ++i) {
            u[i] = g.createNode("unitConversion", "u" + std::to_string(i));
            if (i % 15000 == 14999) set(g, u[i], "conversionFactor", {2.0});
            if (i > 0) g.connect(Plug{u[i - 1], "output"}, Plug{u[i], "input"});
        }
        set(g, u[0], "input", {3.0});
        const NodeId t = g.createNode("transform", "t");
        g.connect(Plug{u[kChain - 1], "output"}, Plug{t, "translateX"});
        Evaluator ev(g, 1.0);
        const double x = ev.getDouble(t, "translateX", -1.0);
        const glm::dmat4 world = ev.worldMatrix(g.firstDagPath(t));
        if (x != 3.0 * 1024.0 || world[3][0] != 3.0 * 1024.0) {
            std::fprintf(stderr, "translateX %g, world x %g\n", x, world[3][0]);
            return 1;
        }
        return ev.diagnostics().empty() ? 0 : 2;
    });
    expectBounded("150,000-long unitConversion chain", run, 30.0, 1200.0);
}

TEST(BoundedWork, ConnectionCycleIsReportedOnceAndBroken) {
    Graph g;
    const NodeId a = g.createNode("transform", "a");
    const NodeId b = g.createNode("transform", "b");
    set(g, a, "translateX", {5.0});
    set(g, b, "translateX", {7.0});
    g.connect(Plug{a, "translateX"}, Plug{b, "translateX"});
    g.connect(Plug{b, "translateX"}, Plug{a, "translateX"});
    Evaluator ev(g, 1.0);
    // a.tx ← b.tx ← a.tx (on the stack): broken with a's static 5, which then flows round.
    EXPECT_EQ(ev.getDouble(a, "translateX", -1.0), 5.0);
    EXPECT_EQ(ev.getDouble(b, "translateX", -1.0), 5.0);
    EXPECT_EQ(ev.getDouble(a, "translateX", -1.0), 5.0);
    ASSERT_EQ(ev.diagnostics().size(), 1u);
    EXPECT_NE(ev.diagnostics()[0].message.find("connection cycle through 'a.translateX'"), std::string::npos)
        << ev.diagnostics()[0].message;
}

// ------------------------------------------------------------------ deep and wide DAGs

TEST(BoundedWork, DeepDagPlacesItsShapesAndReportsThem) {
    // g0 > g1 > … > g149999, each translated by (1, 0, 0), with a mesh and a point light at the
    // bottom: world x = 150,000 (a recursive DAG walk overflowed the stack at 80,000 and took
    // quadratic time). Measured on 2 shared cores: 5 s, 140 MiB (graph included).
    constexpr int kDepth = 150000;
    const ChildRun run = runInChild([] {
        Graph g;
        NodeId parent = kNoNode;
        for (int i = 0; i < kDepth; ++i) {
            parent = g.createNode("transform", "g" + std::to_string(i), parent);
            set(g, parent, "translate", {1.0, 0.0, 0.0}, Numbers::Kind::Tuple);
        }
        const NodeId shape = g.createNode("mesh", "shape", parent);
        const NodeId light = g.createNode("pointLight", "bulb", parent);
        const auto paths = g.dagPaths(shape);
        if (paths.size() != 1 || paths[0].size() != size_t(kDepth) + 1 || g.firstDagPath(shape) != paths[0]) return 1;
        Evaluator ev(g, 1.0);
        const glm::dmat4 world = ev.worldMatrix(paths[0]);
        if (world[3][0] != double(kDepth)) {
            std::fprintf(stderr, "world x %g\n", world[3][0]);
            return 2;
        }
        if (!ev.hiddenReason(paths[0]).empty()) return 3;
        const RenderSetup setup = extractRenderSetup(g);
        if (setup.lights.size() != 1 || setup.lights[0].shape != light || setup.lights[0].path.size() != size_t(kDepth) + 1)
            return 4;
        const std::string json = sceneInfoJson(g, 1.0);
        if (json.find("|g149999|shape") == std::string::npos) return 5;
        // Finding the bottom by its full path walks the million levels once.
        std::string full;
        for (int i = 0; i < kDepth; ++i) full += "|g" + std::to_string(i);
        if (g.find(full + "|shape") != shape) return 6;
        return 0;
    });
    expectBounded("150,000-deep DAG", run, 50.0, 1400.0);
}

TEST(BoundedWork, DiamondDagPathsStopAtTheBudget) {
    // 40 levels of two nodes, each a child of both nodes of the level above: 2^40 paths to the
    // shape. Enumeration stops at the budget, and name lookups do not walk every path.
    Graph g;
    const NodeId shape = addDiamondDag(g, 40);
    DagPathBudget budget;
    budget.maxPaths = 5000;
    const auto start = std::chrono::steady_clock::now();
    const auto paths = g.dagPaths(shape, &budget);
    EXPECT_TRUE(budget.exhausted);
    EXPECT_EQ(paths.size(), 5000u);
    EXPECT_EQ(paths[0].size(), 41u);
    EXPECT_EQ(g.dagPathName(paths[0]).rfind("|a0|a1|a2|", 0), 0u);
    std::string path;
    for (int level = 0; level < 40; ++level) path += (level % 2 ? "|b" : "|a") + std::to_string(level);
    EXPECT_EQ(g.find(path + "|shape"), shape);
    EXPECT_EQ(g.find(path + "|nothing"), kNoNode);
    const std::string message = dagPathBudgetMessage(g, shape, budget);
    EXPECT_NE(message.find("'shape'"), std::string::npos) << message;
    // Measured: well under 0.1 s.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
}

TEST(BoundedWork, DiamondDagInTheSceneReportIsCutWithOneWarning) {
    // The scene report lists every instance of a shape: 2^25 here, cut at the default budget
    // (2^24 path nodes: 645,277 paths of 26 nodes) with one warning naming the shape. Measured on
    // 2 shared cores: 4.3 s, 410 MiB.
    const ChildRun run = runInChild([] {
        Graph g;
        addDiamondDag(g, 25);
        const SceneReport report = describeScene(g, 1.0);
        int cut = 0;
        for (const std::string& w : report.warnings)
            if (w.find("'shape': DAG instance paths not all listed") != std::string::npos) ++cut;
        if (cut != 1 || report.shapes.size() != DagPathBudget::kDefaultMaxPathNodes / 26) {
            std::fprintf(stderr, "%d warnings, %zu shapes\n", cut, report.shapes.size());
            return 1;
        }
        return 0;
    });
    expectBounded("2^25-path diamond DAG in the scene report", run, 45.0, 4000.0);
}

// ------------------------------------------------------------------ references

TEST(BoundedWork, TenfoldSelfReferenceIsRefusedTenTimes) {
    // 400 bytes that reference themselves ten times: each reference is refused with a warning
    // naming its line. Measured: 30 ms, 3 MiB.
    TempDir dir;
    std::string text = "//Maya ASCII 2018 scene\ncreateNode transform -n \"t\";\n";
    for (int i = 0; i < 10; ++i) text += "file -r -ns \"a\" \"self.ma\";\n";
    text += "// End of self.ma\n";
    const fs::path scene = dir.write("self.ma", text);
    const ChildRun run = runInChild([&] {
        Graph g = MaReader::readFile(scene);
        if (!g.references.empty() || g.warnings().size() != 10) return 1;
        for (size_t i = 0; i < 10; ++i) {
            const Diagnostic& d = g.warnings()[i];
            if (d.line != 3 + i || d.message.find("already being loaded (self.ma -> self.ma)") == std::string::npos) {
                std::fprintf(stderr, "%u: %s\n", d.line, d.message.c_str());
                return 2;
            }
        }
        return 0;
    });
    expectBounded("tenfold self-reference", run, 3.0, 64.0);
}

TEST(BoundedWork, ReferenceFanOutStopsAtTheBudgetNamingFileAndLine) {
    // f0 references f1 ten times, f1 references f2 ten times, … (10^7 loads at depth 7). The
    // default budget of 10,000 references ends it. Measured: 1.6 s, 17 MiB.
    TempDir dir;
    for (int d = 0; d < 8; ++d) {
        std::string text = "createNode transform -n \"t\";\n";
        if (d < 7)
            for (int i = 0; i < 10; ++i)
                text += "file -r -ns \"n" + std::to_string(i) + "\" \"f" + std::to_string(d + 1) + ".ma\";\n";
        dir.write("f" + std::to_string(d) + ".ma", text);
    }
    const ChildRun run = runInChild([&] {
        try {
            MaReader::readFile(dir.path / "f0.ma");
        } catch (const ParseError& e) {
            const std::string what = e.what();
            if (what.find("more than 10000 references loaded") == std::string::npos ||
                e.file().find(".ma") == std::string::npos || e.line() < 2) {
                std::fprintf(stderr, "%s\n", what.c_str());
                return 2;
            }
            return 0;
        }
        return 1;
    });
    expectBounded("reference fan-out", run, 16.0, 200.0);

    // The byte budget ends it too.
    ReadOptions small;
    small.maxReferenceBytes = 1000;
    try {
        MaReader::readFile(dir.path / "f0.ma", small);
        ADD_FAILURE() << "the byte budget did not stop the load";
    } catch (const ParseError& e) {
        EXPECT_NE(std::string(e.what()).find("would exceed 1000 bytes"), std::string::npos) << e.what();
    }
}

// ------------------------------------------------------------------ names

TEST(BoundedWork, ThousandsOfIdenticalNamesAreRenamedInLinearTime) {
    // 200,000 × `createNode transform -n "x";` (6 MB): x, x1, x2, … Measured: 1.1 s, 82 MiB.
    constexpr int kCount = 200000;
    const ChildRun run = runInChild([] {
        std::string text;
        for (int i = 0; i < kCount; ++i) text += "createNode transform -n \"x\";\n";
        Graph g = MaReader::readString(text, "dup.ma");
        if (g.find("x") == kNoNode || g.find("x1") == kNoNode || g.find("x" + std::to_string(kCount - 1)) == kNoNode ||
            g.find("x" + std::to_string(kCount)) != kNoNode)
            return 1;
        // 100 renames listed one by one, then one line for the rest.
        if (g.warnings().size() != 101 ||
            g.warnings().back().message.find(std::to_string(kCount - 101) + " more nodes were renamed") ==
                std::string::npos) {
            std::fprintf(stderr, "%zu warnings\n", g.warnings().size());
            return 2;
        }
        return 0;
    });
    expectBounded("200,000 identical names", run, 11.0, 800.0);
}

TEST(BoundedWork, ManyDagNodesSharingOneNameStayLinear) {
    // 100,000 transforms "p<i>", each with a child "x"; then 100,000 `createNode transform -n "x"`
    // at world level (the first keeps "x", the rest become x1, x2 …) and a connection to every
    // "p<i>|x" by path. A search along the name's nodes would make each line cost 100,000 steps.
    constexpr int kCount = 100000;
    const ChildRun run = runInChild([] {
        std::string text;
        for (int i = 0; i < kCount; ++i)
            text += "createNode transform -n \"p" + std::to_string(i) + "\";\ncreateNode transform -n \"x\" -p \"p" +
                    std::to_string(i) + "\";\n";
        for (int i = 0; i < kCount; ++i) text += "createNode transform -n \"x\";\n";
        for (int i = 0; i < kCount; ++i) text += "setAttr \"p" + std::to_string(i) + "|x.tx\" 1;\n";
        for (int i = 0; i < kCount; ++i) text += "setAttr \"|x" + std::to_string(i + 1 < kCount ? i + 1 : 1) + ".ty\" 2;\n";
        Graph g = MaReader::readString(text, "shared.ma");
        const NodeId worldX = g.find("|x");
        if (worldX == kNoNode || !g.node(worldX).parents().empty()) return 1;
        if (g.find("x") != g.find("|p0|x")) return 2;  // the first created "x" is p0's child
        if (g.find("x" + std::to_string(kCount - 1)) == kNoNode || g.find("x" + std::to_string(kCount)) != kNoNode) return 3;
        const NodeId last = g.find("p" + std::to_string(kCount - 1) + "|x");
        if (last == kNoNode || g.getDouble(last, "translateX") != 1.0) return 4;
        if (g.getDouble(g.find("x5"), "translateY") != 2.0) return 5;
        return 0;
    });
    expectBounded("100,000 DAG nodes named x", run, 20.0, 800.0);
}

TEST(BoundedWork, RenamingAwayFreesTheNumberForTheNextClash) {
    // As Maya numbers: the smallest free trailing number, also after a rename freed one.
    Graph g = MaReader::readString("createNode transform -n \"x\";\n"
                                   "createNode transform -n \"x\";\n"   // x1
                                   "createNode transform -n \"x\";\n"   // x2
                                   "rename \"x1\" \"y\";\n"
                                   "createNode transform -n \"x\";\n"   // x1 again
                                   "createNode transform -n \"x\";\n"   // x3
                                   "createNode mesh;\n"                 // mesh1
                                   "createNode transform -n \"mesh2\";\n"
                                   "createNode mesh;\n",                // mesh3
                                   "names.ma");
    for (const char* name : {"x", "x1", "x2", "x3", "y", "mesh1", "mesh2", "mesh3"})
        EXPECT_NE(g.find(name), kNoNode) << name;
    EXPECT_EQ(g.node(g.find("x1")).type, "transform");
    EXPECT_GT(g.find("x1"), g.find("x2"));  // created after x2
}

// ------------------------------------------------------------------ files and tokens

TEST(BoundedWork, LongTokenIsQuotedToTwoHundredCharacters) {
    const std::string name(5 << 20, 'a');
    {
        // A connection from a node that does not exist: skipped, with a warning that quotes it shortly.
        Graph g = MaReader::readString("createNode transform -n \"t\";\nconnectAttr \"" + name + ".tx\" \"t.tx\";\n", "long.ma");
        ASSERT_EQ(g.warnings().size(), 1u);
        const Diagnostic& d = g.warnings()[0];
        EXPECT_EQ(d.line, 2u);
        EXPECT_LT(d.message.size(), 600u);
        EXPECT_NE(d.message.find(std::string(200, 'a') + "... (" + std::to_string(name.size()) + " bytes)"),
                  std::string::npos)
            << d.message.substr(0, 600);
        EXPECT_LT(d.node.size(), 250u);
    }
    try {
        // The same name in a statement cut off by the end of the file: an error, quoted as shortly.
        MaReader::readString("createNode transform -n \"t\";\nconnectAttr \"" + name + ".tx\" \"t.tx\"", "long.ma");
        ADD_FAILURE() << "a truncated statement was accepted";
    } catch (const ParseError& e) {
        EXPECT_LT(std::string(e.what()).size(), 600u);
        EXPECT_NE(std::string(e.what()).find("long.ma:2:"), std::string::npos);
        EXPECT_LT(e.node().size(), 250u);
    }
    // A duplicate of a long name: the rename warning quotes both names shortly.
    const std::string text = "createNode transform -n \"" + name + "\";\ncreateNode transform -n \"" + name + "\";\n";
    Graph g = MaReader::readString(text, "long.ma");
    ASSERT_EQ(g.warnings().size(), 1u);
    EXPECT_LT(g.warnings()[0].message.size(), 700u);
    EXPECT_LT(g.warnings()[0].node.size(), 250u);
}

TEST(BoundedWork, DirectoryIsNotAScene) {
    TempDir dir;
    try {
        MaReader::readFile(dir.path);
        ADD_FAILURE() << "a directory was read as a scene";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(dir.path.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
    }
    EXPECT_THROW(MaReader::readFile("/dev/null"), IoError);
}

TEST(BoundedWork, MayaFileWithoutItsEndCommentIsFlaggedAsTruncated) {
    const std::string head = "//Maya ASCII 2018 scene\n//Name: cut.ma\ncreateNode transform -n \"a\";\n";
    Graph cut = MaReader::readString(head + "createNode transform -n \"b\";\n", "cut.ma");
    EXPECT_NE(cut.find("b"), kNoNode);  // the load goes on
    ASSERT_EQ(cut.warnings().size(), 1u);
    EXPECT_EQ(cut.warnings()[0].file, "cut.ma");
    EXPECT_EQ(cut.warnings()[0].line, 4u);  // where its last command ends
    EXPECT_NE(cut.warnings()[0].message.find("may be truncated"), std::string::npos) << cut.warnings()[0].message;

    Graph whole = MaReader::readString(head + "// End of cut.ma\n", "cut.ma");
    EXPECT_TRUE(whole.warnings().empty());
    // Commands after the end comment: the file was not written by Maya as it stands.
    Graph appended = MaReader::readString(head + "// End of cut.ma\ncreateNode transform -n \"c\";\n", "cut.ma");
    EXPECT_EQ(appended.warnings().size(), 1u);
    // Hand-written text without Maya's header is not judged.
    Graph hand = MaReader::readString("createNode transform -n \"a\";\n", "hand.ma");
    EXPECT_TRUE(hand.warnings().empty());
}

}  // namespace
}  // namespace pushpin::scene
