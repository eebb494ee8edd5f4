// Tests for core/render/image_output.h and framebuffer.h: Maya format codes, file naming for every
// convention, round trips through OpenImageIO, depth output, the final colour steps and the
// atomic write (no partial or temporary files, an old frame replaced only by a whole new one).
#include "core/render/image_output.h"

#include "cache/error.h"
#include "tests/support/image_read.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>
#include <sstream>

namespace pushpin::render {
namespace {

namespace fs = std::filesystem;

struct TempDir {
    fs::path path;
    TempDir() {
        std::random_device rd;
        path = fs::temp_directory_path() / ("pushpin_image_output_" + std::to_string(rd()) + std::to_string(rd()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& e : fs::recursive_directory_iterator(path)) names.push_back(fs::relative(e.path(), path).string());
        std::sort(names.begin(), names.end());
        return names;
    }
};

// Images read back with their raw stored values, not premultiplied by the reader: writeImage stores
// colour as given.
using ReadBack = test::ImageReadBack<float>;
using test::readImage;

// A small image with distinct values in every channel, row 0 at the top.
Framebuffer testFrame(int w, int h, bool depth = false) {
    Framebuffer f;
    f.resize(w, h, depth);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            float* p = f.pixel(x, y);
            p[0] = (x + 0.25f) / w;
            p[1] = (y + 0.5f) / h;
            p[2] = float((x * 7 + y * 3) % 11) / 10.0f;
            p[3] = (x + y) % 3 == 0 ? 1.0f : 0.5f;
            if (depth) f.depth[static_cast<size_t>(y) * w + x] = (x + y) % 4 == 0 ? std::numeric_limits<float>::infinity()
                                                                                 : 1.5f + x + 10.0f * y;
        }
    }
    return f;
}

RenderSettings plainSettings() {
    RenderSettings s;
    s.jitterFinalColor = false;
    return s;
}

std::string fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
}

TEST(Framebuffer, ResizeClearsPixelsAndDepth) {
    Framebuffer f;
    f.resize(3, 2, true);
    EXPECT_EQ(f.width, 3);
    EXPECT_EQ(f.height, 2);
    ASSERT_EQ(f.rgba.size(), 24u);
    ASSERT_EQ(f.depth.size(), 6u);
    for (float v : f.rgba) EXPECT_EQ(v, 0.0f);
    for (float d : f.depth) EXPECT_TRUE(std::isinf(d) && d > 0);
    f.pixel(2, 1)[3] = 1.0f;
    EXPECT_EQ(f.rgba[(1 * 3 + 2) * 4 + 3], 1.0f);
    f.resize(2, 2, false);
    EXPECT_EQ(f.rgba.size(), 16u);
    EXPECT_TRUE(f.depth.empty());
    for (float v : f.rgba) EXPECT_EQ(v, 0.0f);
    f.resize(-4, 5, true);
    EXPECT_EQ(f.width, 0);
    EXPECT_TRUE(f.rgba.empty());
}

TEST(ImageOutput, MayaFormatCodes) {
    struct Row {
        int code;
        const char* oiio;
        const char* ext;
        int bits;
        bool isFloat;
    } rows[] = {
        {7, "iff", "iff", 8, false},   {10, "iff", "iff", 16, false},  {3, "tiff", "tif", 8, false},
        {4, "tiff", "tif", 16, false}, {5, "sgi", "sgi", 8, false},    {13, "sgi", "sgi", 16, false},
        {8, "jpeg", "jpg", 8, false},  {19, "targa", "tga", 8, false}, {20, "bmp", "bmp", 8, false},
        {32, "png", "png", 8, false},  {40, "openexr", "exr", 32, true},
    };
    for (const Row& r : rows) {
        RenderSettings s;
        s.imageFormat = r.code;
        const OutputFormat f = outputFormat(s);
        EXPECT_EQ(f.oiioName, r.oiio) << r.code;
        EXPECT_EQ(f.extension, r.ext) << r.code;
        EXPECT_EQ(f.bitsPerChannel, r.bits) << r.code;
        EXPECT_EQ(f.floatPixels, r.isFloat) << r.code;
    }
    RenderSettings s;
    s.imageFormat = 51;
    s.imfPluginKey = "exr";
    EXPECT_EQ(outputFormat(s).oiioName, "openexr");
    s.imageFormat = 40;
    s.imfPluginKey = "";
    EXPECT_EQ(outputFormat(s).extension, "exr");
    s.imageFormat = 51;
    s.imfPluginKey = "png";
    EXPECT_EQ(outputFormat(s).oiioName, "png");
}

