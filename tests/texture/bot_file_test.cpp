// Tests of texture/bot_file.h: lossless round trips, mip levels against an independent reference,
// sRGB filtering in linear light, and clear errors for damaged or hostile files.
#include "texture/bot_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cache/error.h"
#include "texture/detail/bot_checksum.h"
#include "cache/zstd_codec.h"
#include "texture/detail/bot_layout.h"
#include "texture/detail/bot_page.h"
#include "texture/detail/bot_rans.h"
#include "texture/mipmap.h"

namespace pushpin::texture {
namespace {

namespace fs = std::filesystem;

fs::path tempDir() {
    fs::path dir = fs::temp_directory_path() / ("pushpin_bot_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

std::vector<uint8_t> readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const fs::path& p, const std::vector<uint8_t>& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void reseal(std::vector<uint8_t>& b);  // below, with the damaged-file tests

// Values exactly representable in `type`, so level 0 must come back bit for bit.
std::vector<float> makeImage(uint32_t w, uint32_t h, uint32_t ch, PixelType type, uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<float> px(size_t(w) * h * ch);
    for (size_t i = 0; i < px.size(); ++i) {
        switch (type) {
            case PixelType::U8: px[i] = float(rng() % 256) / 255.0f; break;
            case PixelType::U16: px[i] = float(rng() % 65536) / 65535.0f; break;
            case PixelType::Half: px[i] = float(Imath::half(float(int(rng() % 20001) - 10000) / 997.0f)); break;
            case PixelType::Float: px[i] = std::ldexp(float(int(rng() % 2000001) - 1000000), -int(rng() % 30)); break;
        }
    }
    return px;
}

// Reads a whole level (unpadded) through readPage.
std::vector<float> readLevel(const BotFile& file, uint32_t level) {
    const BotHeader& h = file.header();
    const BotLevel& lv = h.levels.at(level);
    const uint32_t ch = h.channels;
    std::vector<float> out(size_t(lv.width) * lv.height * ch);
    std::vector<float> page(kPageSizeTexels * kPageSizeTexels * ch);
    const int fd = ::open(file.path().c_str(), O_RDONLY);
    EXPECT_GE(fd, 0);
    for (uint32_t py = 0; py < lv.pagesY; ++py) {
        for (uint32_t px = 0; px < lv.pagesX; ++px) {
            file.readPage(fd, level, px, py, page.data());
            for (uint32_t y = 0; y < kPageSizeTexels; ++y) {
                for (uint32_t x = 0; x < kPageSizeTexels; ++x) {
                    const uint32_t gx = px * kPageSizeTexels + x, gy = py * kPageSizeTexels + y;
                    const float* t = page.data() + (y * kPageSizeTexels + x) * ch;
                    // Padding repeats the edge texels.
                    const uint32_t sx = std::min(gx, lv.width - 1), sy = std::min(gy, lv.height - 1);
                    if (gx < lv.width && gy < lv.height) {
                        std::memcpy(out.data() + (size_t(gy) * lv.width + gx) * ch, t, ch * sizeof(float));
                    } else {
                        const float* e = page.data() +
                                         ((sy - py * kPageSizeTexels) * kPageSizeTexels + (sx - px * kPageSizeTexels)) * ch;
                        for (uint32_t c = 0; c < ch; ++c) EXPECT_EQ(t[c], e[c]) << "padding at " << gx << "," << gy;
                    }
                }
            }
        }
    }
    ::close(fd);
    return out;
}

// 8-bit sRGB quantisation of linear values is the nearest code: the number of code midpoints (in
// sRGB space, mapped to linear) at or below the value, counted here by brute force.
TEST(BotPage, SrgbQuantisationIsTheNearestCode) {
    std::vector<float> midpoints(255);
    for (int k = 0; k < 255; ++k) {
        const double s = (k + 0.5) / 255.0;
        midpoints[size_t(k)] = float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
    }
    std::vector<float> values;
    for (uint32_t bits = 0; bits <= 0x3f800000u; bits += 4093) {
        float v;
        std::memcpy(&v, &bits, 4);
        values.push_back(v);
    }
    for (float m : midpoints) values.insert(values.end(), {m, std::nextafter(m, 0.0f), std::nextafter(m, 2.0f)});
    values.insert(values.end(), {-1.0f, 0.0f, 1.0f, 1.5f, INFINITY, -INFINITY, NAN});
    while (values.size() % 64) values.push_back(0.5f);
    for (size_t b = 0; b < values.size(); b += 64) {
        uint8_t out[64];
        detail::quantizePage(values.data() + b, 1, PixelType::U8, ColorSpace::SRGB, -1, true, out);
        for (size_t i = 0; i < 64; ++i) {
            const float v = values[b + i];
            int expected = 0;
            if (v > 0.0f) expected = int(std::upper_bound(midpoints.begin(), midpoints.end(), v) - midpoints.begin());
            ASSERT_EQ(int(out[i]), expected) << "linear value " << v;
        }
    }
}

TEST(BotChecksum, MatchesPublishedXxh64Values) {
    EXPECT_EQ(detail::xxh64("", 0, 0), 0xEF46DB3751D8E999ull);
    EXPECT_EQ(detail::xxh64("abc", 3, 0), 0x44BC2CF5AD770999ull);
}

class BotRoundTrip : public ::testing::TestWithParam<std::tuple<PixelType, uint32_t>> {};

TEST_P(BotRoundTrip, LevelZeroReproducesSourceExactly) {
    const auto [type, version] = GetParam();
    for (auto [w, h, ch] : {std::tuple<uint32_t, uint32_t, uint32_t>{37, 21, 3}, {13, 7, 4}, {1, 9, 1}, {200, 130, 2}}) {
        const std::vector<float> src = makeImage(w, h, ch, type, w * 131 + h);
        const fs::path path = tempDir() / ("rt_" + std::string(pixelTypeName(type)) + ".bot");
        BotWriteOptions opt;
        opt.pixelType = type;
        opt.version = version;
        writeBot(path, src.data(), w, h, ch, opt);
        const auto file = BotFile::open(path);
        EXPECT_EQ(file->version(), version);
        EXPECT_EQ(file->header().width, w);
        EXPECT_EQ(file->header().height, h);
        EXPECT_EQ(file->header().channels, ch);
        EXPECT_EQ(file->header().pixelType, type);
        EXPECT_EQ(file->fileBytes(), fs::file_size(path));
        const std::vector<float> back = readLevel(*file, 0);
        ASSERT_EQ(back.size(), src.size());
        for (size_t i = 0; i < src.size(); ++i) ASSERT_EQ(back[i], src[i]) << "sample " << i << " of " << w << "x" << h;
    }
}

INSTANTIATE_TEST_SUITE_P(AllPixelTypes, BotRoundTrip,
                         ::testing::Combine(::testing::Values(PixelType::U8, PixelType::U16, PixelType::Half,
                                                              PixelType::Float),
                                            ::testing::Values(2u, 3u)),
                         [](const auto& p) {
                             return std::string(pixelTypeName(std::get<0>(p.param))) + "_v" +
                                    std::to_string(std::get<1>(p.param));
                         });

// Smooth content with per-texel noise, as in scanned and painted textures: the mean filter and the
// literal dictionary are made for it. Values are exact in every pixel type.
std::vector<float> noisyImage(uint32_t w, uint32_t h, uint32_t ch, uint32_t seed, int noiseCodes = 7) {
    std::mt19937 rng(seed);
    std::vector<float> px(size_t(w) * h * ch);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < ch; ++c) {
                const float v = 0.45f + 0.3f * std::sin(0.021f * x * float(c + 1)) * std::cos(0.017f * y) + 0.1f * (c == 3);
                const int code = std::clamp(int(v * 255.0f) + int(rng() % uint32_t(noiseCodes)) - noiseCodes / 2, 0, 255);
                px[(size_t(y) * w + x) * ch + c] = float(code) / 255.0f;
            }
    return px;
}

// Every page filter with every dictionary kind, for every pixel type, reproduces level 0 exactly.
class BotCodings : public ::testing::TestWithParam<std::tuple<PixelType, PageFilter, BotDictionary>> {};

TEST_P(BotCodings, LevelZeroRoundTrips) {
    const auto [type, filter, dictionary] = GetParam();
    const uint32_t w = 160, h = 136, ch = type == PixelType::U8 ? 3 : 4;  // 460 pages: enough for a dictionary
    std::vector<float> src = noisyImage(w, h, ch, 11);
    if (type == PixelType::Half)
        for (float& v : src) v = float(Imath::half(v));  // exact in the stored type
    const fs::path path = tempDir() / ("coding_" + std::string(pixelTypeName(type)) + "_" + pageFilterName(filter) +
                                       "_" + botDictionaryName(dictionary) + ".bot");
    BotWriteOptions opt;
    opt.pixelType = type;
    opt.pageFilter = filter;
    opt.dictionary = dictionary;
    opt.version = 2;
    writeBot(path, src.data(), w, h, ch, opt);
    const auto file = BotFile::open(path);
    EXPECT_EQ(file->pageFilter(), filter);
    if (dictionary == BotDictionary::None) {
        EXPECT_EQ(file->dictionaryBytes(), 0u);
    } else {
        EXPECT_GT(file->dictionaryBytes(), 0u);
    }
    EXPECT_EQ(readLevel(*file, 0), src);
    for (uint32_t l = 1; l < file->header().levels.size(); ++l) {
        const std::vector<float> level = readLevel(*file, l);  // every page decodes
        for (float v : level) ASSERT_TRUE(std::isfinite(v)) << "level " << l;
    }
}

INSTANTIATE_TEST_SUITE_P(
    All, BotCodings,
    ::testing::Combine(::testing::Values(PixelType::U8, PixelType::U16, PixelType::Half, PixelType::Float),
                       ::testing::Values(PageFilter::None, PageFilter::Med, PageFilter::Mean),
                       ::testing::Values(BotDictionary::None, BotDictionary::Trained, BotDictionary::Literal)),
    [](const auto& p) {
        return std::string(pixelTypeName(std::get<0>(p.param))) + "_" + pageFilterName(std::get<1>(p.param)) + "_" +
               botDictionaryName(std::get<2>(p.param));
    });

// A 256×192 RGB image of smooth noise with a constant top-left corner (channel c is constant(c))
// and white noise in the bottom-right corner: pages of every kind.
template <class Constant>
std::vector<float> everyKindImage(Constant&& constant) {
    const uint32_t w = 256, h = 192, ch = 3;
    std::vector<float> src = noisyImage(w, h, ch, 21);
    std::mt19937 rng(4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < ch; ++c) {
                float& v = src[(size_t(y) * w + x) * ch + c];
                if (y < 48 && x < 64) v = constant(c);
                if (y >= 144 && x >= 192) v = float(rng() % 256) / 255.0f;
            }
    return src;
}

// Constant areas (runs: blocks with sequences), white noise (incompressible: raw) and smooth noisy
// areas (literals) in one file. Whole frames are what a zstd that writes other headers would leave;
// FramePagesAreRead covers them.
TEST(BotFile, EveryPageKindIsWrittenAndReadBack) {
    const uint32_t w = 256, h = 192, ch = 3;
    const std::vector<float> src = everyKindImage([](uint32_t) { return 0.0f; });
    const fs::path path = tempDir() / "kinds.bot";
    BotWriteOptions opt;
    opt.pageFilter = PageFilter::Med;
    opt.version = 2;
    writeBot(path, src.data(), w, h, ch, opt);
    const auto file = BotFile::open(path);
    uint64_t kinds[4] = {};
    for (uint64_t i = 0; i < file->pageCount(); ++i) ++kinds[unsigned(file->pageEntry(i).kind)];
    for (BotPageKind k : {BotPageKind::Raw, BotPageKind::Block, BotPageKind::Literals})
        EXPECT_GT(kinds[unsigned(k)], 0u) << pageKindName(k) << " pages";
    EXPECT_EQ(readLevel(*file, 0), src);
}

// A page stored as a whole compact frame (the form kept when zstd's output has headers the reader
// would not rebuild) reads back like the others. The test rewrites a one-page row of a file that
// way: the page goes to the end of the file, its row offset and entry are updated and resealed.
TEST(BotFile, FramePagesAreRead) {
    using namespace detail;
    const uint32_t w = 64, h = 64, ch = 3;
    const std::vector<float> src = noisyImage(w, h, ch, 51);
    const fs::path path = tempDir() / "frame_src.bot";
    BotWriteOptions opt;
    opt.dictionary = BotDictionary::Literal;
    opt.version = 2;
    writeBot(path, src.data(), w, h, ch, opt);
    std::vector<uint8_t> b = readBytes(path);
    const auto file = BotFile::parse(b.data(), b.size(), "frame.bot");
    ASSERT_GT(file->dictionaryBytes(), 0u);
    const uint32_t level = 3;  // 8x8 texels: one page, alone in its row
    const uint64_t index = file->pageIndex(level, 0, 0);
    std::vector<float> expected(64 * ch);
    file->readPageFromMemory(b.data(), b.size(), level, 0, 0, expected.data());

    // The packed page, from its texels, and its zstd part as a plain compact frame.
    uint8_t samples[64 * 3], packed[64 * 3];
    for (size_t i = 0; i < sizeof samples; ++i) samples[i] = uint8_t(std::lround(expected[i] * 255.0f));
    packPage(samples, ch, PixelType::U8, file->pageFilter(), packed);
    const uint32_t prefix = pagePrefixBytes(ch, PixelType::U8), raw = pageRawBytes(ch, PixelType::U8);
    const uint64_t dictOffset = get64(&b[kFieldDictionary]);
    auto dict = std::make_shared<cache::ZstdDictionary>(&b[dictOffset], get32(&b[kFieldDictionaryBytes]), 1);
    cache::ZstdCompressor z(1, dict);
    std::vector<uint8_t> stored(packed, packed + prefix);
    std::vector<uint8_t> frame(cache::zstdCompressBound(raw));
    const size_t n = z.compress(packed + prefix, raw - prefix, frame.data(), frame.size());
    ASSERT_GT(n, 0u);
    stored.insert(stored.end(), frame.begin(), frame.begin() + ptrdiff_t(n));
    ASSERT_LT(stored.size(), raw);

    const uint64_t newOffset = b.size();
    b.insert(b.end(), stored.begin(), stored.end());
    uint64_t row = 0;
    for (uint32_t l = 0; l < level; ++l) row += file->header().levels[l].pagesY;
    put64(&b[get64(&b[kFieldRowTable]) + row * 8], newOffset);
    const uint64_t entry = get64(&b[kFieldPageTable]) + index * kBotPageEntryBytes;
    put16(&b[entry], uint16_t(uint32_t(BotPageKind::Frame) << kBotPageKindShift | uint32_t(stored.size())));
    put32(&b[entry + 2], uint32_t(xxh64(stored.data(), stored.size(), index | uint64_t(BotPageKind::Frame) << 56)));
    reseal(b);

    const auto rewritten = BotFile::parse(b.data(), b.size(), "frame.bot");
    ASSERT_EQ(rewritten->pageEntry(index).kind, BotPageKind::Frame);
    std::vector<float> back(64 * ch);
    rewritten->readPageFromMemory(b.data(), b.size(), level, 0, 0, back.data());
    EXPECT_EQ(back, expected);
}

// The automatic choice picks the coding that stores the file smallest, within what estimating from
// the first pages allows, and the writer's figures describe the file.
// The coding trials run in parallel and pages are compressed by whichever thread is free; the file
// must not depend on it.
TEST(BotWriter, SameBytesWithOneOrTwoThreads) {
    const uint32_t w = 384, h = 320;
    for (uint32_t version : {2u, 3u})
        for (PixelType type : {PixelType::U8, PixelType::Half}) {
            std::vector<float> src = noisyImage(w, h, 3, 61);
            if (type == PixelType::Half)
                for (float& v : src) v = float(Imath::half(v));
            std::vector<std::vector<uint8_t>> files;
            for (int threads : {1, 2}) {
                const fs::path path = tempDir() / ("threads_" + std::to_string(threads) + ".bot");
                BotWriteOptions opt;
                opt.pixelType = type;
                opt.threads = threads;
                opt.version = version;
                writeBot(path, src.data(), w, h, 3, opt);
                files.push_back(readBytes(path));
            }
            EXPECT_EQ(files[0], files[1]) << pixelTypeName(type) << " version " << version;
        }
}

// A flat texture: residuals are all zero, which a literal table cannot be fitted to (zstd codes a
// block of one byte value without one); the writer falls back to the other kinds, and runs of
// zeros become matches.
TEST(BotWriter, ConstantImageCodesToAlmostNothing) {
    const uint32_t w = 512, h = 512, ch = 3;
    const std::vector<float> src(size_t(w) * h * ch, 128.0f / 255.0f);
    const fs::path path = tempDir() / "constant.bot";
    writeBot(path, src.data(), w, h, ch, BotWriteOptions{});
    const auto file = BotFile::open(path);
    EXPECT_EQ(readLevel(*file, 0), src);
    const uint64_t raw = file->pageCount() * file->pageRawBytes();
    EXPECT_LT(file->fileBytes(), raw / 8) << file->fileBytes() << " of " << raw;
    for (uint64_t i = 0; i < file->pageCount(); ++i) ASSERT_NE(file->pageEntry(i).kind, BotPageKind::Raw);
}

TEST(BotWriter, AutomaticCodingIsAsSmallAsTheBestForcedOne) {
    const uint32_t w = 512, h = 384, ch = 3;
    const std::vector<float> src = noisyImage(w, h, ch, 31, 9);
    auto sizeWith = [&](std::optional<PageFilter> filter, BotDictionary dictionary, BotWriteStats* stats) {
        const fs::path path = tempDir() / "auto_coding.bot";
        BotWriteOptions opt;
        opt.pageFilter = filter;
        opt.dictionary = dictionary;
        opt.version = 2;
        BotWriter writer(path, w, h, ch, opt);
        MipCascade cascade(w, h, ch, MipFilter::Box, opt.colorSpace, opt.alphaChannel,
                           [&](uint32_t level, uint32_t first, uint32_t count, const float* rows, bool linear) {
                               writer.addRows(level, first, count, rows, linear);
                           });
        cascade.pushRows(src.data(), h);
        const BotWriteStats s = writer.finish();
        if (stats) *stats = s;
        EXPECT_EQ(s.fileBytes, fs::file_size(path));
        return s.fileBytes;
    };
    BotWriteStats chosen;
    const uint64_t automatic = sizeWith(std::nullopt, BotDictionary::Auto, &chosen);
    uint64_t best = ~uint64_t(0);
    for (PageFilter f : {PageFilter::Med, PageFilter::Mean})
        for (BotDictionary d : {BotDictionary::None, BotDictionary::Trained, BotDictionary::Literal})
            best = std::min(best, sizeWith(f, d, nullptr));
    EXPECT_LE(double(automatic), 1.01 * double(best));
    // On noisy 8-bit content the mean filter and the literal table win.
    EXPECT_EQ(chosen.pageFilter, PageFilter::Mean);
    EXPECT_EQ(chosen.dictionary, BotDictionary::Literal);
    uint64_t pages = 0;
    for (uint64_t n : chosen.pagesOfKind) pages += n;
    EXPECT_EQ(pages, chosen.pages);
    EXPECT_GT(chosen.pagesOfKind[unsigned(BotPageKind::Literals)], chosen.pages / 2);
}

TEST(BotFile, LargeImageTrainsDictionaryAndRoundTrips) {
    // Smooth content with mild noise: many pages, enough for the dictionary trainer.
    const uint32_t w = 512, h = 512, ch = 3;
    std::vector<float> src(size_t(w) * h * ch);
    std::mt19937 rng(9);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < ch; ++c) {
                const float v = 0.5f + 0.4f * std::sin(0.02f * x * (c + 1)) * std::cos(0.03f * y);
                const int code = std::clamp(int(v * 255.0f) + int(rng() % 5) - 2, 0, 255);
                src[(size_t(y) * w + x) * ch + c] = float(code) / 255.0f;
            }
    const fs::path path = tempDir() / "large.bot";
    BotWriteOptions opt;
    opt.version = 2;
    writeBot(path, src.data(), w, h, ch, opt);
    const auto file = BotFile::open(path);
    EXPECT_GT(file->dictionaryBytes(), 0u);
    EXPECT_EQ(file->header().levels.size(), 10u);
    EXPECT_EQ(readLevel(*file, 0), src);
    EXPECT_LT(file->fileBytes(), uint64_t(w) * h * ch);  // compresses
}

TEST(BotFile, LevelTableFollowsFloorRule) {
    const std::vector<float> src = makeImage(13, 7, 1, PixelType::Float, 1);
    const fs::path path = tempDir() / "levels.bot";
    BotWriteOptions opt;
    opt.pixelType = PixelType::Float;
    writeBot(path, src.data(), 13, 7, 1, opt);
    const auto file = BotFile::open(path);
    const auto& lv = file->header().levels;
    ASSERT_EQ(lv.size(), 4u);
    EXPECT_EQ(lv[1].width, 6u);
    EXPECT_EQ(lv[1].height, 3u);
    EXPECT_EQ(lv[2].width, 3u);
    EXPECT_EQ(lv[2].height, 1u);
    EXPECT_EQ(lv[3].width, 1u);
    EXPECT_EQ(lv[3].height, 1u);
    EXPECT_EQ(lv[0].pagesX, 2u);
    EXPECT_EQ(lv[0].pagesY, 1u);
}

// ------------------------------------------------------------------ mip levels vs a reference

// Weight of source texel j for destination texel i when resampling n -> m, written directly from
// the filter definitions in BOT_FORMAT.md: box = exact coverage; triangle and Lanczos-3 sample the
// kernel at source texel centres, clamped indices, normalised.
std::vector<std::vector<double>> referenceWeights(uint32_t n, uint32_t m, const std::string& filter) {
    std::vector<std::vector<double>> w(m, std::vector<double>(n, 0.0));
    const double s = double(n) / double(m);
    for (uint32_t i = 0; i < m; ++i) {
        if (filter == "box") {
            for (uint32_t j = 0; j < n; ++j) {
                const double lo = std::max(double(j), i * s), hi = std::min(double(j + 1), (i + 1) * s);
                if (hi > lo) w[i][j] = (hi - lo) / s;
            }
        } else {
            const double c = (i + 0.5) * s;
            for (int j = -200; j < int(n) + 200; ++j) {
                const double x = (j + 0.5 - c) / s;
                double k = 0.0;
                if (filter == "triangle") {
                    k = std::max(0.0, 1.0 - std::fabs(x));
                } else if (std::fabs(x) < 3.0) {
                    auto sinc = [](double t) { return t == 0.0 ? 1.0 : std::sin(M_PI * t) / (M_PI * t); };
                    k = sinc(x) * sinc(x / 3.0);
                }
                w[i][std::clamp(j, 0, int(n) - 1)] += k;
            }
        }
        double sum = 0.0;
        for (double v : w[i]) sum += v;
        for (double& v : w[i]) v /= sum;
    }
    return w;
}

std::vector<double> referenceDownsample(const std::vector<float>& src, uint32_t w, uint32_t h, uint32_t ch,
                                        uint32_t w2, uint32_t h2, const std::string& filter) {
    const auto wx = referenceWeights(w, w2, filter), wy = referenceWeights(h, h2, filter);
    std::vector<double> out(size_t(w2) * h2 * ch, 0.0);
    for (uint32_t j = 0; j < h2; ++j)
        for (uint32_t i = 0; i < w2; ++i)
            for (uint32_t y = 0; y < h; ++y)
                for (uint32_t x = 0; x < w; ++x) {
                    const double k = wx[i][x] * wy[j][y];
                    if (k == 0.0) continue;
                    for (uint32_t c = 0; c < ch; ++c) out[(size_t(j) * w2 + i) * ch + c] += k * src[(size_t(y) * w + x) * ch + c];
                }
    return out;
}

class BotMipLevels : public ::testing::TestWithParam<std::string> {};

TEST_P(BotMipLevels, MatchIndependentDownsampleOfTheLevelAbove) {
    const std::string filter = GetParam();
    for (auto [w, h] : {std::pair<uint32_t, uint32_t>{13, 7}, {1, 9}, {16, 16}, {37, 70}, {9, 1}}) {
        const uint32_t ch = 2;
        std::vector<float> src(size_t(w) * h * ch);
        std::mt19937 rng(w * 7 + h);
        for (float& v : src) v = float(rng() % 10000) / 10000.0f;
        const fs::path path = tempDir() / ("mip_" + filter + ".bot");
        BotWriteOptions opt;
        opt.pixelType = PixelType::Float;
        opt.filter = filter;
        writeBot(path, src.data(), w, h, ch, opt);
        const auto file = BotFile::open(path);
        const auto& levels = file->header().levels;
        std::vector<float> above = readLevel(*file, 0);
        for (uint32_t l = 1; l < levels.size(); ++l) {
            const std::vector<float> got = readLevel(*file, l);
            const auto ref = referenceDownsample(above, levels[l - 1].width, levels[l - 1].height, ch, levels[l].width,
                                                 levels[l].height, filter);
            ASSERT_EQ(got.size(), ref.size());
            for (size_t i = 0; i < ref.size(); ++i)
                ASSERT_NEAR(got[i], ref[i], 1e-6) << filter << " " << w << "x" << h << " level " << l << " sample " << i;
            above = got;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllFilters, BotMipLevels, ::testing::Values("box", "triangle", "lanczos3"));

TEST(BotMipLevels, BoxOfConstantImageIsConstant) {
    std::vector<float> src(size_t(13) * 7 * 3, 0.25f);
    const fs::path path = tempDir() / "const.bot";
    BotWriteOptions opt;
    opt.pixelType = PixelType::Float;
    opt.filter = "lanczos3";
    writeBot(path, src.data(), 13, 7, 3, opt);
    const auto file = BotFile::open(path);
    for (uint32_t l = 0; l < file->header().levels.size(); ++l)
        for (float v : readLevel(*file, l)) ASSERT_NEAR(v, 0.25f, 1e-6f) << "level " << l;
}

TEST(BotMipLevels, SrgbEightBitIsFilteredInLinearLight) {
    // A black/white checker averages to half the linear intensity, i.e. sRGB code 188, not 128.
    const uint32_t w = 2, h = 2, ch = 4;
    std::vector<float> src(w * h * ch);
    for (uint32_t i = 0; i < w * h; ++i) {
        const float v = (i == 0 || i == 3) ? 1.0f : 0.0f;
        src[i * ch + 0] = src[i * ch + 1] = src[i * ch + 2] = v;
        src[i * ch + 3] = v;  // alpha is linear and averages to 0.5
    }
    const fs::path path = tempDir() / "srgb.bot";
    BotWriteOptions opt;
    opt.colorSpace = ColorSpace::SRGB;
    writeBot(path, src.data(), w, h, ch, opt);
    const auto file = BotFile::open(path);
    EXPECT_EQ(file->header().colorSpace, ColorSpace::SRGB);
    const std::vector<float> top = readLevel(*file, 1);
    const double srgbHalf = 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055;
    const int code = int(std::lround(srgbHalf * 255.0));
    EXPECT_EQ(code, 188);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(std::lround(top[c] * 255.0f), code) << "channel " << c;
    EXPECT_EQ(std::lround(top[3] * 255.0f), 128);  // 127.5 rounds up

    // The same data tagged linear averages in the stored values.
    const fs::path linPath = tempDir() / "lin.bot";
    writeBot(linPath, src.data(), w, h, ch, BotWriteOptions{});
    const auto lin = BotFile::open(linPath);
    EXPECT_EQ(std::lround(readLevel(*lin, 1)[0] * 255.0f), 128);
}

TEST(BotMipLevels, NanAndInfinityDoNotSpreadIntoMips) {
    std::vector<float> src(16 * 16, 0.5f);
    src[17] = std::nanf("");
    src[40] = INFINITY;
    const fs::path path = tempDir() / "nan.bot";
    BotWriteOptions opt;
    opt.pixelType = PixelType::Float;
    writeBot(path, src.data(), 16, 16, 1, opt);
    const auto file = BotFile::open(path);
    for (uint32_t l = 1; l < file->header().levels.size(); ++l)
        for (float v : readLevel(*file, l)) ASSERT_FALSE(std::isnan(v)) << "level " << l;
}

// ------------------------------------------------------------------ damaged and hostile files

std::vector<uint8_t> validFile(uint32_t w, uint32_t h, uint32_t ch, const std::string& name, uint32_t version = 2) {
    const std::vector<float> src = makeImage(w, h, ch, PixelType::U8, 77);
    const fs::path path = tempDir() / name;
    BotWriteOptions opt;
    opt.version = version;
    writeBot(path, src.data(), w, h, ch, opt);
    return readBytes(path);
}

// Recomputes the table checksum after a test edits header or tables, so the edit itself is what
// the reader has to reject.
void reseal(std::vector<uint8_t>& b) {
    using namespace detail;
    if (get32(&b[kFieldVersion]) == kBotVersion3) {
        const uint64_t trailer = get64(&b[kField3TrailerOffset]);
        ASSERT_LE(trailer, b.size());
        put64(&b[kFieldMetaChecksum],
              xxh64(b.data() + trailer, size_t(b.size() - trailer), xxh64(b.data(), kFieldMetaChecksum, 0)));
        return;
    }
    const uint64_t dataStart = get64(&b[kFieldDictionary]) + get32(&b[kFieldDictionaryBytes]);
    ASSERT_LE(dataStart, b.size());
    put64(&b[kFieldMetaChecksum],
          xxh64(b.data() + kBotHeaderBytes, size_t(dataStart - kBotHeaderBytes), xxh64(b.data(), kFieldMetaChecksum, 0)));
}

std::string openError(const std::vector<uint8_t>& bytes, const fs::path& path) {
    writeBytes(path, bytes);
    try {
        BotFile::open(path);
    } catch (const FormatError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        return e.what();
    }
    return "";
}

TEST(BotFileErrors, MissingFileIsIoErrorNamingIt) {
    const fs::path path = tempDir() / "does_not_exist.bot";
    try {
        BotFile::open(path);
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("does_not_exist.bot"), std::string::npos);
    }
}

TEST(BotFileErrors, TruncatedFilesAreFormatErrors) {
    const std::vector<uint8_t> good = validFile(40, 30, 3, "trunc_src.bot");
    const fs::path path = tempDir() / "truncated.bot";
    for (size_t len : {size_t(0), size_t(5), size_t(95), size_t(96), size_t(200), good.size() / 2, good.size() - 1}) {
        std::vector<uint8_t> cut(good.begin(), good.begin() + std::ptrdiff_t(len));
        EXPECT_NE(openError(cut, path), "") << "length " << len;
    }
}

TEST(BotFileErrors, FlippedPageByteNamesThePage) {
    std::vector<uint8_t> bytes = validFile(40, 30, 3, "flip_src.bot");
    const fs::path path = tempDir() / "flipped.bot";
    writeBytes(path, bytes);
    const auto file = BotFile::open(path);
    const uint64_t index = file->pageIndex(0, 2, 1);
    const BotPageEntry e = file->pageEntry(index);
    bytes[e.offsetBytes + e.storedBytes / 2] ^= 0x10;
    writeBytes(path, bytes);
    const auto damaged = BotFile::open(path);  // tables are intact
    std::vector<float> page(64 * 3);
    const int fd = ::open(path.c_str(), O_RDONLY);
    try {
        damaged->readPage(fd, 0, 2, 1, page.data());
        FAIL() << "no exception";
    } catch (const FormatError& err) {
        const std::string msg = err.what();
        EXPECT_NE(msg.find("checksum mismatch"), std::string::npos) << msg;
        EXPECT_NE(msg.find("level 0 page (2, 1)"), std::string::npos) << msg;
        EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    }
    EXPECT_NO_THROW(damaged->readPage(fd, 0, 1, 1, page.data()));  // neighbours still read
    ::close(fd);
}

TEST(BotFileErrors, PageTableNamingTheWrongKindFailsTheChecksum) {
    using namespace detail;
    const uint32_t w = 160, h = 136;
    const std::vector<float> src = noisyImage(w, h, 3, 41);
    const fs::path path = tempDir() / "kind_src.bot";
    BotWriteOptions opt;
    opt.version = 2;
    writeBot(path, src.data(), w, h, 3, opt);
    const auto file = BotFile::open(path);
    const uint64_t pageTable = get64(&readBytes(path)[kFieldPageTable]);
    // Rewrite each compressed page's kind as every other compressed kind, seal the tables again:
    // the page's own checksum still catches it.
    int tried = 0;
    for (uint64_t index : {uint64_t(0), file->pageIndex(0, 7, 5), file->pageIndex(1, 2, 3)}) {
        const BotPageEntry e = file->pageEntry(index);
        ASSERT_NE(e.kind, BotPageKind::Raw);
        for (BotPageKind other : {BotPageKind::Frame, BotPageKind::Block, BotPageKind::Literals}) {
            if (other == e.kind) continue;
            std::vector<uint8_t> b = readBytes(path);
            put16(&b[pageTable + index * kBotPageEntryBytes], uint16_t(uint32_t(other) << kBotPageKindShift | e.storedBytes));
            reseal(b);
            const auto damaged = BotFile::parse(b.data(), b.size(), "kind.bot");
            std::vector<float> page(64 * 3);
            uint32_t level = 0, px = 0, py = 0;
            for (uint32_t l = 0; l < damaged->header().levels.size(); ++l)
                if (index >= damaged->pageIndex(l, 0, 0)) level = l;
            const uint64_t inLevel = index - damaged->pageIndex(level, 0, 0);
            px = uint32_t(inLevel % damaged->header().levels[level].pagesX);
            py = uint32_t(inLevel / damaged->header().levels[level].pagesX);
            try {
                damaged->readPageFromMemory(b.data(), b.size(), level, px, py, page.data());
                ADD_FAILURE() << "no exception for " << pageKindName(other);
            } catch (const FormatError& err) {
                EXPECT_NE(std::string(err.what()).find("checksum mismatch"), std::string::npos) << err.what();
            }
            ++tried;
        }
    }
    EXPECT_EQ(tried, 6);
}

TEST(BotFileErrors, FileTruncatedAfterOpenNamesThePage) {
    std::vector<uint8_t> bytes = validFile(40, 30, 3, "late_src.bot");
    const fs::path path = tempDir() / "late.bot";
    writeBytes(path, bytes);
    const auto file = BotFile::open(path);
    const BotPageEntry last = file->pageEntry(file->pageIndex(0, 4, 3));
    ::truncate(path.c_str(), off_t(last.offsetBytes + 1));
    const int fd = ::open(path.c_str(), O_RDONLY);
    std::vector<float> page(64 * 3);
    try {
        file->readPage(fd, 0, 4, 3, page.data());
        FAIL() << "no exception";
    } catch (const FormatError& err) {
        EXPECT_NE(std::string(err.what()).find("level 0 page (4, 3)"), std::string::npos) << err.what();
    }
    ::close(fd);
}

TEST(BotFileErrors, CorruptTablesAreDetectedByChecksum) {
    std::vector<uint8_t> bytes = validFile(40, 30, 3, "table_src.bot");
    bytes[detail::kBotHeaderBytes + 20] ^= 1;
    EXPECT_NE(openError(bytes, tempDir() / "table.bot").find("checksum"), std::string::npos);
}

TEST(BotFileErrors, BadOffsetsAndSizesPastEndNameThePage) {
    using namespace detail;
    const std::vector<uint8_t> good = validFile(40, 30, 3, "off_src.bot");
    const uint64_t rowTable = get64(&good[kFieldRowTable]);
    const uint64_t pageTable = get64(&good[kFieldPageTable]);
    const fs::path path = tempDir() / "offsets.bot";
    {
        std::vector<uint8_t> b = good;
        put64(&b[rowTable + 8], uint64_t(1) << 40);  // level 0, page row 1 far past the end
        reseal(b);
        const std::string msg = openError(b, path);
        EXPECT_NE(msg.find("level 0 page (0, 1) lies outside the file"), std::string::npos) << msg;
    }
    {
        std::vector<uint8_t> b = good;
        put64(&b[rowTable], 3);  // inside the header
        reseal(b);
        EXPECT_NE(openError(b, path).find("level 0 page (0, 0)"), std::string::npos);
    }
    {
        std::vector<uint8_t> b = good;
        const uint64_t lastRow = rowTable + 8 * 3;  // level 0 has 4 page rows; move the last one to the end
        put64(&b[lastRow], b.size() - 100);
        reseal(b);
        const std::string msg = openError(b, path);
        EXPECT_NE(msg.find("level 0 page (0, 3) lies outside the file"), std::string::npos) << msg;
    }
    const uint32_t frame = uint32_t(BotPageKind::Frame) << kBotPageKindShift;
    {
        std::vector<uint8_t> b = good;
        put16(&b[pageTable], uint16_t(frame | 0));
        reseal(b);
        EXPECT_NE(openError(b, path).find("bad stored size 0 of level 0 page (0, 0)"), std::string::npos);
    }
    {
        std::vector<uint8_t> b = good;
        put16(&b[pageTable + kBotPageEntryBytes], uint16_t(frame | 3));  // no more than the prefix
        reseal(b);
        EXPECT_NE(openError(b, path).find("bad stored size 3 of level 0 page (1, 0)"), std::string::npos);
    }
    {
        std::vector<uint8_t> b = good;
        put16(&b[pageTable + 2 * kBotPageEntryBytes], uint16_t(frame | 192));  // not smaller than raw
        reseal(b);
        EXPECT_NE(openError(b, path).find("bad stored size 192 of level 0 page (2, 0)"), std::string::npos);
    }
    {
        std::vector<uint8_t> b = good;
        put16(&b[pageTable], 5);  // raw, with a size
        reseal(b);
        EXPECT_NE(openError(b, path).find("bad size field 5 of raw level 0 page (0, 0)"), std::string::npos);
    }
    {
        std::vector<uint8_t> b = good;
        put64(&b[kFieldPageTable], 1ull << 62);
        EXPECT_NE(openError(b, path).find("bad table offsets"), std::string::npos);
    }
}

TEST(BotFileErrors, AbsurdHeaderValuesAreRejectedWithoutAllocating) {
    using namespace detail;
    const std::vector<uint8_t> good = validFile(40, 30, 3, "absurd_src.bot");
    const fs::path path = tempDir() / "absurd.bot";
    auto with = [&](auto edit) {
        std::vector<uint8_t> b = good;
        edit(b);
        return openError(b, path);
    };
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldWidth], 1u << 31); put32(&b[kFieldHeight], 1u << 31); })
                  .find("bad dimensions 2147483648x2147483648"),
              std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldWidth], 0); }).find("bad dimensions"), std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldChannels], 0); }).find("bad channel count 0"), std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldChannels], 100000); }).find("bad channel count"), std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldLevelCount], 1000); }).find("bad level count 1000"), std::string::npos);
    EXPECT_NE(with([](auto& b) { b[kFieldPixelType] = 9; }).find("bad pixel type 9"), std::string::npos);
    EXPECT_NE(with([](auto& b) { b[0] = 'X'; }).find("bad magic"), std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldVersion], 1); }).find("unsupported BOT version 1"), std::string::npos);
    EXPECT_NE(with([](auto& b) { put32(&b[kFieldVersion], 4); }).find("unsupported BOT version 4"), std::string::npos);
    EXPECT_NE(with([](auto& b) { b[kFieldPageFilter] = 3; }).find("bad page filter 3"), std::string::npos);
    // Largest legal dimensions, but the page table they imply does not fit in the file.
    EXPECT_NE(with([](auto& b) {
                  put32(&b[kFieldWidth], kMaxDimension);
                  put32(&b[kFieldHeight], kMaxDimension);
                  put32(&b[kFieldLevelCount], 25);
              }).find("page count"),
              std::string::npos);
    EXPECT_NE(with([](auto& b) {
                  put32(&b[kFieldDictionaryBytes], 1u << 19);
              }).find("past end of file"),
              std::string::npos);
}

