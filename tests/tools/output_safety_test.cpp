// Runs the `pushpin` program against hostile output conditions and checks that every frame on
// disk is whole or absent: a real full file system (a small tmpfs when running as root, a file
// size limit otherwise), a sequence that fills the disk part way, symbolic links planted at
// predictable temporary names, two renders sharing a folder, SIGTERM/SIGINT while writing, image
// prefixes that try to leave the output folder, and the exit status of each (farm.md §6: 0 done,
// 1 scene error, 2 usage, 75 output failure, 130/143 after SIGINT/SIGTERM).
#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include "tests/support/temp_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct TempDir : pushpin::test::TempFolder {
    TempDir() : TempFolder("output") {}
};

std::string readAll(const fs::path& p) { return pushpin::test::readWholeFile(p); }

void writeFile(const fs::path& p, const std::string& text) { pushpin::test::writeWholeFile(p, text); }

struct Outcome {
    int exitCode = -1;  // the exit status, or -1 when a signal ended the process
    int signal = 0;
    std::string output;  // stdout and stderr
};

std::ostream& operator<<(std::ostream& os, const Outcome& o) {
    return os << "exit " << o.exitCode << (o.signal ? " signal " + std::to_string(o.signal) : "") << ": "
              << o.output.substr(0, 2000);
}

struct RunOptions {
    fs::path cwd;                 // empty: the test's working folder
    uint64_t fileSizeLimit = 0;   // RLIMIT_FSIZE in bytes with SIGXFSZ ignored; 0: none
};

// Starts pushpin with `args`; stdout and stderr go to `log`. The child stops itself (SIGSTOP)
// before exec when `stopBeforeExec`, so the caller knows its pid before pushpin runs.
pid_t startPushpin(const std::vector<std::string>& args, const fs::path& log, const RunOptions& options,
                   bool stopBeforeExec = false) {
    const std::string exe = (fs::path(PUSHPIN_BINARY_DIR) / "pushpin").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (!options.cwd.empty() && ::chdir(options.cwd.c_str()) != 0) ::_exit(126);
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0) ::_exit(126);
        ::dup2(fd, 1);
        ::dup2(fd, 2);
        if (options.fileSizeLimit > 0) {
            // A write past the limit then fails with EFBIG instead of killing the process: the
            // same path through the code as ENOSPC on a full disk.
            ::signal(SIGXFSZ, SIG_IGN);
            struct rlimit limit = {options.fileSizeLimit, options.fileSizeLimit};
            if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(126);
        }
        if (stopBeforeExec) ::raise(SIGSTOP);
        std::vector<char*> argv{const_cast<char*>(exe.c_str())};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    return pid;
}

Outcome waitFor(pid_t pid, const fs::path& log) {
    Outcome o;
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status)) o.exitCode = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
    o.output = readAll(log);
    return o;
}

Outcome runPushpin(const std::vector<std::string>& args, const RunOptions& options = {}) {
    TempDir logDir;
    const fs::path log = logDir.path / "output.txt";
    return waitFor(startPushpin(args, log, options), log);
}

// Every file under `dir` with its size and content, for before/after comparisons.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string name = e.path().lexically_relative(dir).string();
        if (e.is_symlink()) files[name] = "link -> " + fs::read_symlink(e.path()).string();
        else if (e.is_regular_file()) files[name] = std::to_string(e.file_size()) + " bytes: " + readAll(e.path());
        else files[name] = "folder";
    }
    return files;
}

std::vector<std::string> names(const std::map<std::string, std::string>& files) {
    std::vector<std::string> out;
    for (const auto& [name, content] : files) out.push_back(name);
    return out;
}

// Whether OpenImageIO reads `path` as a whole width × height image.
bool wholeImage(const fs::path& path, int width, int height) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return false;
    const OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    in->close();
    return ok && spec.width == width && spec.height == height;
}

