// Tests of texture/row_source.h: the libwebp reader hands out exactly what OpenImageIO's float read
// gives (lossy and lossless, with and without alpha, any band size, any slice of the file fed at a
// time), fails with the file and rows named on truncated and damaged files, and openRowSource picks
// the reader by the file's bytes.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <webp/encode.h>

#include <cstring>
#include <string>
#include <vector>

#include "cache/error.h"
#include "tests/support/temp_folder.h"
#include "texture/oiio_row_source.h"
#include "texture/row_source.h"

namespace pushpin::texture {
namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;

struct WebpCase {
    uint32_t width, height;
    bool alpha, lossless;
};

// Busy content: gradients with noise, and (with alpha) every alpha value.
std::vector<uint8_t> makePixels(const WebpCase& c) {
    const uint32_t channels = c.alpha ? 4 : 3;
    std::vector<uint8_t> px(size_t(c.width) * c.height * channels);
    uint32_t seed = 12345;
    for (uint32_t y = 0; y < c.height; ++y)
        for (uint32_t x = 0; x < c.width; ++x) {
            uint8_t* p = &px[(size_t(y) * c.width + x) * channels];
            seed = seed * 1103515245u + 12345u;
            const uint32_t noise = (seed >> 16) & 31;
            p[0] = uint8_t((x * 3 + noise) & 255);
            p[1] = uint8_t((y * 5 + noise) & 255);
            p[2] = uint8_t(((x ^ y) + noise) & 255);
            if (c.alpha) p[3] = uint8_t((x + y * c.width) & 255);
        }
    return px;
}

fs::path writeWebp(const fs::path& dir, const std::string& name, const WebpCase& c) {
    const std::vector<uint8_t> px = makePixels(c);
    uint8_t* out = nullptr;
    size_t n = 0;
    const int stride = int(c.width * (c.alpha ? 4 : 3));
    if (c.lossless)
        n = c.alpha ? WebPEncodeLosslessRGBA(px.data(), int(c.width), int(c.height), stride, &out)
                    : WebPEncodeLosslessRGB(px.data(), int(c.width), int(c.height), stride, &out);
    else
        n = c.alpha ? WebPEncodeRGBA(px.data(), int(c.width), int(c.height), stride, 90, &out)
                    : WebPEncodeRGB(px.data(), int(c.width), int(c.height), stride, 90, &out);
    EXPECT_GT(n, 0u);
    const fs::path path = dir / name;
    test::writeWholeFile(path, std::string(reinterpret_cast<const char*>(out), n));
    WebPFree(out);
    return path;
}

std::vector<float> oiioPixels(const fs::path& path, uint32_t& channels) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in);
    if (!in) return {};
    const OIIO::ImageSpec spec = in->spec();
    channels = uint32_t(spec.nchannels);
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    return px;
}

std::vector<float> readAll(RowSource& source, uint32_t band) {
    const RowSourceInfo& info = source.info();
    const size_t stride = size_t(info.width) * info.channels;
    std::vector<float> px(stride * info.height);
    for (uint32_t y = 0; y < info.height; y += band)
        source.read(y, std::min(band, info.height - y), px.data() + y * stride);
    return px;
}

TEST(RowSource, WebpRowsAreOpenImageIOsFloatRowsBitForBit) {
    test::TempFolder dir("rows");
    const WebpCase cases[] = {
        {67, 45, false, false}, {67, 45, true, false}, {256, 256, true, true}, {130, 97, false, true}, {1, 1, false, false},
    };
    for (const WebpCase& c : cases) {
        const std::string name = std::to_string(c.width) + "x" + std::to_string(c.height) + (c.alpha ? "a" : "") +
                                 (c.lossless ? "-lossless" : "-lossy") + ".webp";
        SCOPED_TRACE(name);
        const fs::path path = writeWebp(dir.path, name, c);
        uint32_t oiioChannels = 0;
        const std::vector<float> expected = oiioPixels(path, oiioChannels);
        // Slices from a few bytes (the decoder suspends inside every row) to the default.
        for (size_t slice : {size_t(7), size_t(500), size_t(32 * 1024)})
            for (uint32_t band : {1u, 13u, 64u}) {
                SCOPED_TRACE("slice " + std::to_string(slice) + " band " + std::to_string(band));
                auto source = openWebpRowSource(path, slice);
                EXPECT_STREQ(source->info().reader, "libwebp");
                ASSERT_EQ(source->info().channels, oiioChannels);
                EXPECT_EQ(source->info().alphaChannel, c.alpha ? 3 : -1);
                EXPECT_EQ(source->info().colorSpace, ColorSpace::SRGB);
                EXPECT_EQ(source->info().pixelType, PixelType::U8);
                const std::vector<float> got = readAll(*source, band);
                ASSERT_EQ(got.size(), expected.size());
                EXPECT_EQ(std::memcmp(got.data(), expected.data(), got.size() * sizeof(float)), 0);
            }
    }
}

