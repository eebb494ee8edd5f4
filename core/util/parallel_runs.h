// core/util/parallel_runs.h: a loop over [0, n) cut into fixed runs of consecutive indices, run on
// the threads of the caller's task arena.
// Determinism: the runs depend only on n and the run length, never on the thread count, so a body
// that writes only what its run owns (and results joined in run order) gives the same bits on any
// number of threads.
// Isolated: a thread waiting for the runs takes no other work of its caller's (a tile, say), which
// could otherwise wait on something the caller holds.
#pragma once

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstddef>

namespace pushpin::util {

// Calls body(r, lo, hi) for every run r, covering [lo, hi) = [r·run, min(n, (r + 1)·run)).
template <class Body>
void forEachRun(size_t n, size_t run, Body&& body) {
    const size_t runs = (n + run - 1) / run;
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(size_t(0), runs, [&](size_t r) { body(r, r * run, std::min(n, (r + 1) * run)); });
    });
}

// The number of runs forEachRun makes of n indices.
constexpr size_t runCount(size_t n, size_t run) { return (n + run - 1) / run; }

}  // namespace pushpin::util