// A small valid image written straight through OpenImageIO: the "good existing frame".
void writeSmallImage(const fs::path& path) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out) << path;
    OIIO::ImageSpec spec(8, 8, 3, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> px(8 * 8 * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<unsigned char>(i * 37);
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    ASSERT_TRUE(out->close());
}

// A file system that can be filled: a tmpfs mounted in a temporary folder when the test runs as
// root (as CI does), else an ordinary folder where pushpin runs with a file size limit.
class FillableFolder {
public:
    explicit FillableFolder(uint64_t sizeBytes) {
        path = m_dir.path / "disk";
        fs::create_directories(path);
        if (::geteuid() == 0) {
            const std::string options = "size=" + std::to_string(sizeBytes);
            m_mounted = ::mount("tmpfs", path.c_str(), "tmpfs", 0, options.c_str()) == 0;
        }
    }
    ~FillableFolder() {
        if (m_mounted) ::umount2(path.c_str(), MNT_DETACH);
    }
    bool realDisk() const { return m_mounted; }

    // Leaves `freeBytes` (rounded down to whole pages) writable: a filler file takes the rest of
    // the tmpfs. Without the mount, the child's file size limit plays the same part.
    void fill(uint64_t freeBytes) {
        if (!m_mounted) {
            m_limit = std::max<uint64_t>(freeBytes, 1);
            return;
        }
        const fs::path filler = path / "filler";
        const int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ASSERT_GE(fd, 0);
        std::vector<char> block(4096, 'f');
        off_t size = 0;
        for (;;) {
            const ssize_t n = ::write(fd, block.data(), block.size());
            if (n <= 0) break;
            size += n;
        }
        ASSERT_EQ(errno, ENOSPC);
        ASSERT_EQ(::ftruncate(fd, std::max<off_t>(0, size - off_t(freeBytes / 4096 * 4096))), 0);
        ::close(fd);
    }
    // Empties the folder (the filler too).
    void clear() {
        for (const auto& e : fs::directory_iterator(path)) fs::remove_all(e.path());
        m_limit = 0;
    }
    RunOptions options() const { return RunOptions{{}, m_limit}; }

    fs::path path;

private:
    TempDir m_dir;
    bool m_mounted = false;
    uint64_t m_limit = 0;
};

// A camera, and a cube that is out of view at frame 1 and fills much of the view at frames 2
// and 3, so frame 1's image is far smaller than the others.
constexpr const char* kAnimatedScene =
    "//Maya ASCII 2018 scene\n"
    "requires maya \"2018\";\n"
    "currentUnit -l centimeter -a degree -t film;\n"
    "createNode transform -n \"cam\";\n"
    "\tsetAttr \".t\" -type \"double3\" 0 0 20 ;\n"
    "createNode camera -n \"camShape\" -p \"cam\";\n"
    "\tsetAttr \".rnd\" yes;\n"
    "createNode transform -n \"box\";\n"
    "createNode mesh -n \"boxShape\" -p \"box\";\n"
    "createNode polyCube -n \"polyCube1\";\n"
    "createNode animCurveTL -n \"box_translateX\";\n"
    "\tsetAttr -s 3 \".ktv[0:2]\"  1 1000 2 0 3 0;\n"
    "\tsetAttr -s 3 \".kit[0:2]\" 2 2 2;\n"
    "\tsetAttr -s 3 \".kot[0:2]\" 2 2 2;\n"
    "createNode animCurveTL -n \"box_translateZ\";\n"
    "\tsetAttr -s 3 \".ktv[0:2]\"  1 0 2 17 3 17.5;\n"
    "\tsetAttr -s 3 \".kit[0:2]\" 2 2 2;\n"
    "\tsetAttr -s 3 \".kot[0:2]\" 2 2 2;\n"
    "connectAttr \"box_translateX.o\" \"box.tx\";\n"
    "connectAttr \"box_translateZ.o\" \"box.tz\";\n"
    "connectAttr \"polyCube1.out\" \"boxShape.i\";\n"
    "connectAttr \"boxShape.iog\" \":initialShadingGroup.dsm\" -na;\n"
    "// End of anim.ma\n";

// The same scene with defaultRenderGlobals.imageFilePrefix set to `prefix`.
std::string sceneWithPrefix(const std::string& prefix) {
    std::string text = kAnimatedScene;
    const size_t end = text.find("// End of");
    text.insert(end, "select -ne :defaultRenderGlobals;\n\tsetAttr \".ifp\" -type \"string\" \"" + prefix + "\";\n");
    return text;
}

// ---------------------------------------------------------------- full disk

// Every format pushpin writes, into a file system with one page left: exit 75, a message naming
// the image, and the folder exactly as before, including a good frame of the same name.
class FullDisk : public ::testing::TestWithParam<const char*> {};

TEST_P(FullDisk, FailedFrameLeavesTheFolderAsItWas) {
    const std::string format = GetParam();
    FillableFolder disk(256 << 10);
    const fs::path existing = disk.path / ("softSpotlight." + format);  // each -of name is its extension
    writeSmallImage(existing);
    disk.fill(4096);
    const auto before = snapshot(disk.path);

    // 160 × 120 gives more than 4 KB in every format (JPEG, the smallest, about 5 KB).
    const Outcome o = runPushpin({"--demo", "-x", "160", "-y", "120", "-of", format, "-rd", disk.path.string()},
                                 disk.options());
    EXPECT_EQ(o.exitCode, 75) << format << (disk.realDisk() ? " (tmpfs) " : " (file size limit) ") << o;
    EXPECT_NE(o.output.find("Error: "), std::string::npos) << o;
    EXPECT_NE(o.output.find(existing.string()), std::string::npos) << o;
    EXPECT_EQ(o.output.find("->"), std::string::npos) << "a success line was printed: " << o;
    const auto after = snapshot(disk.path);
    EXPECT_EQ(names(after), names(before)) << format;
    EXPECT_TRUE(after == before) << format << ": a file changed";
    EXPECT_TRUE(wholeImage(existing, 8, 8)) << format;
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, FullDisk,
                         ::testing::Values("png", "tga", "bmp", "sgi", "gif", "jpg", "exr", "tif", "iff"));

// A frame too big for the disk also leaves its depth companion unpublished: both or neither.
TEST(FullDiskOutput, DepthCompanionIsPublishedWithTheImageOrNotAtAll) {
    FillableFolder disk(256 << 10);
    disk.fill(4096);
    const auto before = snapshot(disk.path);
    const Outcome o = runPushpin({"--demo", "-x", "160", "-y", "120", "-of", "png", "-depth", "on", "-rd",
                                  disk.path.string()},
                                 disk.options());
    EXPECT_EQ(o.exitCode, 75) << o;
    EXPECT_TRUE(snapshot(disk.path) == before) << o;
}

// A sequence whose disk fills after frame 1: frame 1 is whole, nothing of frames 2 and 3 is on
// disk, and the run exits 75 at frame 2.
TEST(FullDiskOutput, SequenceStopsAtTheFirstFrameThatDoesNotFit) {
    TempDir work;
    writeFile(work.path / "anim.ma", kAnimatedScene);
    const std::vector<std::string> render = {"-s", "1", "-e", "3", "-fnc", "3", "-of", "png", "-x", "160", "-y", "120"};

    // The frames as they come out on a disk with room.
    std::vector<std::string> args = render;
    args.insert(args.end(), {"-rd", (work.path / "free").string(), (work.path / "anim.ma").string()});
    const Outcome free = runPushpin(args);
    ASSERT_EQ(free.exitCode, 0) << free;
    const std::string frame1 = readAll(work.path / "free" / "anim.1.png");
    const uint64_t frame2Size = fs::file_size(work.path / "free" / "anim.2.png");
    ASSERT_FALSE(frame1.empty());
    // One page holds frame 1 but not frame 2 (tmpfs counts whole pages; the size limit, bytes).
    ASSERT_LE(frame1.size(), 4096u);
    FillableFolder disk(256 << 10);
    if (disk.realDisk()) {
        ASSERT_GT(frame2Size, 0u);
        disk.fill(4096);
    } else {
        ASSERT_LT(frame1.size() + 64, frame2Size) << "frame 2 must be larger than frame 1";
        disk.fill((frame1.size() + frame2Size) / 2);
    }

    args = render;
    args.insert(args.end(), {"-rd", disk.path.string(), (work.path / "anim.ma").string()});
    const Outcome o = runPushpin(args, disk.options());
    EXPECT_EQ(o.exitCode, 75) << o;
    EXPECT_NE(o.output.find("anim.2.png"), std::string::npos) << o;
    EXPECT_EQ(o.output.find("anim.3.png"), std::string::npos) << "the run went on after frame 2: " << o;
    EXPECT_EQ(readAll(disk.path / "anim.1.png"), frame1);
    auto files = names(snapshot(disk.path));
    files.erase(std::remove(files.begin(), files.end(), "filler"), files.end());
    EXPECT_EQ(files, std::vector<std::string>{"anim.1.png"}) << o;
}

// --stats into a full file system: exit 75 naming the file, and an existing stats file kept.
TEST(FullDiskOutput, StatsFileOnAFullDiskExits75AndKeepsTheOldFile) {
    TempDir work;
    FillableFolder disk(256 << 10);
    const fs::path stats = disk.path / "stats.json";
    writeFile(stats, "{\"old\": true}\n");
    // No page free; without the mount, a 256-byte limit that the 2 × 2 image fits in and the
    // statistics do not.
    disk.fill(disk.realDisk() ? 0 : 256);
    const auto before = snapshot(disk.path);
    const Outcome o = runPushpin({"--demo", "-x", "2", "-y", "2", "-rd", (work.path / "out").string(), "--stats",
                                  stats.string()},
                                 disk.options());
    EXPECT_EQ(o.exitCode, 75) << o;
    EXPECT_NE(o.output.find(stats.string()), std::string::npos) << o;
    EXPECT_TRUE(snapshot(disk.path) == before) << o;
}

// ---------------------------------------------------------------- temporary names

// Links planted at every temporary name the pid-and-counter scheme would use, pointing at a file
// outside: the render neither follows nor removes them, and the images are whole.
TEST(TemporaryNames, PlantedLinksAreNotFollowed) {
    TempDir work;
    const fs::path out = work.path / "out";
    fs::create_directories(out);
    const fs::path victim = work.path / "victim.txt";
    writeFile(victim, "precious");
    const fs::path log = work.path / "log.txt";
    const fs::path stats = out / "stats.json";
    const pid_t pid = startPushpin({"--demo", "-x", "32", "-y", "24", "-depth", "on", "-rd", out.string(), "--stats",
                                    stats.string()},
                                   log, {}, true);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, WUNTRACED), pid);
    ASSERT_TRUE(WIFSTOPPED(status));
    const std::string id = std::to_string(pid);
    std::vector<fs::path> links;
    for (int n = 0; n < 4; ++n) {
        links.push_back(out / ("softSpotlight.tmp-" + id + "-" + std::to_string(n) + ".png"));
        links.push_back(out / ("softSpotlight_depth.tmp-" + id + "-" + std::to_string(n) + ".exr"));
    }
    links.push_back(out / ("stats.json.tmp-" + id));
    for (const fs::path& link : links) fs::create_symlink(victim, link);
    ::kill(pid, SIGCONT);
    const Outcome o = waitFor(pid, log);
    EXPECT_EQ(o.exitCode, 0) << o;
    EXPECT_EQ(readAll(victim), "precious");
    for (const fs::path& link : links) EXPECT_TRUE(fs::is_symlink(link)) << link;
    EXPECT_TRUE(wholeImage(out / "softSpotlight.png", 32, 24));
    EXPECT_TRUE(wholeImage(out / "softSpotlight_depth.exr", 32, 24));
    EXPECT_NE(readAll(stats).find("\"images\""), std::string::npos);
}

