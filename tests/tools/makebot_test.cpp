// Tests of the makebot and botinfo programs, run from PUSHPIN_BINARY_DIR: exit codes, messages
// naming the file, no output on failure, an existing output left untouched on failure.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <webp/encode.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <set>
#include <thread>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "texture/bot_file.h"

namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;

fs::path binary(const char* name) { return fs::path(PUSHPIN_BINARY_DIR) / name; }

fs::path tempDir() {
    fs::path dir = fs::temp_directory_path() / ("pushpin_makebot_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

struct Result {
    int exitCode = -1;
    std::string output;  // stdout and stderr together
};

Result run(const std::string& args) {
    const std::string cmd = args + " 2>&1";
    Result r;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    const int status = ::pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

// A small 8-bit RGB PNG with a gradient.
fs::path makePng(const std::string& name, int w, int h) {
    const fs::path path = tempDir() / name;
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    std::vector<uint8_t> px(size_t(w) * h * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 5) % 251);
    EXPECT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) &&
                out->close());
    return path;
}

// An 8-bit RGB WebP of `px` in WebP's lossless mode, which keeps every value.
fs::path makeLosslessWebp(const std::string& name, int w, int h, const std::vector<uint8_t>& px) {
    const fs::path path = tempDir() / name;
    uint8_t* encoded = nullptr;
    const size_t n = WebPEncodeLosslessRGB(px.data(), w, h, w * 3, &encoded);
    EXPECT_GT(n, 0u);
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(encoded), std::streamsize(n));
    WebPFree(encoded);
    return path;
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Makebot, ConvertsPngAndBotinfoReportsIt) {
    const fs::path png = makePng("small.png", 37, 21);
    const fs::path bot = tempDir() / "small.bot";
    const Result r = run(quote(binary("makebot")) + " -v --filter lanczos3 " + quote(png) + " " + quote(bot));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("level  0"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ratio"), std::string::npos) << r.output;
    const auto file = pushpin::texture::BotFile::open(bot);
    EXPECT_EQ(file->header().width, 37u);
    EXPECT_EQ(file->header().pixelType, pushpin::texture::PixelType::U8);
    EXPECT_EQ(file->header().colorSpace, pushpin::texture::ColorSpace::SRGB);  // 8-bit default

    const Result info = run(quote(binary("botinfo")) + " --verify " + quote(bot));
    EXPECT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("37x21"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("0 of"), std::string::npos) << info.output;
    const Result json = run(quote(binary("botinfo")) + " --json " + quote(bot));
    EXPECT_EQ(json.exitCode, 0);
    EXPECT_NE(json.output.find("\"levels\": ["), std::string::npos) << json.output;
    EXPECT_NE(json.output.find("\"compressedBytes\""), std::string::npos);
    EXPECT_NE(json.output.find("\"version\": 3"), std::string::npos) << json.output;
    EXPECT_NE(info.output.find("version 3"), std::string::npos) << info.output;
    // --bot-version 2 writes the other version, which botinfo reads as well.
    const fs::path bot2 = tempDir() / "small2.bot";
    const Result r2 = run(quote(binary("makebot")) + " --bot-version 2 " + quote(png) + " " + quote(bot2));
    ASSERT_EQ(r2.exitCode, 0) << r2.output;
    EXPECT_EQ(pushpin::texture::BotFile::open(bot2)->version(), 2u);
    const Result info2 = run(quote(binary("botinfo")) + " --verify " + quote(bot2));
    EXPECT_EQ(info2.exitCode, 0) << info2.output;
    EXPECT_NE(info2.output.find("version 2"), std::string::npos) << info2.output;
    for (const auto& e : fs::directory_iterator(tempDir()))
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

// The default thread count runs in an arena of its own; the bytes are those of one thread.
TEST(Makebot, WritesTheSameBytesWhateverTheThreadCount) {
    const fs::path png = makePng("threads.png", 150, 90);
    std::string bytes[3];
    const char* counts[3] = {"", "--threads 1 ", "--threads 2 "};
    for (int k = 0; k < 3; ++k) {
        const fs::path bot = tempDir() / ("threads" + std::to_string(k) + ".bot");
        const Result r = run(quote(binary("makebot")) + " " + counts[k] + quote(png) + " " + quote(bot));
        ASSERT_EQ(r.exitCode, 0) << r.output;
        bytes[k] = readAll(bot);
    }
    EXPECT_FALSE(bytes[0].empty());
    EXPECT_EQ(bytes[0], bytes[1]);
    EXPECT_EQ(bytes[0], bytes[2]);
}

TEST(Makebot, HonoursFormatWrapAndColorspaceOptions) {
    const fs::path png = makePng("opts.png", 16, 16);
    const fs::path bot = tempDir() / "opts.bot";
    const Result r = run(quote(binary("makebot")) + " --format half --wrap clamp,mirror --colorspace linear --threads 1 " +
                         quote(png) + " " + quote(bot));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto file = pushpin::texture::BotFile::open(bot);
    EXPECT_EQ(file->header().pixelType, pushpin::texture::PixelType::Half);
    EXPECT_EQ(file->header().wrapS, pushpin::texture::WrapMode::Clamp);
    EXPECT_EQ(file->header().wrapT, pushpin::texture::WrapMode::Mirror);
    EXPECT_EQ(file->header().colorSpace, pushpin::texture::ColorSpace::Linear);
}

// A WebP still is read by libwebp as it decodes; the file is the one its pixels make through
// OpenImageIO (here from a PNG of the same pixels, which WebP's lossless mode keeps exactly).
TEST(Makebot, WebpIsStreamedByLibwebpAndConvertsLikeThePngOfItsPixels) {
    const int w = 150, h = 90;
    std::vector<uint8_t> px(size_t(w) * h * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 7 + i / 450) % 253);
    const fs::path png = tempDir() / "same.png";
    {
        auto out = OIIO::ImageOutput::create(png.string());
        OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
        ASSERT_TRUE(out && out->open(png.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) &&
                    out->close());
    }
    const fs::path webp = makeLosslessWebp("same.webp", w, h, px);

    const fs::path fromPng = tempDir() / "same-png.bot", fromWebp = tempDir() / "same-webp.bot";
    const Result a = run(quote(binary("makebot")) + " -v " + quote(png) + " " + quote(fromPng));
    const Result b = run(quote(binary("makebot")) + " -v " + quote(webp) + " " + quote(fromWebp));
    ASSERT_EQ(a.exitCode, 0) << a.output;
    ASSERT_EQ(b.exitCode, 0) << b.output;
    EXPECT_NE(a.output.find("read by OpenImageIO"), std::string::npos) << a.output;
    EXPECT_NE(b.output.find("read by libwebp"), std::string::npos) << b.output;
    EXPECT_EQ(readAll(fromPng), readAll(fromWebp));

    // Truncated: exit 1, the file and rows named, nothing written.
    const std::string bytes = readAll(webp);
    const fs::path cut = tempDir() / "cut.webp";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    const fs::path cutBot = tempDir() / "cut.bot";
    const Result c = run(quote(binary("makebot")) + " " + quote(cut) + " " + quote(cutBot));
    EXPECT_EQ(c.exitCode, 1) << c.output;
    EXPECT_NE(c.output.find("cut.webp"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("truncated"), std::string::npos) << c.output;
    EXPECT_FALSE(fs::exists(cutBot));
}

// makebot loads OpenImageIO only through makebot-oiio.so, for inputs libwebp does not read: on its
// own it converts WebP, and says which file it misses for anything else.
TEST(Makebot, LoadsOpenImageIOOnlyForFormatsOtherThanWebp) {
    const Result ldd = run("ldd " + quote(binary("makebot")));
    ASSERT_EQ(ldd.exitCode, 0) << ldd.output;
    EXPECT_EQ(ldd.output.find("libOpenImageIO"), std::string::npos) << ldd.output;
    EXPECT_NE(ldd.output.find("libwebp"), std::string::npos) << ldd.output;

    const fs::path alone = tempDir() / "alone";
    fs::create_directories(alone);
    fs::copy_file(binary("makebot"), alone / "makebot", fs::copy_options::overwrite_existing);
    const int w = 40, h = 30;
    std::vector<uint8_t> px(size_t(w) * h * 3, 90);
    const fs::path webp = makeLosslessWebp("alone.webp", w, h, px);
    const Result a = run(quote(alone / "makebot") + " " + quote(webp) + " " + quote(tempDir() / "alone-webp.bot"));
    EXPECT_EQ(a.exitCode, 0) << a.output;
    const fs::path png = makePng("alone.png", 20, 10);
    const fs::path pngBot = tempDir() / "alone-png.bot";
    const Result b = run(quote(alone / "makebot") + " " + quote(png) + " " + quote(pngBot));
    EXPECT_EQ(b.exitCode, 1) << b.output;
    EXPECT_NE(b.output.find("makebot-oiio.so"), std::string::npos) << b.output;
    EXPECT_FALSE(fs::exists(pngBot));
}

TEST(Makebot, MissingInputIsNamedAndLeavesNoOutput) {
    const fs::path missing = tempDir() / "no_such_image.png";
    const fs::path bot = tempDir() / "missing.bot";
    const Result r = run(quote(binary("makebot")) + " " + quote(missing) + " " + quote(bot));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("no_such_image.png"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(bot));
}

TEST(Makebot, FailureKeepsExistingOutputUntouched) {
    const fs::path bad = tempDir() / "broken.png";
    {
        std::ofstream out(bad, std::ios::binary);
        out << "\x89PNG\r\n\x1a\n this is not really a png";
    }
    const fs::path bot = tempDir() / "existing.bot";
    {
        std::ofstream out(bot, std::ios::binary);
        out << "previous content";
    }
    const Result r = run(quote(binary("makebot")) + " " + quote(bad) + " " + quote(bot));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("broken.png"), std::string::npos) << r.output;
    EXPECT_EQ(readAll(bot), "previous content");
    for (const auto& e : fs::directory_iterator(tempDir()))
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(Makebot, UnwritableOutputFolderIsAnError) {
    const fs::path png = makePng("nodir.png", 8, 8);
    const Result r = run(quote(binary("makebot")) + " " + quote(png) + " " + quote(tempDir() / "absent" / "x.bot"));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.output.find("x.bot"), std::string::npos) << r.output;
}

TEST(Makebot, BadOptionsAreUsageErrors) {
    const fs::path png = makePng("usage.png", 8, 8);
    const fs::path bot = tempDir() / "usage.bot";
    for (const std::string opt : {"--filter gauss", "--format u32", "--wrap sideways", "--threads -1", "--bogus"}) {
        const Result r = run(quote(binary("makebot")) + " " + opt + " " + quote(png) + " " + quote(bot));
        EXPECT_EQ(r.exitCode, 2) << opt << ": " << r.output;
        EXPECT_FALSE(fs::exists(bot)) << opt;
    }
    EXPECT_EQ(run(quote(binary("makebot")) + " " + quote(png)).exitCode, 2);
}

TEST(Botinfo, VerifyNamesTheCorruptPage) {
    const fs::path png = makePng("verify.png", 40, 24);
    const fs::path bot = tempDir() / "verify.bot";
    ASSERT_EQ(run(quote(binary("makebot")) + " " + quote(png) + " " + quote(bot)).exitCode, 0);
    const auto file = pushpin::texture::BotFile::open(bot);
    const auto entry = file->pageEntry(file->pageIndex(0, 3, 2));
    {
        std::fstream f(bot, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(entry.offsetBytes));
        char c = 0;
        f.read(&c, 1);
        c = char(c ^ 0x40);
        f.seekp(std::streamoff(entry.offsetBytes));
        f.write(&c, 1);
    }
    const Result r = run(quote(binary("botinfo")) + " --verify " + quote(bot));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("level 0 page (3, 2)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("verify.bot"), std::string::npos) << r.output;
    // Without --verify only the tables are read, and they are intact.
    EXPECT_EQ(run(quote(binary("botinfo")) + " " + quote(bot)).exitCode, 0);
}

TEST(Botinfo, NotABotFileIsNamed) {
    const fs::path png = makePng("notbot.png", 8, 8);
    const Result r = run(quote(binary("botinfo")) + " " + quote(png));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("notbot.png"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("bad magic"), std::string::npos) << r.output;
    EXPECT_EQ(run(quote(binary("botinfo"))).exitCode, 2);
}

}  // namespace

namespace {

// Writes a 256x256 RGB gradient with noise in `format` ("tiff" with `compression`, "png", "jpeg",
// "openexr") and returns its path.
fs::path makeImage(const std::string& name, const std::string& compression = "") {
    const fs::path path = tempDir() / name;
    auto out = OIIO::ImageOutput::create(path.string());
    const bool half = path.extension() == ".exr";
    OIIO::ImageSpec spec(256, 256, 3, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
    if (!compression.empty()) spec.attribute("compression", compression);
    std::vector<float> px(size_t(256) * 256 * 3);
    uint32_t h = 12345;
    for (size_t i = 0; i < px.size(); ++i) {
        h = h * 1664525u + 1013904223u;
        px[i] = float((i % 768) / 768.0 * 0.7 + (h >> 24) / 255.0 * 0.3);
    }
    EXPECT_TRUE(out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) &&
                out->close());
    return path;
}

fs::path truncatedCopy(const fs::path& image, double keep) {
    const std::string bytes = readAll(image);
    const fs::path cut = image.parent_path() / ("cut-" + image.filename().string());
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() * keep));
    return cut;
}

