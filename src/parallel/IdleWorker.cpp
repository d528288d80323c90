// Idle-priority workers, and how the rank's main thread waits while one runs.
#include <pthread.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <ctime>

#include "rangefuse/parallel/Threads.h"

namespace rangefuse {
namespace {

/// The idle-priority workers alive in this process.
std::atomic<int> workers{0};

/// How long a waiting thread sleeps while a worker runs: about the cost of a wake-up, so that
/// a rank answers its peers within tens of microseconds instead of a scheduler tick (4 ms at
/// Debian's 250 Hz), and the worker keeps most of the core.
constexpr long kWaitNanoseconds = 50'000;

}  // namespace

IdleWorker::IdleWorker() {
#ifdef SCHED_IDLE
  sched_param before{};
  int policy = 0;
  const sched_param none{};
  if (pthread_getschedparam(pthread_self(), &policy, &before) == 0 &&
      pthread_setschedparam(pthread_self(), SCHED_IDLE, &none) == 0)
    policy_ = policy;
#endif
  ++workers;
}

IdleWorker::~IdleWorker() {
  --workers;
  if (policy_ < 0) return;
  const sched_param normal{};
  pthread_setschedparam(pthread_self(), policy_, &normal);
}

}  // namespace rangefuse

/// Open MPI, told to yield while it waits, calls sched_yield() each time it finds nothing to
/// do. A yielding thread stays runnable, so the scheduler does not preempt an idle-priority
/// worker for it until its next tick: a rank that its peer's message has reached then waits up
/// to a tick before it sees it, and a tracked frame's fits and adds meet their peers about 20
/// times a frame (the kitchen's dev frames: fits 6.2 s a rank with the yield, 3.7 s with the
/// sleep and the sums passed along the ranks, decision 56). A thread that
/// wakes from a sleep preempts an idle-priority one at once. So while a worker runs, a yield
/// here is a short sleep; otherwise it is the system's yield. Defined in the library, this
/// takes the place of the C library's for the whole process (the Python module, loaded with
/// its symbols local, keeps the system's).
extern "C" int sched_yield() noexcept {
  if (rangefuse::workers.load(std::memory_order_relaxed) > 0) {
    const timespec pause{0, rangefuse::kWaitNanoseconds};
    nanosleep(&pause, nullptr);
    return 0;
  }
  return static_cast<int>(syscall(SYS_sched_yield));
}
