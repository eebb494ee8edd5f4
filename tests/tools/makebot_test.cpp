// Tests of the makebot and botinfo programs, run from PUSHPIN_BINARY_DIR: exit codes, messages
// naming the file, no output on failure, an existing output left untouched on failure.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
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
    for (const auto& e : fs::directory_iterator(tempDir()))
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
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
