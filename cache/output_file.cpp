// Exclusive temporary files, the checked publish sequence (write, fsync, close, rename, fsync of
// the folder) and the async-signal-safe table of names that SIGINT, SIGTERM and exit() remove.
#include "cache/output_file.h"

#include "cache/error.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace pushpin::cache {

namespace {

namespace fs = std::filesystem;

// The table the signal handler walks. A handler may only make async-signal-safe calls, so it can
// neither lock nor allocate: each slot is a fixed buffer whose state word says whether the path in
// it is complete (Live) and may be unlinked. A slot is claimed Free → Filling with a CAS, filled,
// then published Live with a release store; the handler reads the state with acquire order.
constexpr int kSlots = 64;
constexpr size_t kPathBytes = 4096;
enum SlotState : int { Free = 0, Filling = 1, Live = 2 };
struct Slot {
    std::atomic<int> state{Free};
    char path[kPathBytes];
};
Slot g_slots[kSlots];

void unlinkRegistered() noexcept {
    for (Slot& s : g_slots)
        if (s.state.load(std::memory_order_acquire) == Live) ::unlink(s.path);
}

extern "C" void onTerminatingSignal(int sig) {
    unlinkRegistered();
    ::_exit(128 + sig);
}

extern "C" void onExit() { unlinkRegistered(); }

std::once_flag g_installOnce;

std::string hex64(uint64_t v) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

uint64_t randomWord() {
    uint64_t v = 0;
    ssize_t got = -1;
    do got = ::getrandom(&v, sizeof v, 0);
    while (got < 0 && errno == EINTR);
    if (got == sizeof v) return v;
    // No kernel random source (a very old kernel): time and address bits still differ between
    // processes; O_EXCL keeps a collision from ever sharing a file.
    static std::atomic<uint64_t> counter{0};
    uint64_t z = uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) ^
                 (uint64_t(::getpid()) << 32) ^ reinterpret_cast<uintptr_t>(&v) ^ counter.fetch_add(1) * 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

}  // namespace

void installTemporaryFileCleanup() {
    std::call_once(g_installOnce, [] {
        struct sigaction sa;
        std::memset(&sa, 0, sizeof sa);
        sa.sa_handler = onTerminatingSignal;
        sigemptyset(&sa.sa_mask);
        // Block the other terminating signal while one is handled, so the table is walked once.
        sigaddset(&sa.sa_mask, SIGINT);
        sigaddset(&sa.sa_mask, SIGTERM);
        ::sigaction(SIGINT, &sa, nullptr);
        ::sigaction(SIGTERM, &sa, nullptr);
        std::atexit(onExit);
    });
}

TemporaryName::TemporaryName(const fs::path& path) {
    const std::string& text = path.native();
    if (text.empty() || text.size() >= kPathBytes) return;
    for (int i = 0; i < kSlots; ++i) {
        int expected = Free;
        if (g_slots[i].state.compare_exchange_strong(expected, Filling, std::memory_order_acquire)) {
            std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
            g_slots[i].state.store(Live, std::memory_order_release);
            m_slot = i;
            return;
        }
    }
}

TemporaryName::~TemporaryName() {
    if (m_slot >= 0) g_slots[m_slot].state.store(Free, std::memory_order_release);
}

fs::path temporaryPathFor(const fs::path& finalPath) {
    // NAME_MAX is 255 on the file systems farms use; keep the visible part of the name well
    // under it after the dot, the random digits and the suffix are added.
    std::string name = finalPath.filename().string();
    constexpr size_t kMaxNameBytes = 200;
    if (name.size() > kMaxNameBytes) name.resize(kMaxNameBytes);
    const fs::path dir = finalPath.has_parent_path() ? finalPath.parent_path() : fs::path(".");
    return dir / ("." + name + "." + hex64(randomWord()) + ".tmp");
}

OutputFile::OutputFile(const fs::path& finalPath) : OutputFile(finalPath, temporaryPathFor) {}

OutputFile::OutputFile(const fs::path& finalPath, const NameSource& nameFor) : m_final(finalPath) {
    installTemporaryFileCleanup();
    // A name that exists already is someone else's (or a planted link): O_EXCL refuses it, and
    // O_NOFOLLOW refuses a link even in the final component. Another random name is tried.
    for (int attempt = 0; attempt < 16; ++attempt) {
        fs::path temp = nameFor(finalPath);
        // Registered before the file exists, so a signal between open() and registration cannot
        // leave it behind. Should the open fail, the handler could at worst unlink a file of the
        // same 64 random bits, which the O_EXCL refusal says someone else holds: unregister first.
        auto name = std::make_unique<TemporaryName>(temp);
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) {
            m_fd = fd;
            m_temp = std::move(temp);
            m_name = std::move(name);
            return;
        }
        const int e = errno;
        name.reset();
        if (e != EEXIST) throw OutputError(finalPath, "cannot create temporary file " + temp.string(), e);
    }
    throw OutputError(finalPath, "cannot create a temporary file: every random name tried exists", EEXIST);
}

OutputFile::~OutputFile() {
    if (!m_committed) discard();
}

void OutputFile::discard() noexcept {
    if (m_fd >= 0) ::close(m_fd);
    m_fd = -1;
    if (!m_temp.empty()) ::unlink(m_temp.c_str());
    m_name.reset();
}

void OutputFile::write(const void* data, size_t size) {
    if (m_fd < 0) throw OutputError(m_final, "write after the file was closed");
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(m_fd, p, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw OutputError(m_final, "cannot write " + m_temp.string(), errno);
        }
        if (n == 0) throw OutputError(m_final, "cannot write " + m_temp.string(), EIO);
        p += n;
        size -= size_t(n);
        m_bytes += uint64_t(n);
    }
}

void OutputFile::copyFrom(int sourceFd, const std::string& sourceName) {
    std::vector<char> buffer(size_t(1) << 20);
    off_t offset = 0;
    for (;;) {
        const ssize_t n = ::pread(sourceFd, buffer.data(), buffer.size(), offset);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw IoError(sourceName, "cannot read", errno);
        }
        if (n == 0) return;
        write(buffer.data(), size_t(n));
        offset += n;
    }
}

void OutputFile::commit() {
    if (m_committed || m_fd < 0) throw OutputError(m_final, "commit of a file that is not open");
    // fsync before rename: after a crash the final name holds either the old file or all of the
    // new one, never a name pointing at blocks that were not written.
    if (::fsync(m_fd) != 0) {
        const int e = errno;
        discard();
        throw OutputError(m_final, "cannot flush " + m_temp.string() + " to disk", e);
    }
    const int fd = m_fd;
    m_fd = -1;
    if (::close(fd) != 0) {
        const int e = errno;
        discard();
        throw OutputError(m_final, "cannot close " + m_temp.string(), e);
    }
    if (::rename(m_temp.c_str(), m_final.c_str()) != 0) {
        const int e = errno;
        discard();
        throw OutputError(m_final, "cannot rename " + m_temp.string() + " into place", e);
    }
    m_committed = true;
    m_name.reset();
    // The rename is durable once the folder is: best effort, since some file systems refuse
    // fsync on a directory (EINVAL) and the file itself is complete either way.
    const fs::path dir = m_final.has_parent_path() ? m_final.parent_path() : fs::path(".");
    const int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        (void)::fsync(dirFd);
        ::close(dirFd);
    }
}

}  // namespace pushpin::cache