TEST(RowSource, PicksTheReaderByTheFilesBytes) {
    test::TempFolder dir("rows");
    const fs::path webp = writeWebp(dir.path, "a.webp", {32, 24, false, true});
    // A WebP under another name is still read by libwebp.
    const fs::path renamed = dir.path / "texture.png";
    fs::copy_file(webp, renamed);
    EXPECT_STREQ(openRowSource(webp, openOiioRowSource)->info().reader, "libwebp");
    EXPECT_STREQ(openRowSource(renamed, openOiioRowSource)->info().reader, "libwebp");

    const fs::path png = dir.path / "b.png";
    auto out = OIIO::ImageOutput::create(png.string());
    OIIO::ImageSpec spec(32, 24, 3, OIIO::TypeDesc::UINT8);
    std::vector<uint8_t> px(32 * 24 * 3, 77);
    ASSERT_TRUE(out && out->open(png.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) &&
                out->close());
    auto source = openRowSource(png, openOiioRowSource);
    EXPECT_STREQ(source->info().reader, "OpenImageIO");
    std::vector<float> row(32 * 3 * 24);
    source->read(0, 24, row.data());
    EXPECT_FLOAT_EQ(row[5], 77.0f / 255.0f);
}

TEST(RowSource, TruncatedWebpNamesTheFileAndRows) {
    test::TempFolder dir("rows");
    for (bool lossless : {false, true}) {
        const fs::path whole = writeWebp(dir.path, lossless ? "w1.webp" : "w0.webp", {200, 150, false, lossless});
        const std::string bytes = test::readWholeFile(whole);
        const fs::path cut = dir.path / (lossless ? "cut1.webp" : "cut0.webp");
        test::writeWholeFile(cut, bytes.substr(0, bytes.size() * 2 / 3));
        auto source = openWebpRowSource(cut);
        std::vector<float> px(size_t(200) * 3 * 150);
        try {
            readAll(*source, 16);
            ADD_FAILURE() << "a truncated file was read whole";
        } catch (const FormatError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(cut.string()), std::string::npos) << what;
            EXPECT_NE(what.find("rows"), std::string::npos) << what;
            EXPECT_NE(what.find("truncated"), std::string::npos) << what;
        }
        // Cut inside the header: no reader at all.
        test::writeWholeFile(cut, bytes.substr(0, 20));
        EXPECT_THROW(openWebpRowSource(cut), FormatError);
    }
}

TEST(RowSource, DamagedWebpFailsCleanlyOrDecodes) {
    test::TempFolder dir("rows");
    for (bool lossless : {false, true}) {
        const fs::path whole = writeWebp(dir.path, "d.webp", {120, 90, true, lossless});
        const std::string bytes = test::readWholeFile(whole);
        // Flip bytes at several places past the header; each file must fail cleanly or decode.
        for (size_t at : {size_t(40), bytes.size() / 3, bytes.size() / 2, bytes.size() - 5}) {
            std::string bad = bytes;
            for (size_t k = at; k < std::min(bad.size(), at + 4); ++k) bad[k] = char(bad[k] ^ 0x5a);
            const fs::path path = dir.path / "bad.webp";
            test::writeWholeFile(path, bad);
            try {
                auto source = openWebpRowSource(path, 100);
                readAll(*source, 7);
            } catch (const FormatError& e) {
                EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
            }
        }
    }
}

