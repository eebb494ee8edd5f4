#include "cache/error.h"

#include <cstring>

namespace pushpin {

namespace {

// A path as messages quote it: at most 200 bytes of it (its head and its file name), so an
// input that names a 50 MB path still makes a one-line message.
std::string quotedPath(const std::filesystem::path& path) {
    const std::string& text = path.native();
    constexpr size_t kMax = 200;
    if (text.size() <= kMax) return text;
    std::string tail = path.filename().native();
    if (tail.size() > kMax / 2) tail = tail.substr(0, kMax / 2) + "...";
    return text.substr(0, kMax / 2) + ".../" + tail + " (" + std::to_string(text.size()) + " bytes)";
}

}  // namespace

IoError::IoError(const std::filesystem::path& path, const std::string& what, int errnoValue)
    : Error(quotedPath(path) + ": " + what + ": " + std::strerror(errnoValue)), m_path(path), m_errno(errnoValue) {}

IoError::IoError(const std::filesystem::path& path, const std::string& message)
    : Error(quotedPath(path) + ": " + message), m_path(path) {}

FormatError::FormatError(const std::filesystem::path& path, const std::string& message)
    : Error(quotedPath(path) + ": " + message), m_path(path) {}

MemoryCapError::MemoryCapError(const std::string& message, uint64_t neededBytes, uint64_t capBytes)
    : Error(message), m_neededBytes(neededBytes), m_capBytes(capBytes) {}

}  // namespace pushpin
