// tests/support/temp_folder.h: a private temporary folder for one test (mkdtemp under TMPDIR),
// removed with everything in it when the object goes out of scope, plus whole-file helpers.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

namespace pushpin::test {

class TempFolder {
public:
    // `prefix` names the folder ("pushpin-<prefix>-XXXXXX") so a leftover one says whose it is.
    explicit TempFolder(const std::string& prefix = "test") {
        std::string tmpl = (std::filesystem::temp_directory_path() / ("pushpin-" + prefix + "-XXXXXX")).string();
        if (!::mkdtemp(tmpl.data())) std::abort();
        path = tmpl;
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    std::filesystem::path path;
};

inline std::string readWholeFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void writeWholeFile(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary).write(text.data(), std::streamsize(text.size()));
}

}  // namespace pushpin::test