TEST(ImageOutput, UnwritableFormatsThrowNamingTheCode) {
    for (int code : {21, 22, 23, 1, 6, 9, 11, 31, 35, 99, -3}) {
        RenderSettings s;
        s.imageFormat = code;
        try {
            (void)outputFormat(s);
            ADD_FAILURE() << "code " << code << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(std::to_string(code)), std::string::npos) << e.what();
        }
    }
    RenderSettings s;
    s.imageFormat = 51;
    EXPECT_THROW((void)outputFormat(s), Error);  // no key
    s.imfPluginKey = "nosuchformat";
    try {
        (void)outputFormat(s);
        ADD_FAILURE() << "unknown key accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nosuchformat"), std::string::npos) << e.what();
    }
}

TEST(ImageOutput, FormatNamesAndCodes) {
    EXPECT_EQ(outputFormatFromName("tif").oiioName, "tiff");
    EXPECT_EQ(outputFormatFromName("tiff16").bitsPerChannel, 16);
    EXPECT_EQ(outputFormatFromName("jpeg").extension, "jpg");
    EXPECT_EQ(outputFormatFromName("targa").extension, "tga");
    EXPECT_EQ(outputFormatFromName("maya").oiioName, "iff");
    EXPECT_EQ(outputFormatFromName("EXR").oiioName, "openexr");
    EXPECT_EQ(outputFormatFromName("rgb16").oiioName, "sgi");
    EXPECT_THROW((void)outputFormatFromName("avi"), Error);
    EXPECT_THROW((void)outputFormatFromName("cin"), Error);
    EXPECT_THROW((void)outputFormatFromName(""), Error);
    EXPECT_THROW((void)outputFormatFromName("webm"), Error);
    EXPECT_EQ(imageFormatCodeFromName("tga").imageFormat, 19);
    EXPECT_EQ(imageFormatCodeFromName("iff16").imageFormat, 10);
    const ImageFormatCode exr = imageFormatCodeFromName("openexr");
    EXPECT_EQ(exr.imageFormat, 40);
    EXPECT_EQ(exr.imfPluginKey, "exr");
    EXPECT_THROW((void)imageFormatCodeFromName("qtl"), Error);
}

TEST(ImageOutput, FileNamesForEveryConvention) {
    const OutputFormat iff = outputFormatFromName("iff");
    struct Row {
        bool an;
        int ofc;
        bool pff;
        int peie;
        const char* expected;
    } rows[] = {
        {false, 1, false, 1, "shot"},          {false, 0, false, 1, "shot.iff"},
        {true, 0, true, 1, "shot.0007.iff"},   {true, 0, false, 1, "shot.iff.0007"},
        {true, 1, false, 1, "shot.0007"},      {true, 0, true, 0, "shot0007.iff"},
        {true, 0, true, 2, "shot_0007.iff"},   {true, 1, false, 2, "shot_0007"},
        {true, 1, false, 0, "shot0007"},
    };
    for (const Row& r : rows) {
        RenderSettings s;
        s.animation = r.an;
        s.outFormatControl = r.ofc;
        s.putFrameBeforeExt = r.pff;
        s.periodInExt = r.peie;
        s.extensionPadding = 4;
        s.imageFilePrefix = "shot";
        EXPECT_EQ(imageFilePath(s, iff, "out", "scene.ma", "persp", 7, false), fs::path("out") / r.expected);
    }
}

TEST(ImageOutput, FrameNumbersAndPadding) {
    const OutputFormat png = outputFormatFromName("png");
    RenderSettings s;
    s.animation = true;
    s.putFrameBeforeExt = true;
    auto name = [&](double frame, int pad) {
        s.extensionPadding = pad;
        return imageFilePath(s, png, "", "a.ma", "persp", frame, false).string();
    };
    EXPECT_EQ(name(7, 1), "a.7.png");
    EXPECT_EQ(name(7, 0), "a.7.png");
    EXPECT_EQ(name(7, 3), "a.007.png");
    EXPECT_EQ(name(12345, 3), "a.12345.png");
    EXPECT_EQ(name(-3, 4), "a.-0003.png");
    EXPECT_EQ(name(12.5, 4), "a.0012.5.png");
    EXPECT_EQ(name(0.25, 2), "a.00.25.png");
    EXPECT_EQ(name(2.9999999, 2), "a.03.png");
    // Without animation no number appears.
    s.animation = false;
    EXPECT_EQ(name(12, 4), "a.png");
}

