// Tests for cache/output_file.h: exclusive random temporary names, the checked publish sequence,
// nothing left behind on failure, and removal by SIGTERM/SIGINT.
#include "cache/output_file.h"

#include "cache/error.h"

#include <gtest/gtest.h>

#include "tests/support/temp_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using pushpin::OutputError;
using pushpin::cache::OutputFile;

namespace {

struct TempDir : pushpin::test::TempFolder {
    TempDir() : TempFolder("output-file") {}
};

std::string readAll(const fs::path& p) { return pushpin::test::readWholeFile(p); }

void writeText(const fs::path& p, const std::string& text) { pushpin::test::writeWholeFile(p, text); }

std::set<std::string> names(const fs::path& dir) {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
    return out;
}

}  // namespace

TEST(OutputFile, PublishesWholeFileOnCommit) {
    TempDir dir;
    const fs::path target = dir.path / "frame.0001.png";
    {
        OutputFile out(target);
        EXPECT_EQ(out.temporaryPath().parent_path(), dir.path);
        EXPECT_FALSE(fs::exists(target));
        out.write("hello ", 6);
        out.write("world", 5);
        EXPECT_EQ(out.bytesWritten(), 11u);
        out.commit();
    }
    EXPECT_EQ(readAll(target), "hello world");
    EXPECT_EQ(names(dir.path), std::set<std::string>{"frame.0001.png"});
}