// Two renders of the same frame into one folder at once both succeed and leave one whole image.
TEST(TemporaryNames, ConcurrentRendersIntoOneFolderBothSucceed) {
    TempDir work;
    const fs::path out = work.path / "out";
    const std::vector<std::string> args = {"--demo", "-x", "200", "-y", "150", "-of", "exr", "-rd", out.string()};
    const pid_t a = startPushpin(args, work.path / "a.txt", {});
    const pid_t b = startPushpin(args, work.path / "b.txt", {});
    const Outcome oa = waitFor(a, work.path / "a.txt");
    const Outcome ob = waitFor(b, work.path / "b.txt");
    EXPECT_EQ(oa.exitCode, 0) << oa;
    EXPECT_EQ(ob.exitCode, 0) << ob;
    EXPECT_EQ(names(snapshot(out)), std::vector<std::string>{"softSpotlight.exr"});
    EXPECT_TRUE(wholeImage(out / "softSpotlight.exr", 200, 150));
}

// ---------------------------------------------------------------- signals

// SIGTERM or SIGINT while the image is being written: exit 143 or 130 and no file left at all.
// The child is stopped once its temporary file appears (inotify) and holds bytes, so the signal
// is sure to arrive while the write is under way. On a fast disk the whole write can finish before
// the child is stopped; the run is then repeated with a larger image (a longer write), and the
// test fails only when no size gives a window.
enum class Caught { Yes, Missed };

