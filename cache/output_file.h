// cache/output_file.h: files that appear whole or not at all. An OutputFile is written under a
// private temporary name in its final folder and published by one rename after every byte is on
// disk; a failure at any step removes the temporary file and leaves whatever the final path held
// before untouched. Temporary names are random and created exclusively, never through a link that
// someone else planted, and SIGINT, SIGTERM and exit() remove the ones still open.
// Thread safety: different OutputFile objects may be used from different threads at once; one
// object is not thread-safe. installTemporaryFileCleanup() may be called from any thread.
// Memory: owns a file descriptor and two paths; charges nothing to the MemoryBudget.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace pushpin::cache {

// Installs, once per process (later calls do nothing), SIGINT and SIGTERM handlers that unlink
// every temporary name registered with TemporaryName (OutputFile registers its own) and then end
// the process with exit status 128 + signal number (130 after SIGINT, 143 after SIGTERM), and an
// exit() hook that unlinks them too, so a library that ends the process leaves nothing behind.
void installTemporaryFileCleanup();

// Registers `path` for removal by the handlers above for the object's lifetime; the destructor
// only unregisters (removing the file is the owner's job). Registration copies the path into a
// fixed table so the signal handler needs no allocation; a path longer than the table holds, or a
// full table (64 names at once), is simply not registered. Not copyable.
class TemporaryName {
public:
    explicit TemporaryName(const std::filesystem::path& path);
    ~TemporaryName();
    TemporaryName(const TemporaryName&) = delete;
    TemporaryName& operator=(const TemporaryName&) = delete;
    bool registered() const { return m_slot >= 0; }

private:
    int m_slot = -1;
};

// A random name for a temporary file beside `finalPath`: ".<file name>.<16 hex digits>.tmp" in the
// same folder (the file name part shortened so the result stays a valid name). The digits come
// from the kernel's random source, so names differ between processes, containers and hosts that
// share the folder.
std::filesystem::path temporaryPathFor(const std::filesystem::path& finalPath);

class OutputFile {
public:
    // Creates the temporary file beside `finalPath` with O_CREAT|O_EXCL|O_NOFOLLOW, mode 0644 less
    // the umask, retrying with a new random name if one exists. The final folder must exist.
    // Throws OutputError naming the final path, the temporary path and strerror.
    explicit OutputFile(const std::filesystem::path& finalPath);
    // The same with the temporary names drawn from `nameFor(finalPath)` instead of
    // temporaryPathFor (tests use it to aim at names they planted).
    using NameSource = std::function<std::filesystem::path(const std::filesystem::path&)>;
    OutputFile(const std::filesystem::path& finalPath, const NameSource& nameFor);
    // Removes the temporary file unless commit() succeeded.
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    const std::filesystem::path& path() const { return m_final; }
    const std::filesystem::path& temporaryPath() const { return m_temp; }
    int fd() const { return m_fd; }
    uint64_t bytesWritten() const { return m_bytes; }

    // Appends `size` bytes, retrying short writes and EINTR. Throws OutputError (ENOSPC, EIO, EFBIG…).
    void write(const void* data, size_t size);
    // Copies everything readable from `sourceFd` from offset 0 (pread; the source offset is not
    // used). Throws OutputError on a write failure and IoError naming `sourceName` on a read failure.
    void copyFrom(int sourceFd, const std::string& sourceName);
    // fsync, close, rename onto the final path, fsync of the folder. Every step is checked; on
    // failure the temporary file is removed, the final path keeps what it had, and OutputError is
    // thrown. Call at most once.
    void commit();

private:
    void discard() noexcept;

    std::filesystem::path m_final;
    std::filesystem::path m_temp;
    int m_fd = -1;
    uint64_t m_bytes = 0;
    bool m_committed = false;
    std::unique_ptr<TemporaryName> m_name;  // registered while the temporary file exists
};

}  // namespace pushpin::cache