TEST(RowSource, AnimatedOrForeignFilesAreNotTakenByTheWebpReader) {
    test::TempFolder dir("rows");
    // RIFF, then a VP8X chunk whose flags say "animation" (bit 1), canvas 16x16.
    std::string animated = "RIFF";
    const uint8_t vp8x[] = {'V', 'P', '8', 'X', 10, 0, 0, 0, 0x02, 0, 0, 0, 15, 0, 0, 15, 0, 0};
    const uint32_t riffSize = 4 + sizeof vp8x;
    animated += std::string{char(riffSize), 0, 0, 0} + "WEBP" + std::string(reinterpret_cast<const char*>(vp8x), sizeof vp8x);
    const fs::path anim = dir.path / "anim.webp";
    test::writeWholeFile(anim, animated);
    try {
        openWebpRowSource(anim);
        ADD_FAILURE() << "an animation was taken";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("animated"), std::string::npos) << e.what();
    }
    const fs::path text = dir.path / "text.webp";
    test::writeWholeFile(text, "not an image at all");
    EXPECT_THROW(openWebpRowSource(text), FormatError);
    EXPECT_THROW(openWebpRowSource(dir.path / "missing.webp"), IoError);
}

TEST(RowSource, RowsMustComeInOrder) {
    test::TempFolder dir("rows");
    const fs::path webp = writeWebp(dir.path, "o.webp", {16, 16, false, true});
    auto source = openWebpRowSource(webp);
    std::vector<float> px(16 * 3 * 16);
    EXPECT_THROW(source->read(4, 4, px.data()), std::logic_error);
    source->read(0, 16, px.data());
    EXPECT_THROW(source->read(16, 1, px.data()), std::logic_error);
}

}  // namespace
}  // namespace pushpin::texture

namespace pushpin::texture {
namespace {

// Rows whose values say where they are; fails on the band starting at failAt.
class CountingSource final : public RowSource {
public:
    CountingSource(uint32_t height, uint32_t band, uint32_t failAt = ~0u) : m_failAt(failAt) {
        m_info.width = 3;
        m_info.height = height;
        m_info.channels = 2;
        m_info.bandRows = band;
    }
    void read(uint32_t y0, uint32_t rows, float* out) override {
        EXPECT_EQ(y0, m_next);
        if (y0 == m_failAt) throw FormatError("counting", "band at " + std::to_string(y0) + " is damaged");
        for (uint32_t r = 0; r < rows; ++r)
            for (uint32_t i = 0; i < 6; ++i) out[r * 6 + i] = float((y0 + r) * 10 + i);
        m_next = y0 + rows;
    }

private:
    uint32_t m_failAt, m_next = 0;
};

TEST(RowPrefetcher, HandsOutEveryBandInOrderWhateverTheDepth) {
    for (uint32_t depth : {1u, 2u, 4u, 50u}) {
        CountingSource source(37, 8);
        RowPrefetcher bands(source, depth);
        uint32_t expect = 0;
        for (RowPrefetcher::Band b = bands.next(); b.rows; b = bands.next()) {
            EXPECT_EQ(b.firstRow, expect);
            EXPECT_EQ(b.rows, std::min(8u, 37u - expect));
            for (uint32_t r = 0; r < b.rows; ++r) EXPECT_EQ(b.values[r * 6 + 5], float((expect + r) * 10 + 5));
            expect += b.rows;
        }
        EXPECT_EQ(expect, 37u);
        EXPECT_EQ(bands.next().rows, 0u);
    }
}

TEST(RowPrefetcher, ASourceErrorReachesTheCallerAtItsBand) {
    CountingSource source(64, 8, 24);
    RowPrefetcher bands(source, 4);
    EXPECT_EQ(bands.next().firstRow, 0u);
    EXPECT_EQ(bands.next().firstRow, 8u);
    EXPECT_EQ(bands.next().firstRow, 16u);
    try {
        bands.next();
        ADD_FAILURE() << "the damaged band was handed out";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("band at 24"), std::string::npos) << e.what();
    }
}

TEST(RowPrefetcher, CanBeLeftBeforeTheEnd) {
    CountingSource source(1000, 4);
    RowPrefetcher bands(source, 3);
    EXPECT_EQ(bands.next().firstRow, 0u);
    // Destroyed here with the thread waiting for a free slot.
}

}  // namespace
}  // namespace pushpin::texture