Caught signalDuringWrite(int sig, int expectedExit, int width, int height) {
    TempDir work;
    const fs::path out = work.path / "out";
    fs::create_directories(out);
    writeFile(work.path / "anim.ma", kAnimatedScene);
    const int watch = ::inotify_init1(IN_CLOEXEC);
    EXPECT_GE(watch, 0);
    EXPECT_GE(::inotify_add_watch(watch, out.c_str(), IN_CREATE), 0);
    const fs::path log = work.path / "log.txt";
    // An uncompressed BMP: copying and flushing it takes long enough to stop it midway.
    const pid_t pid = startPushpin({"--frame", "2", "-of", "bmp", "-x", std::to_string(width), "-y",
                                    std::to_string(height), "-eaa", "3", "-rd", out.string(),
                                    (work.path / "anim.ma").string()},
                                   log, {});
    alignas(struct inotify_event) char buffer[4096];
    const ssize_t n = ::read(watch, buffer, sizeof buffer);  // blocks until a file is created
    ::close(watch);
    EXPECT_GT(n, 0);
    // Stop it once bytes are in the temporary file: the copy into it is under way.
    std::vector<std::string> during;
    bool inWrite = false;
    for (int attempt = 0; attempt < 2000; ++attempt) {
        ::kill(pid, SIGSTOP);
        int status = 0;
        EXPECT_EQ(::waitpid(pid, &status, WUNTRACED), pid);
        if (!WIFSTOPPED(status)) return Caught::Missed;  // it finished first
        during = names(snapshot(out));
        if (during.size() != 1 || during[0].find(".tmp") == std::string::npos) break;  // renamed already
        if (fs::file_size(out / during[0]) > 0) {
            inWrite = true;
            break;
        }
        ::kill(pid, SIGCONT);
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (!inWrite) {
        ::kill(pid, SIGCONT);
        waitFor(pid, log);
        return Caught::Missed;
    }
    EXPECT_NE(during[0], "anim.bmp");
    ::kill(pid, sig);
    ::kill(pid, SIGCONT);
    const Outcome o = waitFor(pid, log);
    EXPECT_EQ(o.exitCode, expectedExit) << o;
    EXPECT_TRUE(snapshot(out).empty()) << names(snapshot(out))[0];
    return Caught::Yes;
}

void expectSignalDuringWriteCleansUp(int sig, int expectedExit) {
    for (const auto& [w, h] : {std::pair{2000, 1500}, std::pair{4000, 3000}, std::pair{6000, 4500}})
        if (signalDuringWrite(sig, expectedExit, w, h) == Caught::Yes) return;
    ADD_FAILURE() << "every write finished before pushpin could be stopped inside it";
}

TEST(Signals, SigtermWhileWritingExits143AndLeavesNothing) { expectSignalDuringWriteCleansUp(SIGTERM, 143); }
TEST(Signals, SigintWhileWritingExits130AndLeavesNothing) { expectSignalDuringWriteCleansUp(SIGINT, 130); }

// SIGTERM while rendering (before any file exists): exit 143 and an empty output folder.
TEST(Signals, SigtermWhileRenderingExits143) {
    TempDir work;
    const fs::path out = work.path / "out";
    const fs::path log = work.path / "log.txt";
    const pid_t pid = startPushpin({"--demo", "-x", "4000", "-y", "3000", "-rd", out.string()}, log, {});
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ::kill(pid, SIGTERM);
    const Outcome o = waitFor(pid, log);
    EXPECT_EQ(o.exitCode, 143) << o;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));
}