TEST(BotFile, ParseFromMemoryMatchesOpen) {
    const std::vector<uint8_t> bytes = validFile(40, 30, 3, "mem_src.bot");
    const auto file = BotFile::parse(bytes.data(), bytes.size(), "memory.bot");
    std::vector<float> a(64 * 3), b(64 * 3);
    const auto disk = BotFile::open(tempDir() / "mem_src.bot");
    const int fd = ::open(disk->path().c_str(), O_RDONLY);
    for (uint32_t l = 0; l < file->header().levels.size(); ++l)
        for (uint32_t py = 0; py < file->header().levels[l].pagesY; ++py)
            for (uint32_t px = 0; px < file->header().levels[l].pagesX; ++px) {
                file->readPageFromMemory(bytes.data(), bytes.size(), l, px, py, a.data());
                disk->readPage(fd, l, px, py, b.data());
                ASSERT_EQ(a, b);
            }
    ::close(fd);
    EXPECT_THROW(file->readPageFromMemory(bytes.data(), bytes.size(), 99, 0, 0, a.data()), std::out_of_range);
}

TEST(BotWriter, AbandonedWriterLeavesNoFileAndKeepsExistingOutput) {
    const fs::path path = tempDir() / "abandoned.bot";
    writeBytes(path, {1, 2, 3});
    {
        BotWriter writer(path, 16, 16, 1, BotWriteOptions{});
        std::vector<float> row(16, 0.5f);
        writer.addRows(0, 0, 1, row.data(), false);
        EXPECT_THROW(writer.finish(), std::logic_error);  // incomplete
    }
    EXPECT_EQ(readBytes(path), (std::vector<uint8_t>{1, 2, 3}));
    for (const auto& entry : fs::directory_iterator(tempDir()))
        EXPECT_EQ(entry.path().filename().string().find(".abandoned.bot.tmp"), std::string::npos) << entry.path();
}

