// libFuzzer entry point for the .ma reader: any input must load or throw pushpin::Error.
// References are not followed, so inputs never touch the file system.
#include "core/scene/ma_reader.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    pushpin::scene::ReadOptions options;
    options.loadReferences = false;
    try {
        pushpin::scene::MaReader::readString(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ma",
                                             options);
    } catch (const pushpin::Error&) {
    }
    return 0;
}
