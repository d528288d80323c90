#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
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
TEST(Threads, RunOnlyWhenIdleLowersTheCallingThreadAlone) {
  const int before = policyOfThisThread();
  int lowered = -1;
  std::thread reader([&] {
    runOnlyWhenIdle();
    lowered = policyOfThisThread();
  });
  reader.join();
  EXPECT_EQ(lowered, SCHED_IDLE);
  EXPECT_EQ(policyOfThisThread(), before);
}
#endif

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