TEST(BotWriter, RejectsBadArguments) {
    const fs::path path = tempDir() / "bad_args.bot";
    EXPECT_THROW(BotWriter(path, 0, 4, 1, BotWriteOptions{}), std::invalid_argument);
    EXPECT_THROW(BotWriter(path, 4, 4, 0, BotWriteOptions{}), std::invalid_argument);
    BotWriteOptions opt;
    opt.filter = "gaussian";
    EXPECT_THROW(BotWriter(path, 4, 4, 1, opt), std::invalid_argument);
    EXPECT_THROW(BotWriter(tempDir() / "no_such_dir" / "x.bot", 4, 4, 1, BotWriteOptions{}), IoError);
    EXPECT_FALSE(fs::exists(path));
}

// ------------------------------------------------------------------ version 3

// Options that write version 3 (also the default; the tests below say so where they depend on it).
BotWriteOptions version3Options() {
    BotWriteOptions opt;
    opt.version = 3;
    return opt;
}

// Every page filter for every pixel type reproduces level 0 exactly, and every level decodes.
class Bot3Codings : public ::testing::TestWithParam<std::tuple<PixelType, PageFilter>> {};

TEST_P(Bot3Codings, LevelZeroRoundTrips) {
    const auto [type, filter] = GetParam();
    const uint32_t w = 160, h = 136, ch = type == PixelType::U8 ? 3 : 4;
    std::vector<float> src = noisyImage(w, h, ch, 11);
    if (type == PixelType::Half)
        for (float& v : src) v = float(Imath::half(v));
    if (type == PixelType::Float)  // full float mantissas, some negative, some large
        for (size_t i = 0; i < src.size(); i += 7) src[i] = (src[i] - 0.3f) * 1.0e4f + float(i) * 1.0e-3f;
    const fs::path path = tempDir() / ("v3_" + std::string(pixelTypeName(type)) + "_" + pageFilterName(filter) + ".bot");
    BotWriteOptions opt = version3Options();
    opt.pixelType = type;
    opt.pageFilter = filter;
    writeBot(path, src.data(), w, h, ch, opt);
    const auto file = BotFile::open(path);
    EXPECT_EQ(file->version(), 3u);
    EXPECT_EQ(file->pageFilter(), filter);
    EXPECT_EQ(readLevel(*file, 0), src);
    for (uint32_t l = 1; l < file->header().levels.size(); ++l) {
        const std::vector<float> level = readLevel(*file, l);
        for (float v : level) ASSERT_TRUE(std::isfinite(v)) << "level " << l;
    }
}

