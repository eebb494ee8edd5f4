// bench/bench_support.h: small helpers the benchmark programs share. Header-only; each benchmark
// is its own executable.
#pragma once

#include <ctime>

namespace pushpin::bench {

// CPU time consumed by the calling thread, in seconds (steadier than wall time on a shared machine).
inline double threadCpuSeconds() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace pushpin::bench
