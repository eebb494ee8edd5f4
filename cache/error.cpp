#include "cache/error.h"

#include <cstring>

namespace pushpin {

IoError::IoError(const std::filesystem::path& path, const std::string& what, int errnoValue)
    : Error(path.string() + ": " + what + ": " + std::strerror(errnoValue)), m_path(path), m_errno(errnoValue) {}

IoError::IoError(const std::filesystem::path& path, const std::string& message)
    : Error(path.string() + ": " + message), m_path(path) {}

FormatError::FormatError(const std::filesystem::path& path, const std::string& message)
    : Error(path.string() + ": " + message), m_path(path) {}

}  // namespace pushpin
