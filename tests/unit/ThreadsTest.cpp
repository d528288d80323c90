#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rangefuse/parallel/Threads.h"

namespace rangefuse {
namespace {

int policyOfThisThread() {
  int policy = -1;
  sched_param param{};
  pthread_getschedparam(pthread_self(), &policy, &param);
  return policy;
}

#ifdef SCHED_IDLE
TEST(Threads, AnIdleWorkerLowersItsThreadAloneWhileItLives) {
  const int before = policyOfThisThread();
  int lowered = -1, after = -1;
  std::thread reader([&] {
    {
      const IdleWorker idle;
      lowered = policyOfThisThread();
    }
    after = policyOfThisThread();
  });
  reader.join();
  EXPECT_EQ(lowered, SCHED_IDLE);
  EXPECT_EQ(after, before);
  EXPECT_EQ(policyOfThisThread(), before);
}
#endif

// Open MPI's waits call sched_yield(): while a worker lives, the library's takes its place and
// sleeps, so that the waiting thread gets its core back as soon as it wakes.
TEST(Threads, AYieldWhileAnIdleWorkerLivesIsASleep) {
  using Clock = std::chrono::steady_clock;
  std::atomic<bool> started{false}, done{false};
  std::thread worker([&] {
    const IdleWorker idle;
    started = true;
    while (!done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const auto t0 = Clock::now();
  for (int k = 0; k < 20; ++k) EXPECT_EQ(sched_yield(), 0);
  const auto slept = Clock::now() - t0;
  done = true;
  worker.join();
  EXPECT_GE(slept, 20 * std::chrono::microseconds(50));  // nanosleep sleeps at least as asked
}

TEST(Threads, ParallelForCallsEveryIndexOnce) {
  std::vector<std::atomic<int>> calls(1000);
  parallelFor(calls.size(), 3, [&](size_t i) { ++calls[i]; });
  for (size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].load(), 1) << i;
}

TEST(Threads, ParallelForRethrowsTheLowestFailureAfterEveryCall) {
  std::atomic<int> done{0};
  try {
    parallelFor(100, 4, [&](size_t i) {
      ++done;
      if (i == 70 || i == 30) throw std::runtime_error("item " + std::to_string(i));
    });
    FAIL() << "nothing was thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 30");
  }
  EXPECT_EQ(done.load(), 100);
}

}  // namespace
}  // namespace rangefuse
