#include "texture/image_input.h"

#include "cache/error.h"

namespace pushpin::texture {

namespace {

// OpenImageIO error texts can run to one line per failed strip: keep the first lines.
std::string firstLines(const std::string& text, size_t maxLines = 3) {
    std::string out;
    size_t lines = 0, pos = 0;
    while (pos < text.size() && lines < maxLines) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        if (!out.empty()) out += "; ";
        out += text.substr(pos, end - pos);
        ++lines;
        pos = end + 1;
    }
    if (pos < text.size()) out += "; ...";
    return out;
}

}  // namespace

std::unique_ptr<OIIO::ImageInput> openImageInput(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) {
        const std::string message = OIIO::geterror();
        throw IoError(path, "cannot read image" + (message.empty() ? std::string() : ": " + firstLines(message)));
    }
    // Text left by open() describes the header, which was accepted; reads start from a clean slate.
    (void)in->geterror();
    return in;
}

void requireCleanRead(OIIO::ImageInput& in, bool ok, const std::filesystem::path& path, const std::string& what) {
    const std::string message = in.geterror();
    if (ok && message.empty()) return;
    throw FormatError(path, "cannot read " + what + (message.empty() ? std::string() : ": " + firstLines(message)) +
                                " (the file may be truncated or damaged)");
}

PixelType pixelTypeOf(const OIIO::TypeDesc& type) {
    switch (type.basetype) {
        case OIIO::TypeDesc::UINT8:
        case OIIO::TypeDesc::INT8: return PixelType::U8;
        case OIIO::TypeDesc::UINT16:
        case OIIO::TypeDesc::INT16: return PixelType::U16;
        case OIIO::TypeDesc::HALF: return PixelType::Half;
        default: return PixelType::Float;
    }
}

}  // namespace pushpin::texture