std::set<std::string> folderNames(const fs::path& dir) {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
    return out;
}

struct TruncatedInput {
    const char* name;
    const char* compression;
};

class MakebotTruncated : public ::testing::TestWithParam<TruncatedInput> {};

// OpenImageIO's TIFF and JPEG readers report success for a file cut in half and fill the rest
// with black; makebot must fail instead of writing a texture that verifies.
TEST_P(MakebotTruncated, FailsAndWritesNothing) {
    const fs::path whole = makeImage(GetParam().name, GetParam().compression);
    const fs::path cut = truncatedCopy(whole, 0.5);
    const fs::path outDir = tempDir() / ("out-" + std::string(GetParam().name));
    fs::create_directories(outDir);
    const fs::path bot = outDir / "cut.bot";
    const Result good = run(quote(binary("makebot")) + " " + quote(whole) + " " + quote(outDir / "whole.bot"));
    ASSERT_EQ(good.exitCode, 0) << good.output;
    const Result r = run(quote(binary("makebot")) + " " + quote(cut) + " " + quote(bot));
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(cut.filename().string()), std::string::npos) << r.output;
    EXPECT_EQ(folderNames(outDir), std::set<std::string>{"whole.bot"});
}

INSTANTIATE_TEST_SUITE_P(Formats, MakebotTruncated,
                         ::testing::Values(TruncatedInput{"zip.tif", "zip"}, TruncatedInput{"lzw.tif", "lzw"},
                                           TruncatedInput{"raw.tif", "none"}, TruncatedInput{"img.png", ""},
                                           TruncatedInput{"img.jpg", ""}, TruncatedInput{"img.exr", "zip"}),
                         [](const ::testing::TestParamInfo<TruncatedInput>& i) {
                             std::string n = i.param.name;
                             for (char& c : n)
                                 if (c == '.') c = '_';
                             return n;
                         });

