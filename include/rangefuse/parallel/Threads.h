// Threads inside a rank: the CPUs a rank may use besides its MPI peers on the same node. Only
// the main thread calls MPI; worker threads read files and compute.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace rangefuse {

/// Collective: the threads each rank of `comm` should use: the CPUs this process may run on,
/// shared among the ranks on its node (at least 1).
int threadsPerRank(MPI_Comm comm);

/// While one lives, the thread that made it runs only on cores no other thread wants (Linux's
/// SCHED_IDLE; elsewhere, or when refused, it keeps its priority). For work done ahead of need,
/// such as preparing the next depth frame: it then fills the time a rank waits for its peers
/// instead of sharing the core with the rank's own step, which its peers wait for in turn.
/// MPI must yield while it waits (`mpi_yield_when_idle`, set by mpi::start) or the worker is
/// starved until its result is asked for. While any worker lives, that yield is a short sleep
/// (decision 56): a yielding thread gets its core back from an idle-priority one only at the
/// scheduler's next tick, and a sleeping one as soon as it wakes.
class IdleWorker {
 public:
  IdleWorker();
  ~IdleWorker();
  IdleWorker(const IdleWorker&) = delete;
  IdleWorker& operator=(const IdleWorker&) = delete;

 private:
  int policy_ = -1;  ///< the thread's policy before, restored after (-1: unchanged)
};

/// Calls fn(i) for every i in [0, n) on up to `threads` threads (the calling one among them).
/// Every call runs; if any threw, the exception of the lowest i is rethrown.
template <class Fn>
void parallelFor(size_t n, int threads, Fn&& fn) {
  std::atomic<size_t> next{0};
  std::mutex mutex;
  size_t failedAt = n;
  std::exception_ptr error;
  auto work = [&] {
    for (size_t i; (i = next++) < n;) {
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (i < failedAt) failedAt = i, error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads && static_cast<size_t>(t) < n; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

/// Calls fn(batch) for consecutive runs of up to `size` of `items`, in order: work shared by
/// `size` threads a batch at a time, so that only one batch of results is held at once.
template <class T, class Fn>
void forEachBatch(const std::vector<T>& items, size_t size, Fn&& fn) {
  size = std::max<size_t>(1, size);
  for (size_t first = 0; first < items.size(); first += size)
    fn(std::vector<T>(items.begin() + first, items.begin() + std::min(items.size(), first + size)));
}

}  // namespace rangefuse
