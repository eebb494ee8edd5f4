// cache/error.h: the one small exception hierarchy every pushpin library throws at load and IO
// boundaries. Inner loops never throw; they return values (see STYLE.md "Errors").
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace pushpin {

// Base of everything pushpin throws on purpose.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// An operating-system call on a file failed: names the path, what was attempted and strerror(errno).
class IoError : public Error {
public:
    IoError(const std::filesystem::path& path, const std::string& what, int errnoValue);
    IoError(const std::filesystem::path& path, const std::string& message);
    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};

// A file was read but its content is invalid (corrupt, truncated, hostile). Names the file.
class FormatError : public Error {
public:
    FormatError(const std::filesystem::path& path, const std::string& message);
    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};

}  // namespace pushpin