// A full disk: a real 64 KiB tmpfs when the tests run as root, else a 64 KiB file-size limit
// (write() then fails with EFBIG, as it fails with ENOSPC on a full disk; SIGXFSZ is ignored so
// the error reaches makebot). The output cannot be written: exit 75 (worth a retry), and the
// folder keeps exactly what it had.
TEST(Makebot, FullDiskIsATransientFailureAndLeavesTheFolderAsItWas) {
    const fs::path mount = tempDir() / "full";
    fs::create_directories(mount);
    const bool mounted = ::geteuid() == 0 && ::mount("tmpfs", mount.c_str(), "tmpfs", 0, "size=64k") == 0;
    const fs::path existing = mount / "tex.bot";
    std::ofstream(existing, std::ios::binary) << "an existing texture";
    const fs::path big = makeImage("big.exr", "none");
    const std::string command = quote(binary("makebot")) + " --format float " + quote(big) + " " + quote(existing);
    const Result r = run(mounted ? command : "sh -c \"trap '' XFSZ; ulimit -f 64; " + command + "\"");
    const std::set<std::string> after = folderNames(mount);
    const std::string kept = readAll(existing);
    if (mounted) ::umount(mount.c_str());
    EXPECT_EQ(r.exitCode, 75) << r.output;
    EXPECT_NE(r.output.find("tex.bot"), std::string::npos) << r.output;
    EXPECT_EQ(after, std::set<std::string>{"tex.bot"});
    EXPECT_EQ(kept, "an existing texture");
}

