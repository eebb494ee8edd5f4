// tests/support/image_read.h: reads a whole image file back through OpenImageIO so that tests can
// check what was written: its size, channel names, stored format, file format and pixels.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pushpin::test {

// An image as read back; `ok` is false (with a test failure already added) when it could not be read.
template <typename T>
struct ImageReadBack {
    bool ok = false;
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> names;
    OIIO::TypeDesc format;   // the stored pixel format
    std::string formatName;  // OpenImageIO's name of the file format: "png", "openexr", ...
    std::vector<T> pixels;   // row-major, every channel, converted to T (float or uint8_t)
};

// Reads subimage 0, mip level 0 of `path` with the stored values as they are: the reader does not
// premultiply colour by alpha. Failures are added to the running test with ADD_FAILURE.
template <typename T = float>
ImageReadBack<T> readImage(const std::filesystem::path& path) {
    ImageReadBack<T> r;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    if (!in) {
        ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
        return r;
    }
    const OIIO::ImageSpec& spec = in->spec();
    r.width = spec.width;
    r.height = spec.height;
    r.channels = spec.nchannels;
    r.names = spec.channelnames;
    r.format = spec.format;
    r.formatName = in->format_name();
    r.pixels.resize(static_cast<size_t>(r.width) * r.height * r.channels);
    r.ok = in->read_image(0, 0, 0, r.channels, OIIO::BaseTypeFromC<T>::value, r.pixels.data());
    EXPECT_TRUE(r.ok) << "cannot read " << path << ": " << in->geterror();
    in->close();
    return r;
}

}  // namespace pushpin::test
