// parallel/WorkStealing.h: every item worked exactly once on one rank whatever the costs, a
// rank's own items worked from the front and given away from the back, batches as asked, and
// a failure on one rank that leaves no other rank waiting.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/WorkStealing.h"

namespace rangefuse {
namespace {

constexpr size_t kPerRank = 24;

/// Rank r's own items: [r * kPerRank, (r + 1) * kPerRank).
std::vector<size_t> ownItems(int r) {
  std::vector<size_t> items(kPerRank);
  for (size_t k = 0; k < kPerRank; ++k) items[k] = r * kPerRank + k;
  return items;
}

/// Every rank's worked list, in rank order.
std::vector<std::vector<size_t>> gathered(const std::vector<size_t>& worked) {
  std::vector<char> bytes;
  mpi::pack(bytes, worked.data(), worked.size());
  std::vector<std::vector<size_t>> all;
  for (const auto& part : mpi::allgatherBytes(bytes, MPI_COMM_WORLD)) {
    std::vector<size_t> items(part.size() / sizeof(size_t));
    size_t pos = 0;
    mpi::unpack(part, pos, items.data(), items.size());
    all.push_back(items);
  }
  return all;
}

/// Each item of [0, n) exactly once over all the lists.
void expectEachOnce(const std::vector<std::vector<size_t>>& all, size_t n) {
  std::vector<int> times(n, 0);
  for (const auto& list : all)
    for (size_t i : list) {
      ASSERT_LT(i, n);
      ++times[i];
    }
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(times[i], 1) << "item " << i;
}

TEST(WorkStealing, SlowRanksItemsMoveAndEachIsWorkedOnce) {
  const int me = mpi::rank(), n = mpi::size();
  // Rank 0's items take 20 ms each (about half a second in all); the others' take nothing.
  const auto work = [&](const std::vector<size_t>&) {
    if (me == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  };
  const auto all = gathered(mpi::forEachStealing(ownItems(me), 1, work, MPI_COMM_WORLD));
  expectEachOnce(all, kPerRank * n);
  // Rank 0 worked a prefix of its list, in order: the others took from its back.
  const std::vector<size_t> own = ownItems(0);
  ASSERT_LE(all[0].size(), own.size());
  EXPECT_TRUE(std::equal(all[0].begin(), all[0].end(), own.begin()));
  if (n > 1) {
    EXPECT_LT(all[0].size(), own.size()) << "nobody took any of rank 0's items";
  }
}

TEST(WorkStealing, BatchesHoldAtMostTheSizeAskedInListOrder) {
  const int me = mpi::rank(), n = mpi::size();
  size_t largest = 0;
  bool ordered = true;
  const auto work = [&](const std::vector<size_t>& batch) {
    largest = std::max(largest, batch.size());
    ordered = ordered && std::is_sorted(batch.begin(), batch.end());
    if (me == n - 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  };
  const auto all = gathered(mpi::forEachStealing(ownItems(me), 5, work, MPI_COMM_WORLD));
  expectEachOnce(all, kPerRank * n);
  EXPECT_LE(largest, 5u);
  EXPECT_GE(largest, 1u);
  EXPECT_TRUE(ordered);
}

TEST(WorkStealing, OneRankHoldingEverythingSharesIt) {
  const int me = mpi::rank(), n = mpi::size();
  std::vector<size_t> mine;
  if (me == 0)
    for (size_t i = 0; i < kPerRank * n; ++i) mine.push_back(i);
  const auto work = [](const std::vector<size_t>&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  };
  const auto all = gathered(mpi::forEachStealing(mine, 1, work, MPI_COMM_WORLD));
  expectEachOnce(all, kPerRank * n);
}

TEST(WorkStealing, NothingToDoAnywhereReturnsEmpty) {
  size_t calls = 0;
  const auto worked = mpi::forEachStealing(
      {}, 2, [&](const std::vector<size_t>&) { ++calls; }, MPI_COMM_WORLD);
  EXPECT_TRUE(worked.empty());
  EXPECT_EQ(calls, 0u);
}

TEST(WorkStealing, AFailureIsRethrownOnItsRankAndNoRankWaits) {
  const int me = mpi::rank(), n = mpi::size();
  const int failing = n - 1;
  const auto work = [&](const std::vector<size_t>& batch) {
    if (me == failing && batch.front() == ownItems(failing)[1])
      throw std::runtime_error("item cannot be read");
    std::this_thread::sleep_for(std::chrono::milliseconds(me == failing ? 10 : 1));
  };
  std::vector<size_t> worked;
  std::string caught;
  try {
    worked = mpi::forEachStealing(ownItems(me), 1, work, MPI_COMM_WORLD);
  } catch (const std::runtime_error& e) {
    caught = e.what();
  }
  EXPECT_EQ(caught, me == failing ? "item cannot be read" : "");
  // Every rank is back here: the agreement after the failure completes.
  EXPECT_FALSE(mpi::agree(caught.empty(), "", MPI_COMM_WORLD));
  const auto all = gathered(worked);
  std::vector<int> times(kPerRank * n, 0);
  for (const auto& list : all)
    for (size_t i : list) EXPECT_EQ(++times[i], 1) << "item " << i << " worked twice";
}

}  // namespace
}  // namespace rangefuse