TEST(ImageOutput, PrefixTokensAndSceneName) {
    const OutputFormat exr = outputFormatFromName("exr");
    RenderSettings s;
    EXPECT_EQ(imageFilePath(s, exr, "img", "/projects/x/shot010.ma", "persp", 1, false), fs::path("img/shot010.exr"));
    EXPECT_EQ(imageFilePath(s, exr, "img", "shot010.MB", "persp", 1, false), fs::path("img/shot010.exr"));
    EXPECT_EQ(imageFilePath(s, exr, "", "", "persp", 1, false), fs::path("untitled.exr"));
    s.imageFilePrefix = "<Scene>/<RenderLayer>/<Camera>_beauty";
    EXPECT_EQ(imageFilePath(s, exr, "img", "shot010.ma", "ns:cam|A", 1, true),
              fs::path("img/shot010/masterLayer/ns_cam_A_beauty.exr"));
    s.imageFilePrefix = "%s_%c";
    EXPECT_EQ(imageFilePath(s, exr, "", "s.ma", "top", 1, false), fs::path("s_top.exr"));
    s.imageFilePrefix = "<scene>";  // tokens are case-insensitive
    EXPECT_EQ(imageFilePath(s, exr, "", "s.ma", "top", 1, false), fs::path("s.exr"));
    // Several cameras and no <Camera> token: a folder per camera.
    s.imageFilePrefix = "";
    EXPECT_EQ(imageFilePath(s, exr, "img", "s.ma", "persp", 1, true), fs::path("img/persp/s.exr"));
    s.imageFilePrefix = "renders/beauty";
    EXPECT_EQ(imageFilePath(s, exr, "img", "s.ma", "side", 1, true), fs::path("img/renders/side/beauty.exr"));
    // Custom extension.
    s.outFormatControl = 2;
    s.outFormatExt = ".pic";
    EXPECT_EQ(imageFilePath(s, exr, "", "s.ma", "side", 1, false), fs::path("renders/beauty.pic"));
    EXPECT_EQ(depthImagePath("out/shot.0001.png", outputFormatFromName("png")), fs::path("out/shot.0001_depth.exr"));
}

TEST(ImageOutput, ExrRoundTripIsExactFloat) {
    TempDir dir;
    Framebuffer f = testFrame(7, 5);
    f.pixel(1, 1)[0] = 3.75f;   // HDR values survive when clipping is off
    f.pixel(2, 1)[1] = -0.125f;
    RenderSettings s = plainSettings();
    s.clipFinalShadedColor = false;
    s.jitterFinalColor = true;  // no dither for float formats
    const fs::path path = dir.path / "frame.exr";
    writeImage(f, path, outputFormatFromName("exr"), s, false);
    const ReadBack r = readImage(path);
    ASSERT_EQ(r.width, 7);
    ASSERT_EQ(r.height, 5);
    ASSERT_EQ(r.channels, 4);
    EXPECT_EQ(r.format, OIIO::TypeDesc::FLOAT);
    for (size_t i = 0; i < f.rgba.size(); ++i) EXPECT_EQ(r.pixels[i], f.rgba[i]) << i;
    EXPECT_EQ(dir.files(), std::vector<std::string>{"frame.exr"});
}

void expectIntegerRoundTrip(const char* format, const char* file, double tolerance, int channels = 4) {
    TempDir dir;
    const Framebuffer f = testFrame(9, 6);
    RenderSettings s;  // dither on: still within one step
    const fs::path path = dir.path / file;
    writeImage(f, path, outputFormatFromName(format), s, false);
    const ReadBack r = readImage(path);
    ASSERT_EQ(r.width, 9) << format;
    ASSERT_EQ(r.height, 6) << format;
    ASSERT_EQ(r.channels, channels) << format;
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 9; ++x)
            for (int c = 0; c < channels; ++c)
                EXPECT_NEAR(r.pixels[(static_cast<size_t>(y) * 9 + x) * channels + c], f.pixel(x, y)[c], tolerance)
                    << format << " pixel " << x << "," << y << " channel " << c;
    EXPECT_EQ(dir.files(), std::vector<std::string>{file});
}

