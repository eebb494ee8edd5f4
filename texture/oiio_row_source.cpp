// texture/oiio_row_source.cpp: the OpenImageIO row reader behind RowSource.
#include "texture/oiio_row_source.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "cache/error.h"
#include "texture/detail/row_checks.h"
#include "texture/image_input.h"

namespace pushpin::texture {
namespace {

using detail::requireConvertibleSize;
using detail::rowsText;

ColorSpace colorSpaceOf(const OIIO::ImageSpec& spec) {
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    std::transform(cs.begin(), cs.end(), cs.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (cs.find("srgb") != std::string::npos) return ColorSpace::SRGB;
    const bool eightBit = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::INT8;
    return (eightBit && cs.empty()) ? ColorSpace::SRGB : ColorSpace::Linear;
}

class OiioRowSource final : public RowSource {
public:
    explicit OiioRowSource(const std::filesystem::path& path) : m_path(path), m_in(openImageInput(path)) {
        const OIIO::ImageSpec& spec = m_in->spec();
        if (spec.depth > 1 || spec.deep) throw FormatError(path, "volume and deep images are not supported");
        requireConvertibleSize(path, spec.width, spec.height, spec.nchannels);
        m_info.width = uint32_t(spec.width);
        m_info.height = uint32_t(spec.height);
        m_info.channels = uint32_t(spec.nchannels);
        m_info.pixelType = pixelTypeOf(spec.format);
        m_info.colorSpace = colorSpaceOf(spec);
        m_info.alphaChannel = spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels ? spec.alpha_channel : -1;
        m_tiled = spec.tile_width > 0 && spec.tile_height > 0;
        // Whole tile rows for tiled files, otherwise 64 scanlines.
        m_info.bandRows =
            m_tiled ? uint32_t(spec.tile_height) * std::max(1u, 64u / uint32_t(spec.tile_height)) : 64u;
        m_info.reader = "OpenImageIO";
    }
    ~OiioRowSource() override { m_in->close(); }

    void read(uint32_t y0, uint32_t rows, float* out) override {
        if (rows == 0 || y0 >= m_info.height || rows > m_info.height - y0)
            throw std::logic_error("OiioRowSource::read: rows outside the image");
        const OIIO::ImageSpec& spec = m_in->spec();
        bool ok;
        if (m_tiled) {
            ok = m_in->read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y + int(y0), spec.y + int(y0 + rows), spec.z,
                                  spec.z + 1, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out);
        } else {
            ok = m_in->read_scanlines(0, 0, spec.y + int(y0), spec.y + int(y0 + rows), spec.z, 0, spec.nchannels,
                                      OIIO::TypeDesc::FLOAT, out);
        }
        requireCleanRead(*m_in, ok, m_path, rowsText(y0, rows));
    }

private:
    std::filesystem::path m_path;
    std::unique_ptr<OIIO::ImageInput> m_in;
    bool m_tiled = false;
};

}  // namespace

std::unique_ptr<RowSource> openOiioRowSource(const std::filesystem::path& path) {
    return std::make_unique<OiioRowSource>(path);
}

}  // namespace pushpin::texture
