// tools/makebot/oiio/module.cpp: makebot-oiio.so, the OpenImageIO row reader behind the C
// interface of tools/makebot/oiio_module.h.
#include <cstring>
#include <exception>
#include <string>

#include "texture/oiio_row_source.h"
#include "tools/makebot/oiio_module.h"

namespace {

void putMessage(const char* text, char* message, size_t messageBytes) {
    if (!message || messageBytes == 0) return;
    const size_t n = std::min(std::strlen(text), messageBytes - 1);
    std::memcpy(message, text, n);
    message[n] = '\0';
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int pushpin_makebot_oiio_version() { return kMakebotOiioModuleVersion; }

__attribute__((visibility("default"))) void* pushpin_makebot_oiio_open(const char* path,
                                                                        pushpin::texture::RowSourceInfo* info,
                                                                        char* message, size_t messageBytes) {
    try {
        auto source = pushpin::texture::openOiioRowSource(path);
        *info = source->info();
        return source.release();
    } catch (const std::exception& e) {
        putMessage(e.what(), message, messageBytes);
    } catch (...) {
        putMessage("unknown error in the OpenImageIO reader", message, messageBytes);
    }
    return nullptr;
}

__attribute__((visibility("default"))) int pushpin_makebot_oiio_read(void* reader, uint32_t y0, uint32_t rows,
                                                                      float* out, char* message,
                                                                      size_t messageBytes) {
    try {
        static_cast<pushpin::texture::RowSource*>(reader)->read(y0, rows, out);
        return 0;
    } catch (const std::exception& e) {
        putMessage(e.what(), message, messageBytes);
    } catch (...) {
        putMessage("unknown error in the OpenImageIO reader", message, messageBytes);
    }
    return -1;
}

__attribute__((visibility("default"))) void pushpin_makebot_oiio_close(void* reader) {
    delete static_cast<pushpin::texture::RowSource*>(reader);
}

}  // extern "C"