// ---------------------------------------------------------------- where images go

TEST(OutputFolder, AbsoluteScenePrefixIsRefusedNamingTheNode) {
    TempDir work;
    const fs::path victim = work.path / "victim.png";
    writeFile(victim, "precious");
    writeFile(work.path / "abs.ma", sceneWithPrefix((work.path / "victim").string()));
    const fs::path out = work.path / "out";
    const Outcome o = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2", "-rd",
                                  out.string(), (work.path / "abs.ma").string()});
    EXPECT_EQ(o.exitCode, 1) << o;
    EXPECT_NE(o.output.find("defaultRenderGlobals.imageFilePrefix"), std::string::npos) << o;
    EXPECT_NE(o.output.find("--allow-scene-output-paths"), std::string::npos) << o;
    EXPECT_EQ(readAll(victim), "precious");
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));

    // Allowed on request: the scene's path is used as it stands.
    const Outcome allowed = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2",
                                        "--allow-scene-output-paths", "-rd", out.string(),
                                        (work.path / "abs.ma").string()});
    EXPECT_EQ(allowed.exitCode, 0) << allowed;
    EXPECT_TRUE(wholeImage(victim, 32, 24));
}

TEST(OutputFolder, ClimbingScenePrefixIsRefused) {
    TempDir work;
    writeFile(work.path / "up.ma", sceneWithPrefix("../../escaped/<Scene>"));
    const fs::path out = work.path / "a" / "out";
    const Outcome o = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2", "-rd",
                                  out.string(), (work.path / "up.ma").string()});
    EXPECT_EQ(o.exitCode, 1) << o;
    EXPECT_NE(o.output.find("defaultRenderGlobals.imageFilePrefix '../../escaped/<Scene>'"), std::string::npos) << o;
    EXPECT_FALSE(fs::exists(work.path / "escaped"));

    // ".." that stays inside the folder is fine.
    writeFile(work.path / "inside.ma", sceneWithPrefix("shots/../frames/<Scene>"));
    const Outcome inside = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2", "-rd",
                                       out.string(), (work.path / "inside.ma").string()});
    EXPECT_EQ(inside.exitCode, 0) << inside;
    EXPECT_TRUE(wholeImage(out / "frames" / "inside.png", 32, 24));
}

