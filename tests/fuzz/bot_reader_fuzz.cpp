// libFuzzer target for the BOT reader: parses the input as a whole BOT file held in memory and
// decodes every page, once as from memory and once as from a file mapping (the texture cache's
// path), which must agree. pushpin::Error is the expected outcome for bad input; anything else (a
// crash, a sanitizer report, another exception, the two paths disagreeing) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "cache/error.h"
#include "texture/bot_file.h"

namespace {

// Decodes one page through `read`; returns false when it throws pushpin::Error.
template <class Read>
bool decode(Read read, std::vector<float>& page) {
    try {
        read(page.data());
        return true;
    } catch (const pushpin::Error&) {
        return false;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace pushpin::texture;
    try {
        const auto file = BotFile::parse(data, size, "fuzz.bot");
        const size_t n = kPageSizeTexels * kPageSizeTexels * file->header().channels;
        std::vector<float> a(n), b(n);
        for (uint32_t l = 0; l < file->header().levels.size(); ++l)
            for (uint32_t py = 0; py < file->header().levels[l].pagesY; ++py)
                for (uint32_t px = 0; px < file->header().levels[l].pagesX; ++px) {
                    const bool okMemory = decode(
                        [&](float* dst) { file->readPageFromMemory(data, size, l, px, py, dst); }, a);
                    const bool okMapped = decode(
                        [&](float* dst) { file->readPageFromMapping(data, size, l, px, py, dst); }, b);
                    // Compared bitwise: NaN payloads in float pages must survive both paths alike.
                    if (okMemory != okMapped || (okMemory && std::memcmp(a.data(), b.data(), n * sizeof(float)) != 0))
                        std::abort();
                }
    } catch (const pushpin::Error&) {
    }
    return 0;
}
