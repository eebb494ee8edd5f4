// texture/image_input.h: reading source images through OpenImageIO with every error it reports
// treated as an error. Several of OpenImageIO's readers (TIFF strips, JPEG) return success for a
// truncated or damaged file, fill the missing part with black and leave the reason only in the
// reader's error text; a texture made from that would verify and render wrong. These calls fail
// instead.
// Thread safety: the functions are reentrant; one ImageInput is used by one thread at a time.
// Memory: nothing beyond what the caller's buffers hold.
#pragma once

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <memory>
#include <string>

#include "texture/bot_file.h"

namespace pushpin::texture {

// Opens `path`; throws IoError naming the path and OpenImageIO's message when it cannot.
std::unique_ptr<OIIO::ImageInput> openImageInput(const std::filesystem::path& path);

// To call after each read call of `in` (read_image, read_scanlines, read_tiles…) with its return
// value: throws FormatError naming `path`, `what` ("rows 64-127") and the reader's message when the
// call failed or the reader reported any error during it. Consumes the reader's error text.
void requireCleanRead(OIIO::ImageInput& in, bool ok, const std::filesystem::path& path, const std::string& what);

// The stored pixel type closest to an OpenImageIO type: 8-bit -> U8, 16-bit -> U16, half -> Half,
// anything else -> Float.
PixelType pixelTypeOf(const OIIO::TypeDesc& type);

}  // namespace pushpin::texture
