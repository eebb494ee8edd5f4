// libFuzzer target for the BOT reader: parses the input as a whole BOT file held in memory and
// decodes every page, once as from memory and once as from a file mapping (the texture cache's
// path), which must agree. The input is also read as edits of a small valid file of each version
// (2 and 3), optionally with the table checksum sealed again, so that mutations reach the table
// and page decoders behind the checksums without the fuzzer having to find a valid file first.
// pushpin::Error is the expected outcome for bad input; anything else (a crash, a sanitizer report,
// another exception, the two paths disagreeing) is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cache/error.h"
#include "texture/bot_file.h"
#include "texture/detail/bot_checksum.h"
#include "texture/detail/bot_layout.h"

namespace {

using namespace pushpin::texture;

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

void readEverything(const uint8_t* data, size_t size) {
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
}

// A 24x20 RGB file of smooth content with noise (rANS, constant and raw pages in version 3),
// written once per process.
std::vector<uint8_t> seedFile(uint32_t version) {
    const uint32_t w = 24, h = 20, ch = 3;
    std::vector<float> px(size_t(w) * h * ch);
    for (size_t i = 0; i < px.size(); ++i)
        px[i] = float((i / 3 % w < 8 ? 40 : (i * 2654435761u >> 13) % 23 + (i / 3 / w) * 4) % 256) / 255.0f;
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("pushpin_bot_fuzz_seed_" + std::to_string(::getpid()) + ".bot");
    BotWriteOptions opt;
    opt.version = version;
    writeBot(path, px.data(), w, h, ch, opt);
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(path);
    return bytes;
}

// Seals the table checksum of an edited file again (when its header still says where the tables are).
void reseal(std::vector<uint8_t>& b) {
    using namespace pushpin::texture::detail;
    if (b.size() < kBotHeaderBytes) return;
    uint64_t begin = kBotHeaderBytes, end = 0;
    if (get32(&b[kFieldVersion]) == kBotVersion3) {
        begin = get64(&b[kField3TrailerOffset]);
        end = b.size();
    } else {
        end = get64(&b[kFieldDictionary]) + get32(&b[kFieldDictionaryBytes]);
    }
    if (begin > end || end > b.size()) return;
    put64(&b[kFieldMetaChecksum], xxh64(b.data() + begin, size_t(end - begin), xxh64(b.data(), kFieldMetaChecksum, 0)));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    readEverything(data, size);
    // Edits of a valid file: byte 0 picks the version (bit 0) and whether to seal the tables again
    // (bit 1); then each 3 bytes set the byte at a 16-bit position (modulo the size) to a value.
    static const std::vector<uint8_t> seeds[2] = {seedFile(2), seedFile(3)};
    if (size >= 4) {
        std::vector<uint8_t> b = seeds[data[0] & 1];
        for (size_t i = 1; i + 3 <= size; i += 3) b[(size_t(data[i]) | size_t(data[i + 1]) << 8) % b.size()] = data[i + 2];
        if (data[0] & 2) reseal(b);
        readEverything(b.data(), b.size());
    }
    return 0;
}
