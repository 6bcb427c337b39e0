// See parallel.h.
#include "stripweave/core/parallel.h"

#include "stripweave/core/fp_guard.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace stripweave {

unsigned usable_cores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return static_cast<unsigned>(CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

unsigned parallel_workers(Index n, unsigned max_threads) {
  return std::max(1u, std::min<unsigned>({max_threads, usable_cores(), static_cast<unsigned>(std::max<Index>(n, 1))}));
}

void parallel_for_workers(Index n, const std::function<void(Index, unsigned)>& body, unsigned max_threads) {
  const unsigned threads = parallel_workers(n, max_threads);
  if (threads <= 1) {
    for (Index i = 0; i < n; ++i) body(i, 0);
    return;
  }
  std::atomic<Index> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  // A caller's floating-point guard holds on the helper threads too: their
  // SIGFPE becomes the same InputError, rethrown below.
  const bool guarded = FloatingPointGuard::active();
  auto work = [&](unsigned worker) {
    std::optional<FloatingPointGuard> guard;
    if (guarded && worker > 0) guard.emplace();
    for (Index i = next++; i < n; i = next++) {
      try {
        body(i, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // the others stop at their next index
      }
    }
  };
  std::vector<std::thread> helpers;
  for (unsigned t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (std::thread& h : helpers) h.join();
  if (error) std::rethrow_exception(error);
}

void parallel_for(Index n, const std::function<void(Index)>& body, unsigned max_threads) {
  parallel_for_workers(n, [&](Index i, unsigned) { body(i); }, max_threads);
}

}  // namespace stripweave