INSTANTIATE_TEST_SUITE_P(
    All, Bot3Codings,
    ::testing::Combine(::testing::Values(PixelType::U8, PixelType::U16, PixelType::Half, PixelType::Float),
                       ::testing::Values(PageFilter::None, PageFilter::Med, PageFilter::Mean)),
    [](const auto& p) {
        return std::string(pixelTypeName(std::get<0>(p.param))) + "_" + pageFilterName(std::get<1>(p.param));
    });

// Constant areas (constant pages), white noise (raw pages) and smooth noisy areas (rANS pages).
TEST(Bot3File, EveryPageKindIsWrittenAndReadBack) {
    const uint32_t w = 256, h = 192, ch = 3;
    const std::vector<float> src = everyKindImage([](uint32_t c) { return float(32 * (c + 1)) / 255.0f; });
    const fs::path path = tempDir() / "kinds3.bot";
    writeBot(path, src.data(), w, h, ch, version3Options());
    const auto file = BotFile::open(path);
    uint64_t kinds[kBotPageKinds] = {};
    for (uint64_t i = 0; i < file->pageCount(); ++i) ++kinds[unsigned(file->pageEntry(i).kind)];
    for (BotPageKind k : {BotPageKind::Raw, BotPageKind::Rans, BotPageKind::Constant})
        EXPECT_GT(kinds[unsigned(k)], 0u) << pageKindName(k) << " pages";
    EXPECT_EQ(kinds[unsigned(BotPageKind::Frame)] + kinds[unsigned(BotPageKind::Block)] +
                  kinds[unsigned(BotPageKind::Literals)],
              0u);
    EXPECT_EQ(readLevel(*file, 0), src);
}

