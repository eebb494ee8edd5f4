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
    // The errno of the failed call; 0 when the failure was not an operating-system error.
    int errorCode() const { return m_errno; }

private:
    std::filesystem::path m_path;
    int m_errno = 0;
};

// Writing or publishing an output file failed (a full disk, an I/O error, a folder that cannot be
// written). The tools report it as a transient failure (exit 75): nothing was published, and any
// file that was there before is unchanged.
class OutputError : public IoError {
public:
    using IoError::IoError;
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
