// bench/bench_support.h: small helpers the benchmark programs share. Header-only; each benchmark
// is its own executable.
#pragma once

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

namespace pushpin::bench {

// CPU time consumed by the calling thread, in seconds (steadier than wall time on a shared machine).
inline double threadCpuSeconds() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// What one child process did, as runChild measured it.
struct ChildRun {
    double seconds = 0;  // wall time from fork to reap
    long peakKiB = 0;    // wait4 ru_maxrss: the child's peak resident set (largest of it and the children it reaped)
    int exitCode = -1;   // the child's exit code; -1 when it was killed by a signal or could not be started or reaped
};

// Runs the program at args[0] (a path, not searched in PATH) with args as its argv, waits for it
// and returns its wall time, peak resident memory and exit code. The child's stdout and stderr go to
// the given files (created or truncated; /dev/null by default) and its stdin comes from /dev/null.
// A program that cannot be executed exits with 127. Callable from any thread: between fork and exec
// the child makes only async-signal-safe calls, and each call reaps only its own child. Children run
// at the same time skew each other's times, so the benches run one at a time.
inline ChildRun runChild(const std::vector<std::string>& args, const std::filesystem::path& stdoutPath = "/dev/null",
                         const std::filesystem::path& stderrPath = "/dev/null") {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        const int out = ::open(stdoutPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err = ::open(stderrPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int in = ::open("/dev/null", O_RDONLY);
        if (out >= 0) dup2(out, 1);
        if (err >= 0) dup2(err, 2);
        if (in >= 0) dup2(in, 0);
        execv(argv[0], argv.data());
        _exit(127);
    }
    ChildRun r;
    if (pid < 0) return r;
    int status = 0;
    struct rusage ru {};
    pid_t reaped;
    do {
        reaped = wait4(pid, &status, 0, &ru);
    } while (reaped < 0 && errno == EINTR);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (reaped != pid) return r;
    r.peakKiB = ru.ru_maxrss;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

}  // namespace pushpin::bench
