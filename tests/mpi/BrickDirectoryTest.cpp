// The distributed brick directory against a whole list planned on one rank: the same bricks,
// owners and cuts for any number of ranks and any spread of the work, and no rank holding a
// brick it neither owns nor borders.
#include <gtest/gtest.h>

#include <random>

#include "DirectoryExpectations.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/volume/BrickPlanning.h"

using namespace rangefuse;
using test::expectDirectory;

namespace {

VoxelGrid testGrid() {
  VoxelGrid g;
  g.voxel = 0.5;
  g.brick = 4;
  return g;
}

/// The work every rank adds: clusters of bricks (a surface's runs of neighbours), the same
/// brick often named by several ranks; the entries fall on the ranks round robin, or all on
/// the last rank (`allOnLast`).
std::vector<BrickWork> workOfRanks(int ranks, unsigned seed, bool allOnLast) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coord(0, 40), step(-1, 1), amount(1, 50);
  std::vector<BrickWork> work(ranks);
  int entry = 0;
  for (int cluster = 0; cluster < 12; ++cluster) {
    BrickCoord b(coord(rng), coord(rng), coord(rng));
    for (int k = 0; k < 60; ++k, ++entry) {
      b = (b + BrickCoord(step(rng), step(rng), step(rng))).cwiseMax(0);
      work[allOnLast ? ranks - 1 : entry % ranks][mortonEncode(b)] += amount(rng);
    }
  }
  return work;
}

/// The whole list: every rank's work summed and cut on one rank.
BrickLayout wholeList(const std::vector<BrickWork>& parts, int ranks) {
  BrickWork sum;
  for (const BrickWork& p : parts)
    for (const auto& [code, w] : p) sum[code] += w;
  return layoutFromWork(sum, testGrid(), ranks);
}

/// True when brick `code` is one of `me`'s in `whole` or borders one.
bool ownsOrBorders(const BrickLayout& whole, uint64_t code, int me) {
  const int64_t at = whole.find(code);
  if (at >= 0 && whole.ownerOf(static_cast<size_t>(at)) == me) return true;
  for (uint64_t n : neighbourCodes(code)) {
    const int64_t nb = whole.find(n);
    if (nb >= 0 && whole.ownerOf(static_cast<size_t>(nb)) == me) return true;
  }
  return false;
}

}  // namespace

TEST(BrickDirectory, ReducedWorkCutsAsTheWholeListAndHoldsOnlyOwnAndBorderingBricks) {
  const int ranks = mpi::size(), me = mpi::rank();
  for (const bool allOnLast : {false, true}) {
    const std::vector<BrickWork> parts = workOfRanks(ranks, 7, allOnLast);
    const BrickLayout whole = wholeList(parts, ranks);
    const BrickLayout got = reduceBrickWork(parts[me], testGrid(), UINT64_MAX, MPI_COMM_WORLD);
    expectDirectory(got, whole, me);
    // A rank's directory never holds a brick it neither owns nor borders, and knows every
    // brick bordering its own.
    for (uint64_t code : got.codes) EXPECT_TRUE(ownsOrBorders(whole, code, me)) << code;
    for (size_t i = whole.rankStart[me]; i < whole.rankStart[me + 1]; ++i)
      for (uint64_t n : neighbourCodes(whole.codes[i]))
        EXPECT_EQ(got.find(n) >= 0, whole.find(n) >= 0) << n;
    // Every code's owner, held or not, is the whole list's.
    for (size_t i = 0; i < whole.codes.size(); ++i)
      EXPECT_EQ(got.ownerOfCode(whole.codes[i]), whole.ownerOf(i));
  }
}

TEST(BrickDirectory, OwnersOfCodesItDoesNotHoldComeFromTheRanges) {
  const int ranks = mpi::size(), me = mpi::rank();
  const std::vector<BrickWork> parts = workOfRanks(ranks, 11, false);
  const BrickLayout whole = wholeList(parts, ranks);
  const BrickLayout got = reduceBrickWork(parts[me], testGrid(), UINT64_MAX, MPI_COMM_WORLD);
  for (size_t i = 0; i < whole.codes.size(); ++i) {
    const int owner = whole.ownerOf(i);
    // A held brick or one of another rank: its owner. None of this rank's is missing.
    EXPECT_EQ(got.mayOwn(whole.codes[i], me), owner);
  }
  // A code in this rank's range that no rank planned does not exist: nobody to send it to.
  for (uint64_t code = got.firstCodes[me]; code < got.firstCodes[me + 1] && code < 5000; ++code) {
    if (whole.find(code) >= 0) continue;
    EXPECT_EQ(got.mayOwn(code, me), -1) << code;
  }
}

TEST(BrickDirectory, TooManyVoxelsAreRefusedOnEveryRank) {
  const int ranks = mpi::size(), me = mpi::rank();
  const std::vector<BrickWork> parts = workOfRanks(ranks, 5, false);
  const uint64_t bricks = wholeList(parts, ranks).codes.size();
  // One brick fewer than the plan needs: every rank throws, none waits in a collective.
  EXPECT_THROW(reduceBrickWork(parts[me], testGrid(), (bricks - 1) * 64, MPI_COMM_WORLD),
               InputError);
  EXPECT_NO_THROW(reduceBrickWork(parts[me], testGrid(), bricks * 64, MPI_COMM_WORLD));
}
