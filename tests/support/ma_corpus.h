// tests/support/ma_corpus.h: the folder of public .ma scenes the tests read (PUSHPIN_MA_CORPUS, a
// CMake cache variable). The scenes are other people's data: tests read them in place and skip
// with a message where the folder is absent.
#pragma once

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <vector>

namespace pushpin::test {

inline std::filesystem::path maCorpusDir() { return std::filesystem::path(PUSHPIN_MA_CORPUS); }

// Every .ma file in the corpus folder, sorted so that per-file seeds and messages are stable;
// empty when the folder is absent.
inline std::vector<std::filesystem::path> maCorpusFiles() {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    if (!std::filesystem::is_directory(maCorpusDir(), ec)) return files;
    for (const auto& entry : std::filesystem::directory_iterator(maCorpusDir(), ec))
        if (entry.path().extension() == ".ma") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

// The folder of real scenes laid out as their authors' projects, beside the corpus folder.
inline std::filesystem::path maProjectsDir() { return maCorpusDir().parent_path() / "ma-projects"; }

// Every real .ma scene: the corpus folder's and every one found under the projects folder, sorted.
inline std::vector<std::filesystem::path> realSceneFiles() {
    std::vector<std::filesystem::path> files = maCorpusFiles();
    std::error_code ec;
    if (std::filesystem::is_directory(maProjectsDir(), ec))
        for (auto it = std::filesystem::recursive_directory_iterator(maProjectsDir(), ec);
             !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
            if (it->is_regular_file(ec) && it->path().extension() == ".ma") files.push_back(it->path());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace pushpin::test

// Skips the current test, naming the folder, when the corpus is absent.
#define PUSHPIN_REQUIRE_MA_CORPUS()                                                                 \
    if (::pushpin::test::maCorpusFiles().empty())                                                   \
    GTEST_SKIP() << "no .ma corpus at " << ::pushpin::test::maCorpusDir() << " (PUSHPIN_MA_CORPUS)"