// -im is the user's own, but it cannot leave the output folder unnoticed either: a usage error.
TEST(OutputFolder, CommandLinePrefixOutsideTheFolderIsAUsageError) {
    TempDir work;
    const fs::path out = work.path / "out";
    const Outcome o = runPushpin({"--demo", "-x", "16", "-y", "12", "-rd", out.string(), "-im", "../elsewhere"});
    EXPECT_EQ(o.exitCode, 2) << o;
    EXPECT_NE(o.output.find("-im '../elsewhere'"), std::string::npos) << o;
    EXPECT_FALSE(fs::exists(work.path / "elsewhere.png"));
    const Outcome allowed = runPushpin({"--demo", "-x", "16", "-y", "12", "-rd", out.string(), "-im", "../elsewhere",
                                        "--allow-scene-output-paths"});
    EXPECT_EQ(allowed.exitCode, 0) << allowed;
    EXPECT_TRUE(wholeImage(work.path / "elsewhere.png", 16, 12));
}

// Without -rd, a scene inside a Maya project renders into the project's images folder.
TEST(OutputFolder, ProjectImagesFolderIsTheDefault) {
    TempDir work;
    const fs::path project = work.path / "project";
    fs::create_directories(project / "scenes" / "shot");
    writeFile(project / "workspace.mel",
              "//Maya 2018 Project Definition\n\nworkspace -fr \"scene\" \"scenes\";\n"
              "workspace -fr \"images\" \"renders/frames\";\n");
    writeFile(project / "scenes" / "shot" / "anim.ma", kAnimatedScene);
    const Outcome o = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2",
                                  (project / "scenes" / "shot" / "anim.ma").string()},
                                 RunOptions{work.path, 0});
    EXPECT_EQ(o.exitCode, 0) << o;
    EXPECT_TRUE(wholeImage(project / "renders" / "frames" / "anim.png", 32, 24)) << o;
    EXPECT_FALSE(fs::exists(work.path / "anim.png"));
    // And the prefix is held inside that folder too.
    writeFile(project / "scenes" / "escape.ma", sceneWithPrefix("../../../<Scene>"));
    const Outcome escape = runPushpin({"--frame", "2", "-x", "32", "-y", "24", "-of", "png", "-fnc", "2",
                                       (project / "scenes" / "escape.ma").string()},
                                      RunOptions{work.path, 0});
    EXPECT_EQ(escape.exitCode, 1) << escape;
    EXPECT_NE(escape.output.find("renders/frames"), std::string::npos) << escape;
}

