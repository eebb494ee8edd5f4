// Tests of texture/detail/mapped_file.h: a copy out of a mapping whose file shrank fails cleanly,
// and a fault outside a guarded copy still gets the default SIGBUS action.
#include "texture/detail/mapped_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "texture_test_support.h"

namespace pushpin::texture::detail {
namespace {

constexpr size_t kFileBytes = 64 * 1024;

// A file of kFileBytes bytes where byte i holds i % 251, mapped whole; the descriptor stays open
// so the test can truncate it.
struct MappedFixture {
    testing::TempDir dir{"mapped"};
    int fd = -1;
    const uint8_t* bytes = nullptr;
    MappedFixture() {
        const auto path = dir.path() / "data.bin";
        fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
        std::vector<uint8_t> data(kFileBytes);
        for (size_t i = 0; i < data.size(); ++i) data[i] = uint8_t(i % 251);
        if (fd >= 0 && ::pwrite(fd, data.data(), data.size(), 0) == ssize_t(data.size()))
            bytes = mapFile(fd, kFileBytes);
    }
    ~MappedFixture() {
        unmapFile(bytes, kFileBytes);
        if (fd >= 0) ::close(fd);
    }
};

TEST(MappedFile, CopiesWhatTheFileHolds) {
    MappedFixture f;
    ASSERT_NE(f.bytes, nullptr);
    std::vector<uint8_t> out(300);
    ASSERT_TRUE(copyFromMapping(out.data(), f.bytes + 40000, out.size()));
    for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], uint8_t((40000 + i) % 251));
}

TEST(MappedFile, CopyPastTheEndOfAShrunkFileFailsAndTheThreadGoesOn) {
    MappedFixture f;
    ASSERT_NE(f.bytes, nullptr);
    ASSERT_EQ(::ftruncate(f.fd, 8192), 0);
    std::vector<uint8_t> out(100);
    for (int repeat = 0; repeat < 3; ++repeat)  // SIGBUS stays deliverable after each recovery
        EXPECT_FALSE(copyFromMapping(out.data(), f.bytes + 50000, out.size()));
    // A copy that starts inside the file and runs past the end fails too.
    EXPECT_FALSE(copyFromMapping(out.data(), f.bytes + 8192 + 4096 - 50, out.size()));
    // Bytes still inside the file read as before.
    ASSERT_TRUE(copyFromMapping(out.data(), f.bytes + 1000, out.size()));
    EXPECT_EQ(out[0], uint8_t(1000 % 251));
}

TEST(MappedFile, ZeroBytesOrABadDescriptorDoNotMap) {
    EXPECT_EQ(mapFile(-1, 4096), nullptr);
    MappedFixture f;
    EXPECT_EQ(mapFile(f.fd, 0), nullptr);
}

TEST(MappedFileDeathTest, FaultOutsideAGuardedCopyKeepsTheDefaultAction) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");  // other tests leave worker threads behind
    // The process dies: by SIGBUS itself, or, under a sanitizer whose SIGBUS handler was
    // installed before ours (and so is the one chained to), with that sanitizer's report.
    EXPECT_DEATH(
        {
            MappedFixture f;
            if (f.bytes && ::ftruncate(f.fd, 4096) == 0) {
                const volatile uint8_t* p = f.bytes + 50000;
                (void)*p;
            }
            std::fprintf(stderr, "not reached\n");
            std::_Exit(0);  // surviving the fault would fail the death test
        },
        "");
}

}  // namespace
}  // namespace pushpin::texture::detail