TEST(ImageOutput, PngRoundTripWithinOneStep) { expectIntegerRoundTrip("png", "a.png", 1.0 / 255 + 1e-6); }
TEST(ImageOutput, TiffRoundTripWithinOneStep) { expectIntegerRoundTrip("tif", "a.tif", 1.0 / 255 + 1e-6); }
TEST(ImageOutput, Tiff16RoundTripWithinOneStep) { expectIntegerRoundTrip("tiff16", "a.tif", 1.0 / 65535 + 1e-7); }
TEST(ImageOutput, IffRoundTripWithinOneStep) { expectIntegerRoundTrip("iff", "a.iff", 1.0 / 255 + 1e-6); }
TEST(ImageOutput, TargaRoundTripWithinOneStep) { expectIntegerRoundTrip("tga", "a.tga", 1.0 / 255 + 1e-6); }

TEST(ImageOutput, ExrGetsAZChannel) {
    TempDir dir;
    const Framebuffer f = testFrame(6, 4, true);
    const fs::path path = dir.path / "z.exr";
    writeImage(f, path, outputFormatFromName("exr"), plainSettings(), true);
    const ReadBack r = readImage(path);
    ASSERT_EQ(r.channels, 5);
    EXPECT_EQ(r.names, (std::vector<std::string>{"R", "G", "B", "A", "Z"}));
    for (size_t i = 0; i < f.depth.size(); ++i) EXPECT_EQ(r.pixels[i * 5 + 4], f.depth[i]) << i;
    EXPECT_EQ(dir.files(), std::vector<std::string>{"z.exr"});

    // Without writeDepth (or without depth in the framebuffer) there is no Z.
    writeImage(f, path, outputFormatFromName("exr"), plainSettings(), false);
    EXPECT_EQ(readImage(path).channels, 4);
    writeImage(testFrame(6, 4, false), path, outputFormatFromName("exr"), plainSettings(), true);
    EXPECT_EQ(readImage(path).channels, 4);
}

TEST(ImageOutput, OtherFormatsGetACompanionDepthFile) {
    TempDir dir;
    const Framebuffer f = testFrame(6, 4, true);
    const fs::path path = dir.path / "shot.0003.png";
    writeImage(f, path, outputFormatFromName("png"), plainSettings(), true);
    EXPECT_EQ(dir.files(), (std::vector<std::string>{"shot.0003.png", "shot.0003_depth.exr"}));
    const ReadBack z = readImage(dir.path / "shot.0003_depth.exr");
    ASSERT_EQ(z.channels, 1);
    EXPECT_EQ(z.names, std::vector<std::string>{"Z"});
    for (size_t i = 0; i < f.depth.size(); ++i) EXPECT_EQ(z.pixels[i], f.depth[i]) << i;
    EXPECT_EQ(readImage(path).channels, 4);
}

TEST(ImageOutput, GammaAndClipAreApplied) {
    TempDir dir;
    Framebuffer f;
    f.resize(4, 1, false);
    const float in[4] = {0.25f, 0.5f, 1.5f, -0.5f};
    for (int x = 0; x < 4; ++x) {
        f.pixel(x, 0)[0] = in[x];
        f.pixel(x, 0)[1] = in[x];
        f.pixel(x, 0)[2] = in[x];
        f.pixel(x, 0)[3] = 0.5f;
    }
    RenderSettings s = plainSettings();
    s.gammaCorrection = 2.2;
    const fs::path path = dir.path / "g.exr";
    writeImage(f, path, outputFormatFromName("exr"), s, false);
    ReadBack r = readImage(path);
    for (int x = 0; x < 4; ++x) {
        const double expected = std::clamp(in[x] > 0 ? std::pow(double(in[x]), 1.0 / 2.2) : double(in[x]), 0.0, 1.0);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.pixels[x * 4 + c], expected, 1e-6) << x;
        EXPECT_NEAR(r.pixels[x * 4 + 3], 0.5, 1e-7) << "alpha takes no gamma";
    }
    // Clipping off keeps values outside [0, 1].
    s.clipFinalShadedColor = false;
    writeImage(f, path, outputFormatFromName("exr"), s, false);
    r = readImage(path);
    EXPECT_NEAR(r.pixels[2 * 4], std::pow(1.5, 1.0 / 2.2), 1e-6);
    EXPECT_NEAR(r.pixels[3 * 4], -0.5, 1e-7);
}