// A level wider than a band's page budget allows is cut into bands of page rows, each with its own
// tables; pages of every band read back.
TEST(Bot3File, LevelsAreCutIntoBands) {
    const uint32_t w = 2100, h = 520, ch = 1;  // 263 x 65 pages of 64 bytes: 62 page rows a band
    std::vector<float> src = noisyImage(w, h, ch, 5);
    for (uint32_t y = h / 2; y < h; ++y)  // the lower half smooth: its band fits other tables
        for (uint32_t x = 0; x < w; ++x) src[size_t(y) * w + x] = float((x / 16 + y / 64) % 256) / 255.0f;
    const fs::path path = tempDir() / "bands.bot";
    writeBot(path, src.data(), w, h, ch, version3Options());
    const auto file = BotFile::open(path);
    EXPECT_EQ(detail::bot3BandRows(file->header().levels[0].pagesX, file->pageRawBytes()), 62u);
    // Level 0 (263 x 65 pages): two bands; level 1 (132 x 33 pages): one; levels 2 to 12, each of
    // fewer than 4096 pages: the tail band.
    EXPECT_EQ(file->bandCount(), 4u);
    EXPECT_EQ(readLevel(*file, 0), src);
    for (uint32_t l = 1; l < file->header().levels.size(); ++l) EXPECT_NO_THROW(readLevel(*file, l));
}

