// Sums across ranks that do not depend on the rank count, and the joint equations built from
// them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <random>

#include "rangefuse/parallel/FixedPointSum.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/register/JointSolve.h"

using namespace rangefuse;

namespace {

std::vector<double> randomTerms(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> terms(n);
  for (double& t : terms) t = u(rng) * std::pow(10.0, static_cast<int>(rng() % 7) - 3);
  return terms;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST(FixedPointSum, SameBitsWhateverTheOrderOfTermsAndTheRanks) {
  const std::vector<double> terms = randomTerms(5000, 3);
  double bound = 0;
  for (double t : terms) bound += std::abs(t);
  // All terms on one rank, in order ...
  FixedPointSum alone(2, bound);
  for (size_t k = 0; k < terms.size(); ++k) alone.add(k % 2, terms[k]);
  const std::vector<double> expected = alone.reduce(MPI_COMM_SELF);
  // ... and each rank's share, backwards.
  const int me = mpi::rank(), ranks = mpi::size();
  FixedPointSum shared(2, bound);
  for (size_t k = terms.size(); k-- > 0;)
    if (static_cast<int>(k % ranks) == me) shared.add(k % 2, terms[k]);
  EXPECT_TRUE(sameBits(shared.reduce(MPI_COMM_WORLD), expected));
  long double exact = 0;
  for (size_t k = 0; k < terms.size(); k += 2) exact += terms[k];
  EXPECT_NEAR(expected[0], static_cast<double>(exact), 1e-12 * bound);
}

TEST(JointEquations, ReducedOnAnyRanksAreTheOneRankSumsBitForBit) {
  // Voxels dealt to the ranks in turn; the reduced equations equal one rank's with all of
  // them, bit for bit, and the plain double sums to the fixed point's precision.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), w(0.1, 1);
  const MotionFrame frame{Eigen::Vector3d::Zero(), 2.0};
  std::vector<std::vector<VoxelShare>> all(300), mine;
  for (size_t v = 0; v < all.size(); ++v) {
    const Eigen::Vector3d f = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    for (uint32_t s = 0; s < 5; ++s) {
      if (rng() % 2 && all[v].size() >= 2) continue;
      VoxelShare share;
      share.scan = s;
      share.add(Eigen::Vector3d(u(rng), u(rng), u(rng)), f, 0.5 * u(rng), w(rng), frame);
      all[v].push_back(share);
    }
    if (static_cast<int>(v % mpi::size()) == mpi::rank()) mine.push_back(all[v]);
  }
  const JointEquations one = reduceJointEquations(all, 5, 1.0, MPI_COMM_SELF);
  const JointEquations many = reduceJointEquations(mine, 5, 1.0, MPI_COMM_WORLD);
  const JointEquations plain = jointEquations(all, 5);
  ASSERT_EQ(one.blocks.size(), many.blocks.size());
  ASSERT_EQ(one.blocks.size(), plain.blocks.size());
  for (const auto& [key, h] : one.blocks) {
    EXPECT_EQ(std::memcmp(h.data(), many.blocks.at(key).data(), sizeof(Matrix6d)), 0);
    EXPECT_LT((h - plain.blocks.at(key)).norm(), 1e-12 * (1 + plain.blocks.at(key).norm()));
  }
  for (size_t s = 0; s < 5; ++s) {
    EXPECT_EQ(std::memcmp(one.gradient[s].data(), many.gradient[s].data(), sizeof(Vector6d)), 0);
    EXPECT_LT((one.gradient[s] - plain.gradient[s]).norm(), 1e-12);
    EXPECT_EQ(one.points[s], many.points[s]);
    EXPECT_EQ(one.points[s], plain.points[s]);
    EXPECT_NEAR(one.rms(s), plain.rms(s), 1e-12);
  }
  // Overlap per pair, counted by brute force: each share here holds one control point, so a
  // pair's overlap is twice the voxels both scans reached.
  std::map<std::pair<uint32_t, uint32_t>, uint64_t> expected;
  for (const auto& shares : all)
    for (const VoxelShare& a : shares)
      for (const VoxelShare& b : shares)
        if (a.scan < b.scan) expected[{a.scan, b.scan}] += 2;
  EXPECT_EQ(one.pairPoints, expected);
  EXPECT_EQ(many.pairPoints, expected);
  EXPECT_EQ(plain.pairPoints, expected);
}
