// cache/error.h: the one small exception hierarchy every pushpin library throws at load and IO
// boundaries. Inner loops never throw; they return values (see STYLE.md "Errors").
#pragma once

#include <cstdint>
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

// A render needs more memory than its cap (-mm, or $SLURM_MEM_PER_NODE) allows, found before the
// large allocations were made. The message names what was needed and the cap; the tools exit 33
// (farm.md §6: "over its own memory cap"), which lets a scheduler retry with more memory.
class MemoryCapError : public Error {
public:
    MemoryCapError(const std::string& message, uint64_t neededBytes, uint64_t capBytes);
    uint64_t neededBytes() const { return m_neededBytes; }
    uint64_t capBytes() const { return m_capBytes; }

private:
    uint64_t m_neededBytes = 0;
    uint64_t m_capBytes = 0;
};

}  // namespace pushpin