// Smooth content, where version 2's per-page zstd costs most: version 3 stores it in much less.
TEST(Bot3File, SmoothContentIsSmallerThanVersion2) {
    const uint32_t w = 512, h = 512, ch = 3;
    std::vector<float> src(size_t(w) * h * ch);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < ch; ++c)  // a sky: slow gradients, 8-bit banding
                src[(size_t(y) * w + x) * ch + c] =
                    float(int(40.0f + 120.0f * float(y) / h + 30.0f * float(c) * float(x) / w)) / 255.0f;
    uint64_t bytes[2] = {};
    for (uint32_t version : {2u, 3u}) {
        const fs::path path = tempDir() / ("smooth_v" + std::to_string(version) + ".bot");
        BotWriteOptions opt;
        opt.version = version;
        writeBot(path, src.data(), w, h, ch, opt);
        const auto file = BotFile::open(path);
        EXPECT_EQ(readLevel(*file, 0), src);
        bytes[version - 2] = file->fileBytes();
    }
    EXPECT_LT(double(bytes[1]), 0.6 * double(bytes[0])) << bytes[1] << " against " << bytes[0];
}

// A grey image stored as RGB, or as RGBA with an alpha that follows it (a mask): coding channels 1
// to 3 as differences from the channel before makes them all zero, so the file costs little more
// than the one-channel file of the same image.
TEST(Bot3File, GreyImageAsRgbOrRgbaCostsLittleMoreThanOneChannel) {
    const uint32_t w = 256, h = 192;
    const std::vector<float> grey = noisyImage(w, h, 1, 8);
    uint64_t oneChannel = 0;
    for (uint32_t ch : {1u, 3u, 4u}) {
        std::vector<float> src(grey.size() * ch);
        for (size_t i = 0; i < src.size(); ++i) src[i] = grey[i / ch];
        const fs::path path = tempDir() / ("grey" + std::to_string(ch) + ".bot");
        BotWriteOptions opt = version3Options();
        opt.alphaChannel = ch == 4 ? 3 : -1;
        writeBot(path, src.data(), w, h, ch, opt);
        const auto file = BotFile::open(path);
        EXPECT_EQ(readLevel(*file, 0), src);
        for (uint32_t l = 1; l < file->header().levels.size(); ++l) EXPECT_NO_THROW(readLevel(*file, l));
        if (ch == 1) oneChannel = file->fileBytes();
        else EXPECT_LT(double(file->fileBytes()), 1.3 * double(oneChannel)) << file->fileBytes() << " against " << oneChannel;
    }
}

