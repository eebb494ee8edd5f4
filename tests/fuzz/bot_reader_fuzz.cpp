// libFuzzer target for the BOT reader: parses the input as a whole BOT file held in memory and
// decodes every page. pushpin::Error is the expected outcome for bad input; anything else (a crash,
// a sanitizer report, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cache/error.h"
#include "texture/bot_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace pushpin::texture;
    try {
        const auto file = BotFile::parse(data, size, "fuzz.bot");
        std::vector<float> page(kPageSizeTexels * kPageSizeTexels * file->header().channels);
        for (uint32_t l = 0; l < file->header().levels.size(); ++l)
            for (uint32_t py = 0; py < file->header().levels[l].pagesY; ++py)
                for (uint32_t px = 0; px < file->header().levels[l].pagesX; ++px)
                    file->readPageFromMemory(data, size, l, px, py, page.data());
    } catch (const pushpin::Error&) {
    }
    return 0;
}
