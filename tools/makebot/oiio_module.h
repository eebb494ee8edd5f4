// tools/makebot/oiio_module.h: makebot's OpenImageIO reader lives in a module of its own,
// makebot-oiio.so beside the makebot binary, loaded the first time an input is not a WebP still.
// makebot itself does not link OpenImageIO, whose Debian build brings about 260 libraries: loading
// them costs about 0.18 s and 130 MB of resident memory before a pixel is read, which a WebP
// conversion then does not pay.
// The module's interface is plain C, so that no C++ exception or allocation crosses it: each call
// reports failure by its return value with the error's text in the caller's buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>

#include "texture/row_source.h"

extern "C" {
// Bumped whenever a declaration below changes.
constexpr int kMakebotOiioModuleVersion = 1;
using MakebotOiioVersionFn = int();
// Opens `path`: the reader, with *info filled in (info->reader points into the module), or nullptr
// with the error's text in message (at most messageBytes bytes, NUL-terminated).
using MakebotOiioOpenFn = void*(const char* path, pushpin::texture::RowSourceInfo* info, char* message,
                                size_t messageBytes);
// RowSource::read; 0 when done, else -1 with the error's text in message.
using MakebotOiioReadFn = int(void* reader, uint32_t y0, uint32_t rows, float* out, char* message,
                              size_t messageBytes);
using MakebotOiioCloseFn = void(void* reader);
}

namespace pushpin::makebot {

// The module's file name, looked for in the folder of the running makebot.
constexpr const char* kOiioModuleName = "makebot-oiio.so";

// openOiioRowSource through the module, loading it on the first call. Throws pushpin::Error
// naming the module when it cannot be loaded, and the reader's errors as pushpin::Error with their
// text unchanged.
std::unique_ptr<texture::RowSource> openOiioRowSourceFromModule(const std::filesystem::path& path);

}  // namespace pushpin::makebot
