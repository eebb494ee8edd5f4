// texture/oiio_row_source.h: the OpenImageIO row reader (texture/row_source.h), for every format
// but WebP stills: a band of scanlines or tile rows per read, as float.
// Thread safety and errors: as RowSource's.
// Memory: what OpenImageIO's format reader keeps.
#pragma once

#include <filesystem>
#include <memory>

#include "texture/row_source.h"

namespace pushpin::texture {

std::unique_ptr<RowSource> openOiioRowSource(const std::filesystem::path& path);

}  // namespace pushpin::texture