TEST(OutputFile, ModeIs0644LessTheUmask) {
    TempDir dir;
    const mode_t old = ::umask(027);
    {
        OutputFile out(dir.path / "a.exr");
        out.write("x", 1);
        out.commit();
    }
    ::umask(old);
    struct stat st;
    ASSERT_EQ(::stat((dir.path / "a.exr").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0640u);
}

TEST(OutputFile, AbandonedFileLeavesTheFolderAsItWas) {
    TempDir dir;
    const fs::path target = dir.path / "frame.png";
    writeText(target, "the good frame");
    {
        OutputFile out(target);
        out.write("half a fra", 10);
        // Destroyed without commit: an error path.
    }
    EXPECT_EQ(readAll(target), "the good frame");
    EXPECT_EQ(names(dir.path), std::set<std::string>{"frame.png"});
}

TEST(OutputFile, TemporaryNamesAreRandomAndHidden) {
    std::set<std::string> seen;
    for (int i = 0; i < 200; ++i) {
        const fs::path p = pushpin::cache::temporaryPathFor("/some/dir/shot.0001.exr");
        EXPECT_EQ(p.parent_path(), fs::path("/some/dir"));
        const std::string name = p.filename().string();
        EXPECT_EQ(name.rfind(".shot.0001.exr.", 0), 0u) << name;
        EXPECT_TRUE(name.ends_with(".tmp")) << name;
        seen.insert(name);
    }
    EXPECT_EQ(seen.size(), 200u);
    const std::string longName(1000, 'n');
    EXPECT_LT(pushpin::cache::temporaryPathFor(fs::path("/d") / longName).filename().string().size(), 255u);
}

TEST(OutputFile, PlantedLinksAreNeverFollowed) {
    TempDir dir;
    const fs::path victim = dir.path / "victim.txt";
    writeText(victim, "precious");
    // The first names drawn are links someone planted (to a file, to a missing file) and a plain
    // file someone else owns: creation must refuse each and go on to a fresh name.
    const fs::path planted = dir.path / ".out.png.link.tmp";
    const fs::path dangling = dir.path / ".out.png.dangling.tmp";
    const fs::path taken = dir.path / ".out.png.taken.tmp";
    fs::create_symlink(victim, planted);
    fs::create_symlink(dir.path / "created-through-link", dangling);
    writeText(taken, "another job's file");
    int calls = 0;
    auto names3 = [&](const fs::path& p) {
        ++calls;
        if (calls == 1) return planted;
        if (calls == 2) return dangling;
        if (calls == 3) return taken;
        return pushpin::cache::temporaryPathFor(p);
    };
    {
        OutputFile out(dir.path / "out.png", names3);
        EXPECT_EQ(calls, 4);
        EXPECT_FALSE(fs::is_symlink(out.temporaryPath()));
        out.write("new", 3);
        out.commit();
    }
    EXPECT_EQ(readAll(victim), "precious");
    EXPECT_FALSE(fs::exists(dir.path / "created-through-link"));
    EXPECT_EQ(readAll(taken), "another job's file");
    EXPECT_EQ(readAll(dir.path / "out.png"), "new");
}

TEST(OutputFile, ExistingLinkAtTheFinalNameIsReplacedNotFollowed) {
    TempDir dir;
    const fs::path victim = dir.path / "victim.txt";
    writeText(victim, "precious");
    fs::create_symlink(victim, dir.path / "out.png");
    OutputFile out(dir.path / "out.png");
    out.write("frame", 5);
    out.commit();
    EXPECT_EQ(readAll(victim), "precious");
    EXPECT_FALSE(fs::is_symlink(dir.path / "out.png"));
    EXPECT_EQ(readAll(dir.path / "out.png"), "frame");
}

TEST(OutputFile, MissingFolderIsAnOutputError) {
    TempDir dir;
    try {
        OutputFile out(dir.path / "no" / "such" / "frame.png");
        FAIL() << "created a file in a missing folder";
    } catch (const OutputError& e) {
        EXPECT_EQ(e.errorCode(), ENOENT);
        EXPECT_NE(std::string(e.what()).find("frame.png"), std::string::npos) << e.what();
    }
}

TEST(OutputFile, CopyFromReadsTheWholeSource) {
    TempDir dir;
    std::string big(3 << 20, '\0');
    for (size_t i = 0; i < big.size(); ++i) big[i] = char(i * 2654435761u >> 24);
    writeText(dir.path / "src.bin", big);
    const int fd = ::open((dir.path / "src.bin").c_str(), O_RDONLY);
    ASSERT_GE(fd, 0);
    ::lseek(fd, 12345, SEEK_SET);  // the copy reads from offset 0 whatever the file offset
    {
        OutputFile out(dir.path / "dst.bin");
        out.copyFrom(fd, "src.bin");
        out.commit();
    }
    ::close(fd);
    EXPECT_EQ(readAll(dir.path / "dst.bin"), big);
}

// A file system that is really full: a tiny tmpfs when the tests run as root (CI does), else a
// file-size limit that makes write() fail the same way a full disk does.
class FullDisk : public ::testing::Test {
protected:
    void SetUp() override {
        mount = dir.path / "full";
        fs::create_directory(mount);
        if (::geteuid() == 0 && ::mount("tmpfs", mount.c_str(), "tmpfs", 0, "size=64k") == 0) mounted = true;
    }
    void TearDown() override {
        if (mounted) ::umount(mount.c_str());
    }
    TempDir dir;
    fs::path mount;
    bool mounted = false;
};

TEST_F(FullDisk, WriteFailureRemovesTheTemporaryAndKeepsTheOldFile) {
    const fs::path target = mount / "frame.png";
    writeText(target, "good frame");
    const std::set<std::string> before = names(mount);
    const std::string payload(1 << 20, 'p');  // far more than 64 KiB
    // Run the write in a child so that the fallback limit (RLIMIT_FSIZE) binds only there.
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        if (!mounted) {
            ::signal(SIGXFSZ, SIG_IGN);
            struct rlimit lim{65536, 65536};
            ::setrlimit(RLIMIT_FSIZE, &lim);
        }
        int code = 0;
        try {
            OutputFile out(target);
            out.write(payload.data(), payload.size());
            out.commit();
            code = 10;  // the write should not have succeeded
        } catch (const OutputError& e) {
            code = (e.errorCode() == ENOSPC || e.errorCode() == EFBIG) ? 0 : 11;
        } catch (...) {
            code = 12;
        }
        ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    EXPECT_EQ(names(mount), before);
    EXPECT_EQ(readAll(target), "good frame");
}

// SIGTERM and SIGINT while a temporary file is open: the handler removes it and the process ends
// with 128 + signal.
class SignalCleanup : public ::testing::TestWithParam<int> {};

TEST_P(SignalCleanup, RemovesTemporaryFilesAndExitsWithTheSignalStatus) {
    const int sig = GetParam();
    TempDir dir;
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(ready[0]);
        pushpin::cache::installTemporaryFileCleanup();
        OutputFile a(dir.path / "a.png");
        OutputFile b(dir.path / "b.exr");
        a.write("partial", 7);
        (void)!::write(ready[1], "r", 1);
        for (;;) ::pause();
    }
    ::close(ready[1]);
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    ::close(ready[0]);
    EXPECT_EQ(names(dir.path).size(), 2u);
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_TRUE(names(dir.path).empty());
}

INSTANTIATE_TEST_SUITE_P(TermAndInt, SignalCleanup, ::testing::Values(SIGTERM, SIGINT),
                         [](const ::testing::TestParamInfo<int>& i) { return i.param == SIGTERM ? "SIGTERM" : "SIGINT"; });

TEST(TemporaryName, ExitRemovesRegisteredFiles) {
    TempDir dir;
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        pushpin::cache::installTemporaryFileCleanup();
        auto* out = new OutputFile(dir.path / "left.png");  // never destroyed: exit() runs instead
        out->write("x", 1);
        std::exit(3);  // a library ending the process
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);
    EXPECT_TRUE(names(dir.path).empty());
}