TEST(ImageOutput, NaNIsWrittenAsZero) {
    TempDir dir;
    Framebuffer f = testFrame(3, 3);
    f.pixel(1, 1)[0] = std::numeric_limits<float>::quiet_NaN();
    f.pixel(1, 1)[3] = std::numeric_limits<float>::quiet_NaN();
    RenderSettings s = plainSettings();
    s.clipFinalShadedColor = false;
    const fs::path path = dir.path / "n.exr";
    writeImage(f, path, outputFormatFromName("exr"), s, false);
    const ReadBack r = readImage(path);
    EXPECT_EQ(r.pixels[(1 * 3 + 1) * 4 + 0], 0.0f);
    EXPECT_EQ(r.pixels[(1 * 3 + 1) * 4 + 3], 0.0f);
}

TEST(ImageOutput, DitherIsDeterministicAndWithinHalfAStep) {
    TempDir dir;
    Framebuffer f;
    f.resize(64, 8, false);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 64; ++x) {
            float* p = f.pixel(x, y);
            p[0] = p[1] = p[2] = (x + 0.37f) / 256.0f;  // between 8-bit levels
            p[3] = 1.0f;
        }
    RenderSettings s;
    s.jitterFinalColor = true;
    writeImage(f, dir.path / "a.png", outputFormatFromName("png"), s, false);
    writeImage(f, dir.path / "b.png", outputFormatFromName("png"), s, false);
    EXPECT_EQ(fileBytes(dir.path / "a.png"), fileBytes(dir.path / "b.png"));
    s.jitterFinalColor = false;
    writeImage(f, dir.path / "c.png", outputFormatFromName("png"), s, false);
    EXPECT_NE(fileBytes(dir.path / "a.png"), fileBytes(dir.path / "c.png"));
    const ReadBack dithered = readImage(dir.path / "a.png");
    const ReadBack plain = readImage(dir.path / "c.png");
    int changed = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 64; ++x) {
            const size_t i = (static_cast<size_t>(y) * 64 + x) * 4;
            const double v = f.pixel(x, y)[0];
            // Each written level is one of the two levels around the value.
            EXPECT_LE(std::abs(dithered.pixels[i] - v), 1.0 / 255 + 1e-6);
            EXPECT_EQ(dithered.pixels[i + 3], 1.0f) << "alpha is not dithered";
            changed += dithered.pixels[i] != plain.pixels[i];
        }
    EXPECT_GT(changed, 0);
}

TEST(ImageOutput, MaskOffWritesRgbOnlyAndJpegHasNoAlpha) {
    TempDir dir;
    const Framebuffer f = testFrame(5, 5);
    RenderSettings s = plainSettings();
    s.mask = false;
    writeImage(f, dir.path / "rgb.png", outputFormatFromName("png"), s, false);
    EXPECT_EQ(readImage(dir.path / "rgb.png").channels, 3);
    writeImage(f, dir.path / "a.jpg", outputFormatFromName("jpg"), plainSettings(), false);
    EXPECT_EQ(readImage(dir.path / "a.jpg").channels, 3);
}

TEST(ImageOutput, CreatesParentFolders) {
    TempDir dir;
    const fs::path path = dir.path / "deep" / "er" / "x.tif";
    writeImage(testFrame(2, 2), path, outputFormatFromName("tif"), plainSettings(), false);
    EXPECT_TRUE(fs::is_regular_file(path));
}

