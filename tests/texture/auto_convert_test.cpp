// tests/texture/auto_convert_test.cpp: converting images into TMPDIR once, concurrently, and
// failing cleanly when TMPDIR cannot take the file.
#include "texture/auto_convert.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <thread>

#include "texture_test_support.h"

namespace pushpin::texture {
namespace {

using testing::TempDir;

// Writes an 8-bit RGB PNG whose texel (x, y) is ((x + seed) % 256, y, (x ^ y) & 255) / 255.
std::filesystem::path writePng(const std::filesystem::path& path, uint32_t w, uint32_t h, int seed) {
    std::vector<uint8_t> px(size_t(w) * h * 3);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            uint8_t* p = &px[(size_t(y) * w + x) * 3];
            p[0] = uint8_t((x + seed) % 256);
            p[1] = uint8_t(y % 256);
            p[2] = uint8_t((x ^ y) & 255);
        }
    auto out = OIIO::ImageOutput::create(path.string());
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(int(w), int(h), 3, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open(path.string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    return path;
}

size_t filesIn(const std::filesystem::path& dir) {
    std::error_code ec;
    if (!std::filesystem::exists(dir, ec)) return 0;
    return size_t(std::distance(std::filesystem::directory_iterator(dir), {}));
}

TEST(AutoConvert, SameImageConvertsOnceKeyedByContent) {
    TempDir src("ac-src"), tmp("ac-tmp");
    const auto a = writePng(src.path() / "a.png", 20, 12, 1);
    std::filesystem::copy_file(a, src.path() / "copy-of-a.png");
    const auto b = writePng(src.path() / "b.png", 20, 12, 2);
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    const AutoConvertResult r1 = convertToBot(a, o);
    ASSERT_TRUE(r1.ok()) << r1.error;
    EXPECT_FALSE(r1.reused);
    EXPECT_TRUE(isBotFile(r1.botPath));
    EXPECT_EQ(r1.botPath.parent_path(), conversionDir(o));
    const AutoConvertResult r2 = convertToBot(src.path() / "copy-of-a.png", o);
    ASSERT_TRUE(r2.ok());
    EXPECT_TRUE(r2.reused);
    EXPECT_EQ(r2.botPath, r1.botPath);
    const AutoConvertResult r3 = convertToBot(b, o);
    ASSERT_TRUE(r3.ok());
    EXPECT_NE(r3.botPath, r1.botPath);
    // Different conversion options give a different file.
    AutoConvertOptions wrapped = o;
    wrapped.bot.wrapS = WrapMode::Clamp;
    EXPECT_NE(conversionKey(a, wrapped), conversionKey(a, o));
    EXPECT_EQ(filesIn(conversionDir(o)), 2u);
    // The converted file holds the image (8-bit source → U8 pages, exact).
    const auto bot = BotFile::open(r1.botPath);
    EXPECT_EQ(bot->header().width, 20u);
    EXPECT_EQ(bot->header().channels, 3u);
    EXPECT_EQ(bot->header().pixelType, PixelType::U8);
}

TEST(AutoConvert, ConcurrentConvertersEndWithOneCompleteFile) {
    TempDir src("ac-src"), tmp("ac-tmp");
    const auto img = writePng(src.path() / "shared.png", 300, 200, 5);
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    o.bot.threads = 1;
    std::vector<AutoConvertResult> results(8);
    std::vector<std::thread> threads;
    for (size_t i = 0; i < results.size(); ++i)
        threads.emplace_back([&, i] { results[i] = convertToBot(img, o); });
    for (auto& t : threads) t.join();
    for (const AutoConvertResult& r : results) {
        ASSERT_TRUE(r.ok()) << r.error;
        EXPECT_EQ(r.botPath, results[0].botPath);
    }
    EXPECT_EQ(filesIn(conversionDir(o)), 1u);  // no temporary names left behind
    EXPECT_NO_THROW(BotFile::open(results[0].botPath));
}

TEST(AutoConvert, ConcurrentProcessesEndWithOneCompleteFile) {
    // Separate processes (as separate renders are), each converting the same image; the writer
    // copies a prepared BOT file in small slow steps to keep the race window open.
    TempDir src("ac-src"), tmp("ac-tmp");
    const auto img = writePng(src.path() / "shared.png", 64, 64, 9);
    const auto prepared = src.path() / "prepared.bot";
    {
        const auto pixels = testing::makeImage(64, 64, 3, [](uint32_t x, uint32_t y, uint32_t c) {
            return float((x + y + c) % 256) / 255.0f;
        });
        BotWriteOptions wo;
        wo.threads = 1;
        writeBot(prepared, pixels.data(), 64, 64, 3, wo);
    }
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    o.writer = [&](const std::filesystem::path& path, const float*, uint32_t, uint32_t, uint32_t,
                   const BotWriteOptions&) {
        std::ifstream in(prepared, std::ios::binary);
        std::ofstream out(path, std::ios::binary);
        char buf[256];
        while (in.read(buf, sizeof buf) || in.gcount() > 0) {
            out.write(buf, in.gcount());
            out.flush();
            ::usleep(200);
        }
        if (!out) throw IoError(path, "write converted texture", EIO);
    };
    std::vector<pid_t> children;
    for (int i = 0; i < 4; ++i) {
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            ::alarm(60);  // a stuck child fails the test instead of hanging it
            const AutoConvertResult r = convertToBot(img, o);
            ::_exit(r.ok() && isBotFile(r.botPath) ? 0 : 1);
        }
        children.push_back(pid);
    }
    for (pid_t pid : children) {
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
    }
    EXPECT_EQ(filesIn(conversionDir(o)), 1u);  // one final file, no temporary names left
    const AutoConvertResult r = convertToBot(img, o);
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_TRUE(r.reused);
    EXPECT_EQ(std::filesystem::file_size(r.botPath), std::filesystem::file_size(prepared));
}

TEST(AutoConvert, UnwritableTmpDirFailsWithoutThrowing) {
    TempDir src("ac-src");
    const auto img = writePng(src.path() / "x.png", 8, 8, 0);
    AutoConvertOptions o;
    o.tmpDir = "/proc/self/pushpin-cannot-create";
    const AutoConvertResult r = convertToBot(img, o);
    EXPECT_FALSE(r.ok());
    EXPECT_TRUE(r.botPath.empty());
    EXPECT_NE(r.error.find("pushpin-cannot-create"), std::string::npos) << r.error;
}

TEST(AutoConvert, FullDiskRemovesThePartialFile) {
    TempDir src("ac-src"), tmp("ac-tmp");
    const auto img = writePng(src.path() / "x.png", 16, 16, 0);
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    std::filesystem::path attempted;
    o.writer = [&](const std::filesystem::path& path, const float*, uint32_t, uint32_t, uint32_t,
                   const BotWriteOptions&) {
        attempted = path;
        std::ofstream(path) << "half a file";
        throw IoError(path, "write page", ENOSPC);
    };
    const AutoConvertResult r = convertToBot(img, o);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.error.find(std::strerror(ENOSPC)), std::string::npos) << r.error;
    EXPECT_FALSE(attempted.empty());
    EXPECT_FALSE(std::filesystem::exists(attempted));
    EXPECT_EQ(filesIn(conversionDir(o)), 0u);
    // The next conversion with a working writer succeeds.
    o.writer = nullptr;
    EXPECT_TRUE(convertToBot(img, o).ok());
}

TEST(AutoConvert, UnreadableImageIsAnError) {
    TempDir src("ac-src"), tmp("ac-tmp");
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    AutoConvertResult r = convertToBot(src.path() / "missing.png", o);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.error.find("missing.png"), std::string::npos) << r.error;
    std::ofstream(src.path() / "junk.png") << "not an image at all";
    r = convertToBot(src.path() / "junk.png", o);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.error.find("junk.png"), std::string::npos) << r.error;
    EXPECT_FALSE(isBotFile(src.path() / "junk.png"));
}