// Flat areas: a page whose residuals are all zero stores nothing; its entry (one byte) names a colour
// of its band's palette, where each colour is stored once.
TEST(Bot3File, ConstantPagesCostOneEntryByte) {
    const uint32_t w = 512, h = 512, ch = 4;
    std::vector<float> src(size_t(w) * h * ch);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < ch; ++c)  // four flat quadrants
                src[(size_t(y) * w + x) * ch + c] = float(40 * (c + 1) + 60 * (x >= w / 2) + 30 * (y >= h / 2)) / 255.0f;
    const fs::path path = tempDir() / "flat3.bot";
    writeBot(path, src.data(), w, h, ch, version3Options());
    const auto file = BotFile::open(path);
    EXPECT_EQ(readLevel(*file, 0), src);
    uint64_t constant = 0;
    for (uint64_t i = 0; i < file->pageCount(); ++i) constant += file->pageEntry(i).kind == BotPageKind::Constant;
    EXPECT_GE(constant, 4096u);  // all of level 0, most of the mip levels
    EXPECT_LT(file->fileBytes(), file->pageCount() + 8 * (file->pageCount() - constant) + 4096)
        << file->fileBytes() << " bytes for " << file->pageCount() << " pages";
}

// Where the page table of a version-3 file starts: after the level, row and band tables.
uint64_t bot3PageTable(const std::vector<uint8_t>& b, const BotFile& file) {
    using namespace detail;
    uint64_t rows = 0;
    for (const BotLevel& l : file.header().levels) rows += l.pagesY;
    const uint8_t* at = b.data() + get64(&b[kField3TrailerOffset]) + file.header().levels.size() * 8 + rows * 8;
    for (uint64_t k = 0; k < file.bandCount(); ++k) {
        ++at;  // the band's coding byte
        EXPECT_NE(RansTableSet::parse(at, b.data() + b.size(), ransContextCount(file.header().pixelType)), nullptr);
        uint32_t colours = 0;
        EXPECT_TRUE(readVarint(at, b.data() + b.size(), colours));
        at += colours * pagePrefixBytes(file.header().channels, file.header().pixelType);
    }
    return uint64_t(at - b.data());
}

std::vector<uint8_t> validFile3(const std::string& name) {
    const std::vector<float> src = noisyImage(40, 30, 3, 71);
    const fs::path path = tempDir() / name;
    writeBot(path, src.data(), 40, 30, 3, version3Options());
    return readBytes(path);
}

TEST(Bot3FileErrors, TruncatedFilesAreFormatErrors) {
    const std::vector<uint8_t> good = validFile3("trunc3_src.bot");
    ASSERT_EQ(detail::get32(&good[detail::kFieldVersion]), 3u);
    const fs::path path = tempDir() / "truncated3.bot";
    for (size_t len : {size_t(0), size_t(95), size_t(96), size_t(200), good.size() / 2, good.size() - 1}) {
        std::vector<uint8_t> cut(good.begin(), good.begin() + std::ptrdiff_t(len));
        EXPECT_NE(openError(cut, path), "") << "length " << len;
    }
}

TEST(Bot3FileErrors, FlippedPageByteNamesThePage) {
    std::vector<uint8_t> bytes = validFile3("flip3_src.bot");
    const auto file = BotFile::parse(bytes.data(), bytes.size(), "flip3.bot");
    const uint64_t index = file->pageIndex(0, 2, 1);
    const BotPageEntry e = file->pageEntry(index);
    ASSERT_EQ(e.kind, BotPageKind::Rans);
    std::vector<float> page(64 * 3);
    for (uint32_t at : {0u, uint32_t(e.storedBytes) / 2, uint32_t(e.storedBytes) - 1}) {
        std::vector<uint8_t> b = bytes;
        b[e.offsetBytes + at] ^= 0x10;
        const auto damaged = BotFile::parse(b.data(), b.size(), "flip3.bot");  // the trailer is intact
        try {
            damaged->readPageFromMemory(b.data(), b.size(), 0, 2, 1, page.data());
            ADD_FAILURE() << "no exception, byte " << at;
        } catch (const FormatError& err) {
            const std::string msg = err.what();
            // A rANS page's checksum is checked on what it decodes to, after the decoder's own checks.
            EXPECT_TRUE(msg.find("checksum mismatch in level 0 page (2, 1)") != std::string::npos ||
                        msg.find("corrupt rANS data in level 0 page (2, 1)") != std::string::npos)
                << msg;
            EXPECT_NE(msg.find("flip3.bot"), std::string::npos) << msg;
        }
        EXPECT_NO_THROW(damaged->readPageFromMemory(b.data(), b.size(), 0, 1, 1, page.data()));
    }
}

TEST(Bot3FileErrors, CorruptTrailerIsDetectedByChecksum) {
    std::vector<uint8_t> bytes = validFile3("trailer3_src.bot");
    bytes[bytes.size() - 5] ^= 1;
    EXPECT_NE(openError(bytes, tempDir() / "trailer3.bot").find("header/trailer checksum mismatch"), std::string::npos);
}

// Header fields and tables edited and sealed again, so that only validation can reject them.
TEST(Bot3FileErrors, BadFieldsAndTablesAreRejectedNamingWhat) {
    using namespace detail;
    const std::vector<uint8_t> good = validFile3("fields3_src.bot");
    const auto file = BotFile::parse(good.data(), good.size(), "fields3.bot");
    const fs::path path = tempDir() / "fields3.bot";
    auto with = [&](auto edit) {
        std::vector<uint8_t> b = good;
        edit(b);
        reseal(b);
        return openError(b, path);
    };
    const uint64_t trailer = get64(&good[kField3TrailerOffset]);
    const uint64_t pageTable = bot3PageTable(good, *file);
    const uint64_t rowTable = trailer + file->header().levels.size() * 8;
    const uint64_t bandTable = rowTable + 8 * (4 + 2 + 1 + 1 + 1 + 1);  // page rows of 40x30 ... 1x1
    EXPECT_NE(with([&](auto& b) { b[kFieldPageFilter] = 1; }).find("bad page filter field 1"), std::string::npos);
    EXPECT_NE(with([&](auto& b) { put64(&b[kField3BandCount], 99); }).find("bad band count 99"), std::string::npos);
    EXPECT_NE(with([&](auto& b) { put64(&b[kFieldPageCount], 99); }).find("bad page count 99"), std::string::npos);
    // The trailer's place is checked before its checksum.
    for (uint64_t offset : {trailer + 1, trailer - 1, uint64_t(1) << 62, uint64_t(10)}) {
        std::vector<uint8_t> b = good;
        put64(&b[kField3TrailerOffset], offset);
        EXPECT_NE(openError(b, path).find("bad trailer offset"), std::string::npos) << offset;
    }
    {
        std::vector<uint8_t> b = good;  // a trailer too small for the page table
        put64(&b[kField3TrailerOffset], b.size() - 40);
        put64(&b[kField3TrailerBytes], 40);
        EXPECT_NE(openError(b, path).find("cannot hold the tables of"), std::string::npos);
    }
    EXPECT_NE(with([&](auto& b) { put64(&b[kField3Reserved], 1); }).find("reserved header fields"), std::string::npos);
    EXPECT_NE(with([&](auto& b) { b[bandTable] = 3; }).find("bad coding byte of the tail band (levels 0 to 5)"), std::string::npos);
    EXPECT_NE(with([&](auto& b) { b[bandTable] = 13; }).find("bad coding byte of the tail band (levels 0 to 5)"), std::string::npos);
    // Channel 3 coded as a difference in an RGB file.
    EXPECT_NE(with([&](auto& b) { b[bandTable] = 9; }).find("bad coding byte of the tail band (levels 0 to 5)"), std::string::npos);
    // Sixteen zero bits where the first table's symbol count starts: a gamma code of more than 256.
    EXPECT_NE(with([&](auto& b) {
                  b[bandTable + 1] = 0;
                  b[bandTable + 2] = 0;
              }).find("corrupt coding tables of the tail band (levels 0 to 5)"),
              std::string::npos);
    EXPECT_NE(with([&](auto& b) { put64(&b[rowTable + 8], uint64_t(1) << 40); })
                  .find("level 0 page (0, 1) lies outside the page data"),
              std::string::npos);
    EXPECT_NE(with([&](auto& b) { put64(&b[rowTable], 3); }).find("level 0 page (0, 0) lies outside"), std::string::npos);
    // Page (0, 0)'s entry (one byte): a first byte no entry has, then a size a rANS page cannot
    // have and a colour its band does not have.
    ASSERT_EQ(file->pageEntry(0).kind, BotPageKind::Rans);
    ASSERT_LT(file->pageEntry(0).storedBytes, 7u + 128u);  // one entry byte (RGB 8-bit: 7 bytes of states)
    auto entryWith = [&](std::vector<uint8_t> entry) {
        return with([&](auto& b) { std::copy(entry.begin(), entry.end(), b.begin() + std::ptrdiff_t(pageTable)); });
    };
    EXPECT_NE(entryWith({0xf8}).find("bad page entry 248 of level 0 page (0, 0)"), std::string::npos);
    EXPECT_NE(entryWith({0x80, 57}).find("bad stored size 192 of rans level 0 page (0, 0)"), std::string::npos);
    EXPECT_NE(entryWith({0xe0, 168}).find("bad constant colour 200 of level 0 page (0, 0)"), std::string::npos);
    EXPECT_NE(with([&](auto& b) {
                  b.push_back(0);
                  put64(&b[kField3TrailerBytes], b.size() - trailer);
              }).find("1 unexpected bytes at the end of the trailer"),
              std::string::npos);
}