// A 50 MB image prefix in the scene, and the longest -im Linux passes (an argument holds at most
// 128 KiB, MAX_ARG_STRLEN): one short error line each.
TEST(OutputFolder, HugePrefixGivesAShortError) {
    TempDir work;
    const std::string huge(size_t(50) << 20, 'p');
    const Outcome cli = runPushpin({"--demo", "-x", "8", "-y", "6", "-rd", (work.path / "out").string(), "-im",
                                    std::string(120000, 'p')});
    EXPECT_EQ(cli.exitCode, 2) << cli.exitCode;
    EXPECT_LT(cli.output.size(), 2048u) << cli.output.substr(0, 500);
    EXPECT_NE(cli.output.find("bytes"), std::string::npos) << cli.output.substr(0, 500);

    writeFile(work.path / "huge.ma", sceneWithPrefix(huge));
    const Outcome scene = runPushpin({"--frame", "2", "-x", "8", "-y", "6", "-rd", (work.path / "out").string(),
                                      (work.path / "huge.ma").string()});
    EXPECT_EQ(scene.exitCode, 1) << scene.exitCode;
    EXPECT_LT(scene.output.size(), 2048u) << scene.output.substr(0, 500);
    EXPECT_NE(scene.output.find("defaultRenderGlobals.imageFilePrefix"), std::string::npos)
        << scene.output.substr(0, 500);
    EXPECT_TRUE(!fs::exists(work.path / "out") || fs::is_empty(work.path / "out"));
}

}  // namespace