class MakebotSignal : public ::testing::TestWithParam<int> {};

// SIGTERM or SIGINT while makebot writes: 128 + signal, and no temporary file left.
TEST_P(MakebotSignal, RemovesItsTemporaryFile) {
    const int sig = GetParam();
    const fs::path dir = tempDir() / ("signal-" + std::to_string(sig));
    fs::create_directories(dir);
    // Large enough to take a good fraction of a second, so the signal lands mid-conversion.
    const fs::path input = dir / "large.exr";
    {
        auto out = OIIO::ImageOutput::create(input.string());
        OIIO::ImageSpec spec(4096, 4096, 3, OIIO::TypeDesc::HALF);
        spec.attribute("compression", "none");
        std::vector<float> row(size_t(4096) * 3);
        ASSERT_TRUE(out && out->open(input.string(), spec));
        for (int y = 0; y < 4096; ++y) {
            for (size_t i = 0; i < row.size(); ++i) row[i] = float(((i * 7 + size_t(y) * 13) % 1000) / 1000.0);
            ASSERT_TRUE(out->write_scanline(y, 0, OIIO::TypeDesc::FLOAT, row.data()));
        }
        ASSERT_TRUE(out->close());
    }
    const fs::path outDir = dir / "out";
    fs::create_directories(outDir);
    const std::string exe = binary("makebot").string(), in = input.string(), outPath = (outDir / "large.bot").string();
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::execl(exe.c_str(), exe.c_str(), "--format", "float", in.c_str(), outPath.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    // Wait for the temporary file to appear (bounded), then signal.
    bool sawTemporary = false;
    for (int i = 0; i < 2000 && !sawTemporary; ++i) {
        for (const std::string& n : folderNames(outDir))
            if (n.ends_with(".tmp")) sawTemporary = true;
        if (!sawTemporary) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(sawTemporary) << "makebot finished before it could be signalled";
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_TRUE(folderNames(outDir).empty());
}

INSTANTIATE_TEST_SUITE_P(TermAndInt, MakebotSignal, ::testing::Values(SIGTERM, SIGINT),
                         [](const ::testing::TestParamInfo<int>& i) { return i.param == SIGTERM ? "SIGTERM" : "SIGINT"; });

}  // namespace