// A TIFF cut in half reads "successfully" through OpenImageIO with its lower half black; the
// conversion must fail instead of caching a texture that would render wrong.
TEST(AutoConvert, TruncatedImageIsAnErrorAndCachesNothing) {
    TempDir src("ac-src"), tmp("ac-tmp");
    const auto whole = src.path() / "whole.tif";
    {
        std::vector<uint8_t> px(size_t(128) * 128 * 3);
        for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 31 % 253);
        auto out = OIIO::ImageOutput::create(whole.string());
        OIIO::ImageSpec spec(128, 128, 3, OIIO::TypeDesc::UINT8);
        spec.attribute("compression", "lzw");
        ASSERT_TRUE(out && out->open(whole.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()));
        out->close();
    }
    std::ifstream in(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(src.path() / "cut.tif", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    AutoConvertOptions o;
    o.tmpDir = tmp.path();
    ASSERT_TRUE(convertToBot(whole, o).ok());
    const size_t before = filesIn(conversionDir(o));
    const AutoConvertResult r = convertToBot(src.path() / "cut.tif", o);
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.error.find("cut.tif"), std::string::npos) << r.error;
    EXPECT_EQ(filesIn(conversionDir(o)), before);
}

TEST(AutoConvert, UsesTmpdirFromTheEnvironment) {
    const char* old = std::getenv("TMPDIR");
    const std::string saved = old ? old : "";
    ::setenv("TMPDIR", "/some/render/tmp", 1);
    EXPECT_EQ(conversionDir(AutoConvertOptions{}), std::filesystem::path("/some/render/tmp/pushpin-bot"));
    ::unsetenv("TMPDIR");
    EXPECT_EQ(conversionDir(AutoConvertOptions{}), std::filesystem::path("/tmp/pushpin-bot"));
    if (old) ::setenv("TMPDIR", saved.c_str(), 1);
}

}  // namespace
}  // namespace pushpin::texture