// A rANS page carries its checksum (of the page it decodes to) in its coder's states. Damaged coded
// bytes are refused, almost always already by the decoder noticing that its states do not end where
// the encoder began them (a page whose damage it cannot tell from data decodes to other texels,
// which the checksum catches), and nothing outside the page is read.
TEST(Bot3FileErrors, DamagedRansBytesAreRefused) {
    const std::vector<uint8_t> good = validFile3("forged3_src.bot");
    const auto file = BotFile::parse(good.data(), good.size(), "forged3.bot");
    int byCoding = 0, byChecksum = 0, damaged = 0;
    for (uint64_t index = 0; index < file->pageCount(); ++index) {
        const BotPageEntry e = file->pageEntry(index);
        if (e.kind != BotPageKind::Rans) continue;
        uint32_t level = 0;
        for (uint32_t l = 0; l < file->header().levels.size(); ++l)
            if (index >= file->pageIndex(l, 0, 0)) level = l;
        const uint64_t inLevel = index - file->pageIndex(level, 0, 0);
        const uint32_t px = uint32_t(inLevel % file->header().levels[level].pagesX);
        const uint32_t py = uint32_t(inLevel / file->header().levels[level].pagesX);
        // State A's low byte, state B's low byte, the first and the last byte of the stream.
        for (uint32_t at : {0u, 4u, 7u, uint32_t(e.storedBytes) - 1}) {
            std::vector<uint8_t> b = good;
            b[e.offsetBytes + at] ^= 0x55;
            std::vector<float> page(64 * 3);
            ++damaged;
            try {
                file->readPageFromMemory(b.data(), b.size(), level, px, py, page.data());
                ADD_FAILURE() << "page " << index << " byte " << at << " was not refused";
            } catch (const FormatError& err) {
                const std::string msg = err.what();
                if (msg.find("corrupt rANS data in level") != std::string::npos) ++byCoding;
                else if (msg.find("checksum mismatch in level") != std::string::npos) ++byChecksum;
                else ADD_FAILURE() << msg;
            }
        }
    }
    EXPECT_GT(damaged, 80);
    EXPECT_EQ(byCoding + byChecksum, damaged);
    EXPECT_GE(byCoding, damaged * 9 / 10);
}

}  // namespace
}  // namespace pushpin::texture

// ------------------------------------------------------------------ deterministic mutation test

namespace pushpin::texture {
namespace {

// Parses `bytes` and decodes every page. Returns true when everything read cleanly, false when a
// pushpin::Error was thrown. Anything else (crash, other exception) fails the test.
bool readEverything(const std::vector<uint8_t>& bytes) {
    try {
        const auto file = BotFile::parse(bytes.data(), bytes.size(), "mutant.bot");
        std::vector<float> page(kPageSizeTexels * kPageSizeTexels * file->header().channels);
        for (uint32_t l = 0; l < file->header().levels.size(); ++l)
            for (uint32_t py = 0; py < file->header().levels[l].pagesY; ++py)
                for (uint32_t px = 0; px < file->header().levels[l].pagesX; ++px)
                    file->readPageFromMemory(bytes.data(), bytes.size(), l, px, py, page.data());
        return true;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("mutant.bot"), std::string::npos) << e.what();
        return false;
    }
}

TEST(BotFileMutation, ThousandsOfMutantsNeverCrashAndFlipsAreAlwaysDetected) {
    // Per version: one file with several hundred pages (version 2: a trained dictionary), one
    // small half file.
    std::vector<std::vector<uint8_t>> seeds;
    for (uint32_t version : {2u, 3u}) {
        const std::string v = std::to_string(version);
        {
            const uint32_t w = 300, h = 200;
            std::vector<float> src(size_t(w) * h * 3);
            for (size_t i = 0; i < src.size(); ++i) src[i] = float((i * 7 + (i / 900) * 3) % 256) / 255.0f;
            BotWriteOptions opt;
            opt.version = version;
            writeBot(tempDir() / ("mut_a" + v + ".bot"), src.data(), w, h, 3, opt);
            seeds.push_back(readBytes(tempDir() / ("mut_a" + v + ".bot")));
        }
        {
            const std::vector<float> src = makeImage(13, 7, 2, PixelType::Half, 3);
            BotWriteOptions opt;
            opt.pixelType = PixelType::Half;
            opt.filter = "lanczos3";
            opt.version = version;
            writeBot(tempDir() / ("mut_b" + v + ".bot"), src.data(), 13, 7, 2, opt);
            seeds.push_back(readBytes(tempDir() / ("mut_b" + v + ".bot")));
        }
    }
    for (const auto& seed : seeds) ASSERT_TRUE(readEverything(seed));

    std::mt19937_64 rng(20240611);
    int detected = 0, cases = 0;
    for (int iter = 0; iter < 8000; ++iter) {
        const std::vector<uint8_t>& seed = seeds[iter % seeds.size()];
        const bool version3 = detail::get32(&seed[detail::kFieldVersion]) == detail::kBotVersion3;
        std::vector<uint8_t> b = seed;
        const int kind = int(rng() % 5);
        bool mustFail = false;
        switch (kind) {
            case 0: {  // one flipped bit anywhere: every byte is covered by a checksum
                const size_t pos = rng() % b.size();
                b[pos] ^= uint8_t(1u << (rng() % 8));
                mustFail = true;
                break;
            }
            case 1:  // truncation
                b.resize(rng() % b.size());
                mustFail = true;
                break;
            case 2: {  // inserted bytes
                const size_t pos = rng() % (b.size() + 1);
                const size_t n = 1 + rng() % 16;
                std::vector<uint8_t> ins(n);
                for (auto& v : ins) v = uint8_t(rng());
                b.insert(b.begin() + std::ptrdiff_t(pos), ins.begin(), ins.end());
                break;
            }
            case 3: {  // a header or table field overwritten, then resealed so only validation can catch it
                // Version 2: the header or the tables before the dictionary; version 3: the header
                // or the trailer.
                const size_t trailer = size_t(detail::get64(&b[detail::kField3TrailerOffset]));
                size_t pos = 0;
                if (!version3) {
                    pos = rng() % (size_t(detail::get64(&b[detail::kFieldDictionary])) - 8);
                } else {
                    pos = rng() % (detail::kBotHeaderBytes + (b.size() - trailer) - 8);
                    if (pos >= detail::kBotHeaderBytes) pos = trailer + (pos - detail::kBotHeaderBytes);
                }
                const uint64_t values[] = {0, ~0ull, rng(), 1ull << 31, 1ull << 63, b.size(), b.size() - 1};
                const uint64_t v = values[rng() % 7];
                for (int i = 0; i < 8; ++i) b[pos + size_t(i)] = uint8_t(v >> (8 * i));
                if (pos + 8 <= detail::kFieldMetaChecksum || pos >= detail::kBotHeaderBytes) {
                    const uint64_t dataStart =
                        version3 ? detail::get64(&b[detail::kField3TrailerOffset])
                                 : detail::get64(&b[detail::kFieldDictionary]) +
                                       detail::get32(&b[detail::kFieldDictionaryBytes]);
                    if (dataStart <= b.size() && detail::get32(&b[detail::kFieldVersion]) == (version3 ? 3u : 2u))
                        reseal(b);
                }
                break;
            }
            default: {  // several random bytes
                for (int k = 0; k < 1 + int(rng() % 8); ++k) b[rng() % b.size()] = uint8_t(rng());
                break;
            }
        }
        if (b == seed) continue;
        ++cases;
        const bool clean = readEverything(b);
        if (!clean) ++detected;
        if (mustFail) {
            ASSERT_FALSE(clean) << "undetected mutation kind " << kind << " at iteration " << iter;
        }
    }
    EXPECT_GT(cases, 7800);
    EXPECT_GT(detected, cases / 2);
}

}  // namespace
}  // namespace pushpin::texture
