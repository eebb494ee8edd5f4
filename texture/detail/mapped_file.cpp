// texture/detail/mapped_file.cpp: mmap of BOT files and the SIGBUS guard around copies out of them.
//
// Why a guard: reading a mapped page that lies past the current end of its file raises SIGBUS,
// which kills the process by default. The cache checks the file's size when it maps it, but a
// file can still be truncated in place while mapped (`cp new.bot old.bot` does that; makebot's
// write-to-temporary-and-rename does not, since the mapping keeps the old inode). So the only
// instruction that touches mapped bytes is one memcpy, bracketed by a per-thread guard: a SIGBUS
// whose address lies inside the guarded range jumps back to copyFromMapping, which reports
// failure; the caller then raises an ordinary error for that page. Nothing with a destructor lives
// between the sigsetjmp and the memcpy, so the jump skips no cleanup.
#include "texture/detail/mapped_file.h"

#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <sys/mman.h>

#include <atomic>
#include <cstring>
#include <mutex>

namespace pushpin::texture::detail {
namespace {

// Trivially constructible, so the signal handler reads it without any lazy TLS initialisation.
struct FaultGuard {
    sigjmp_buf* env;
    const uint8_t* begin;
    const uint8_t* end;
};
thread_local FaultGuard t_guard;

struct sigaction g_previous;
std::once_flag g_installed;

void onSigbus(int sig, siginfo_t* info, void* context) {
    FaultGuard& g = t_guard;
    const auto* addr = static_cast<const uint8_t*>(info->si_addr);
    if (g.env && addr >= g.begin && addr < g.end) {
        sigjmp_buf* env = g.env;
        g.env = nullptr;
        // The jump target did not save the signal mask, so make sure SIGBUS is not left blocked
        // (SA_NODEFER already sees to that, unless another handler, a sanitizer's, runs ours).
        sigset_t bus;
        sigemptyset(&bus);
        sigaddset(&bus, SIGBUS);
        pthread_sigmask(SIG_UNBLOCK, &bus, nullptr);
        siglongjmp(*env, 1);
    }
    // Not a guarded copy: behave as if this handler were not installed.
    if (g_previous.sa_flags & SA_SIGINFO) {
        if (g_previous.sa_sigaction) {
            g_previous.sa_sigaction(sig, info, context);
            return;
        }
    } else if (g_previous.sa_handler != SIG_DFL && g_previous.sa_handler != SIG_IGN) {
        g_previous.sa_handler(sig);
        return;
    }
    // Default action. A fault re-executes the faulting access on return and now dies of it; a
    // SIGBUS sent by kill() is raised again.
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, nullptr);
    if (info->si_code <= 0) raise(sig);
}

void installHandler() {
    struct sigaction sa {};
    sa.sa_sigaction = onSigbus;
    sigemptyset(&sa.sa_mask);
    // SA_NODEFER: the handler leaves by siglongjmp to a sigsetjmp that did not save the signal
    // mask (saving it costs a system call per copy), so SIGBUS must not stay blocked afterwards.
    sa.sa_flags = SA_SIGINFO | SA_NODEFER;
    sigaction(SIGBUS, &sa, &g_previous);
}

}  // namespace

const uint8_t* mapFile(int fd, size_t byteCount) {
    if (byteCount == 0) return nullptr;
    std::call_once(g_installed, installHandler);
    void* p = ::mmap(nullptr, byteCount, PROT_READ, MAP_SHARED, fd, 0);
    return p == MAP_FAILED ? nullptr : static_cast<const uint8_t*>(p);
}

void unmapFile(const uint8_t* bytes, size_t byteCount) {
    if (bytes) ::munmap(const_cast<uint8_t*>(bytes), byteCount);
}

bool copyFromMapping(void* dst, const uint8_t* src, size_t n) noexcept {
    sigjmp_buf env;
    FaultGuard& g = t_guard;
    if (sigsetjmp(env, 0) != 0) return false;  // the handler cleared the guard
    g.begin = src;
    g.end = src + n;
    std::atomic_signal_fence(std::memory_order_seq_cst);
    g.env = &env;
    std::atomic_signal_fence(std::memory_order_seq_cst);
    std::memcpy(dst, src, n);
    std::atomic_signal_fence(std::memory_order_seq_cst);
    g.env = nullptr;
    return true;
}

}  // namespace pushpin::texture::detail