TEST(ImageOutput, UnwritableFolderThrowsAndLeavesNoFile) {
    TempDir dir;
    { std::ofstream(dir.path / "blocker") << "not a folder"; }
    const fs::path path = dir.path / "blocker" / "sub" / "x.png";
    try {
        writeImage(testFrame(2, 2), path, outputFormatFromName("png"), plainSettings(), false);
        ADD_FAILURE() << "no error";
    } catch (const OutputError& e) {  // an output failure: the tools exit 75
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(dir.files(), std::vector<std::string>{"blocker"});
}

TEST(ImageOutput, ExistingFileIsReplacedOnlyByAWholeImage) {
    TempDir dir;
    const fs::path path = dir.path / "frame.tga";
    { std::ofstream(path, std::ios::binary) << "old frame"; }
    // Targa cannot hold 70000 pixels across: OpenImageIO fails the write.
    Framebuffer wide;
    wide.resize(70000, 1, false);
    try {
        writeImage(wide, path, outputFormatFromName("tga"), plainSettings(), false);
        ADD_FAILURE() << "no error";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        EXPECT_EQ(e.path(), path);
        // The frame cannot be encoded at all: not an output failure worth a retry.
        EXPECT_EQ(dynamic_cast<const OutputError*>(&e), nullptr) << e.what();
    }
    EXPECT_EQ(fileBytes(path), "old frame");
    EXPECT_EQ(dir.files(), std::vector<std::string>{"frame.tga"});

    writeImage(testFrame(4, 4), path, outputFormatFromName("tga"), plainSettings(), false);
    EXPECT_NE(fileBytes(path), "old frame");
    EXPECT_EQ(readImage(path).width, 4);
    EXPECT_EQ(dir.files(), std::vector<std::string>{"frame.tga"});
}

TEST(ImageOutput, OversizedJpegIsRefusedBeforeWriting) {
    TempDir dir;
    Framebuffer wide;
    wide.resize(70000, 1, false);
    const fs::path path = dir.path / "wide.jpg";
    try {
        writeImage(wide, path, outputFormatFromName("jpg"), plainSettings(), false);
        ADD_FAILURE() << "no error";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("65500"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(dir.files().empty());
}

TEST(ImageOutput, MalformedFramebufferThrows) {
    TempDir dir;
    Framebuffer f = testFrame(3, 3);
    f.rgba.pop_back();
    EXPECT_THROW(writeImage(f, dir.path / "x.png", outputFormatFromName("png"), plainSettings(), false), IoError);
    Framebuffer empty;
    EXPECT_THROW(writeImage(empty, dir.path / "y.png", outputFormatFromName("png"), plainSettings(), false), IoError);
    EXPECT_TRUE(dir.files().empty());
}

// Every writable format, through the in-memory encoders: each file reads back whole, the folder
// holds exactly the images (no temporary files), and the depth companion comes with them.
TEST(ImageOutput, EveryFormatWritesAWholeFileAndNothingElse) {
    for (const char* name : {"exr", "tif", "tiff16", "png", "jpg", "iff", "sgi", "tga", "bmp", "gif", "hdr", "rla"}) {
        TempDir dir;
        const OutputFormat format = outputFormatFromName(name);
        const fs::path path = dir.path / ("f." + format.extension);
        // Wider than one conversion strip (65536 pixels) and taller than one IFF tile row.
        writeImage(testFrame(700, 130, true), path, format, plainSettings(), true);
        const ReadBack r = readImage(path);
        EXPECT_EQ(r.width, 700) << name;
        EXPECT_EQ(r.height, 130) << name;
        std::vector<std::string> expected{"f." + format.extension};
        if (format.oiioName != "openexr") expected.push_back("f_depth.exr");
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(dir.files(), expected) << name;
    }
}

// A name longer than a file system holds is refused before anything is written, quoted short.
TEST(ImageOutput, OverlongNamesAreRefusedShort) {
    TempDir dir;
    const fs::path path = dir.path / (std::string(100000, 'n') + ".png");
    try {
        writeImage(testFrame(2, 2), path, outputFormatFromName("png"), plainSettings(), false);
        ADD_FAILURE() << "no error";
    } catch (const IoError& e) {
        EXPECT_LT(std::string(e.what()).size(), 1000u);
        EXPECT_EQ(dynamic_cast<const OutputError*>(&e), nullptr);
    }
    EXPECT_TRUE(dir.files().empty());
    EXPECT_TRUE(imagePathProblem(dir.path / std::string(255, 'a')).empty());
    EXPECT_NE(imagePathProblem(dir.path / std::string(256, 'a')).find("256 bytes"), std::string::npos);
    std::string deep;
    for (int i = 0; i < 30; ++i) deep += std::string(200, 'd') + "/";
    EXPECT_NE(imagePathProblem(deep + "x.png").find("a path holds at most 4095"), std::string::npos);
}

TEST(ImageOutput, WorkspaceImagesRule) {
    EXPECT_EQ(workspaceImagesRule("//Maya 2018 Project Definition\n\nworkspace -fr \"images\" \"images\";\n"),
              std::optional<std::string>("images"));
    EXPECT_EQ(workspaceImagesRule("workspace -fr \"scene\" \"scenes\";\nworkspace -fileRule \"images\" \"out/img dir\";"),
              std::optional<std::string>("out/img dir"));
    EXPECT_EQ(workspaceImagesRule("workspace -fr \"images\" \"a\";\nworkspace -fr \"images\" \"b\";"),
              std::optional<std::string>("b"));  // the last rule wins
    EXPECT_EQ(workspaceImagesRule("// workspace -fr \"images\" \"commented\";\nworkspace -fr \"sourceImages\" \"x\";"),
              std::nullopt);
    EXPECT_EQ(workspaceImagesRule("workspace -fr \"images\" \"\";"), std::optional<std::string>(""));
    EXPECT_EQ(workspaceImagesRule(""), std::nullopt);
    EXPECT_EQ(workspaceImagesRule("workspace -fr \"images"), std::nullopt);  // cut short
}

TEST(ImageOutput, ProjectImagesFolderSearchesUpward) {
    TempDir dir;
    const fs::path project = dir.path / "proj";
    fs::create_directories(project / "scenes" / "a" / "b");
    EXPECT_TRUE(projectImagesFolder(project / "scenes" / "s.ma").empty());
    { std::ofstream(project / "workspace.mel") << "workspace -fr \"images\" \"renders\";\n"; }
    EXPECT_EQ(projectImagesFolder(project / "scenes" / "s.ma"), project / "renders");
    EXPECT_EQ(projectImagesFolder(project / "scenes" / "a" / "b" / "s.ma"), project / "renders");
    EXPECT_EQ(projectImagesFolder(project / "s.ma"), project / "renders");
    { std::ofstream(project / "workspace.mel") << "workspace -fr \"scene\" \"scenes\";\n"; }
    EXPECT_EQ(projectImagesFolder(project / "scenes" / "s.ma"), project / "images");  // Maya's default
    { std::ofstream(project / "workspace.mel") << "workspace -fr \"images\" \"/farm/out\";\n"; }
    EXPECT_EQ(projectImagesFolder(project / "scenes" / "s.ma"), fs::path("/farm/out"));
    // Four levels up is too far.
    fs::create_directories(project / "scenes" / "a" / "b" / "c");
    EXPECT_TRUE(projectImagesFolder(project / "scenes" / "a" / "b" / "c" / "s.ma").empty());
}

// -proj DIR: the project's own rule, else DIR/images, whatever folder the scene is in.
TEST(ImageOutput, ImagesFolderOfAGivenProject) {
    TempDir dir;
    const fs::path project = dir.path / "farmproj";
    fs::create_directories(project);
    EXPECT_EQ(imagesFolderOfProject(project), project / "images");
    { std::ofstream(project / "workspace.mel") << "workspace -fr \"images\" \"out/renders\";\n"; }
    EXPECT_EQ(imagesFolderOfProject(project), project / "out" / "renders");
    { std::ofstream(project / "workspace.mel") << "workspace -fr \"images\" \"\";\n"; }
    EXPECT_EQ(imagesFolderOfProject(project), project);
}

TEST(ImageOutput, IsInsideFolderIsLexical) {
    EXPECT_TRUE(isInsideFolder("/out/a.png", "/out"));
    EXPECT_TRUE(isInsideFolder("/out/x/../a.png", "/out/"));
    EXPECT_TRUE(isInsideFolder("/out/./cam/a.png", "/out"));
    EXPECT_FALSE(isInsideFolder("/out/../a.png", "/out"));
    EXPECT_FALSE(isInsideFolder("/outside/a.png", "/out"));
    EXPECT_FALSE(isInsideFolder("/etc/passwd", "/out"));
    EXPECT_TRUE(isInsideFolder("a/b.png", "."));
    EXPECT_TRUE(isInsideFolder("a/b.png", "a"));
    EXPECT_FALSE(isInsideFolder("../b.png", "."));
    EXPECT_FALSE(isInsideFolder("a/../../b.png", "a"));
    EXPECT_TRUE(isInsideFolder("/anything", "/"));
}

}  // namespace
}  // namespace pushpin::render
