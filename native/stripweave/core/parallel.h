// Running independent pieces of work on the cores this process may use.
//
// usable_cores() -> the cores in the process's affinity mask (so that a run
//   pinned to one core, as the benchmarks are, works on one thread rather
//   than time-slicing two).
// parallel_for(n, body, max_threads) -> body(i) for i in [0, n), on up to
//   min(max_threads, usable_cores()) threads, each taking the next index.
//   The bodies must be independent (each writes only its own slots), so the
//   result does not depend on the thread count or the scheduling. The first
//   exception a body throws is rethrown after all threads have finished.
//   When the caller holds a FloatingPointGuard (core/fp_guard.h), so does
//   every helper thread: a SIGFPE there is the same InputError, rethrown.
// parallel_for_workers(n, body, max_threads) -> the same, body(i, worker).
#pragma once

#include "stripweave/core/types.h"

#include <functional>

namespace stripweave {

unsigned usable_cores();

void parallel_for(Index n, const std::function<void(Index)>& body, unsigned max_threads = 2);

// The threads parallel_for(n, ..., max_threads) runs on, and the same loop
// telling each body which of them (0 .. workers - 1) runs it: for work that
// needs per-thread state (a B-rep projector's caches), made beforehand.
unsigned parallel_workers(Index n, unsigned max_threads = 2);
void parallel_for_workers(Index n, const std::function<void(Index, unsigned)>& body, unsigned max_threads = 2);

}  // namespace stripweave
