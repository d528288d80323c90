// A fit's sums against brute force: planeSums and correspondenceSums, which read a batch of
// control points' voxels before summing them, give the bits of sampling one point at a time
// and adding the bricks' sums in code order, on one rank and split over the ranks.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "SphereField.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/register/Correspondences.h"

namespace rangefuse {
namespace {

/// Control points about the test sphere, within and beyond the field's reach (some fall off
/// the lattice), with normals near the sphere's and a few facing away; every fifth weighs 0.
struct ControlSet {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> weights;
};

ControlSet controlSet(unsigned seed, size_t count) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> uniform(0, 1);
  ControlSet c;
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const double off = (uniform(rng) - 0.5) * 10;  // past the 3 voxels the field holds
    c.points.push_back(test::kCentre + (test::kRadius + off) * dir);
    Eigen::Vector3d n = dir + 0.4 * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    if (i % 7 == 0) n = -n;
    c.normals.push_back(n.normalized());
    c.weights.push_back(i % 5 == 0 ? 0.0 : 0.25 + uniform(rng));
  }
  return c;
}

CorrespondenceSettings settings(bool byImages) {
  CorrespondenceSettings s;
  s.maxDistance = 2.5;
  s.minCosine = 0.3;
  s.huber = 1;
  s.weightByImages = byImages;
  return s;
}

/// The sums of every point, one at a time, per brick, added in code order: what planeSums
/// must give (the store holds every brick).
PlaneSums planeSumsOneByOne(const BrickStore& store, const ControlSet& c,
                            const Eigen::Vector3d& centre, const CorrespondenceSettings& s) {
  std::map<uint64_t, PlaneSums> perBrick;
  for (size_t i = 0; i < c.points.size(); ++i) {
    FieldSample f;
    if (!(c.weights[i] > 0) || !sampleField(store, c.points[i], c.normals[i], s, f)) continue;
    const double r = std::abs(f.distance);
    const double huber = r > s.huber ? s.huber / r : 1.0;
    perBrick[store.code(f.brick)].add(c.points[i] - centre, f.f, f.distance, c.weights[i] * huber);
  }
  PlaneSums total;
  for (const auto& [code, sums] : perBrick) total += sums;
  return total;
}

/// The same for correspondenceSums.
RigidSums rigidSumsOneByOne(const BrickStore& store, const ControlSet& c,
                            const CorrespondenceSettings& s) {
  std::map<uint64_t, RigidSums> perBrick;
  const Eigen::Vector3d o = store.grid().origin;
  for (size_t i = 0; i < c.points.size(); ++i) {
    Correspondence q;
    if (!(c.weights[i] > 0) || !correspondence(store, c.points[i], c.normals[i], s, q)) continue;
    perBrick[store.code(q.brick)].add(c.points[i] - o, q.q - o, c.weights[i] * q.weight);
  }
  RigidSums total;
  for (const auto& [code, sums] : perBrick) total += sums;
  return total;
}

void expectSameBits(const PlaneSums& a, const PlaneSums& b) {
  EXPECT_EQ(a.A, b.A);
  EXPECT_EQ(a.b, b.b);
  EXPECT_EQ(a.w, b.w);
  EXPECT_EQ(a.wr2, b.wr2);
  EXPECT_EQ(a.wLever, b.wLever);
  EXPECT_EQ(a.count, b.count);
}

void expectSameBits(const RigidSums& a, const RigidSums& b) {
  EXPECT_EQ(a.w, b.w);
  EXPECT_EQ(a.wp, b.wp);
  EXPECT_EQ(a.wq, b.wq);
  EXPECT_EQ(a.wpq, b.wpq);
  EXPECT_EQ(a.wr2, b.wr2);
  EXPECT_EQ(a.count, b.count);
}

TEST(FieldSums, PlaneSumsAreTheOneByOneSumsOnAnyRankCount) {
  BrickStore whole(test::sphereLayout(1), 0);
  test::fillSphere(whole);
  BrickStore split(test::sphereLayout(mpi::size()), mpi::rank());
  test::fillSphere(split);
  for (unsigned seed : {1u, 2u, 3u}) {
    const ControlSet c = controlSet(seed, 5000);
    const Eigen::Vector3d centre(3, -2, 5);
    const PlaneSums expected = planeSumsOneByOne(whole, c, centre, settings(false));
    ASSERT_GT(expected.count, 1000);  // most points find the field, not all
    ASSERT_LT(expected.count, 4000);
    expectSameBits(
        planeSums(whole, c.points, c.normals, c.weights, centre, settings(false), MPI_COMM_SELF),
        expected);
    expectSameBits(
        planeSums(split, c.points, c.normals, c.weights, centre, settings(false), MPI_COMM_WORLD),
        expected);
  }
}

TEST(FieldSums, CorrespondenceSumsAreTheOneByOneSumsOnAnyRankCount) {
  BrickStore whole(test::sphereLayout(1), 0);
  test::fillSphere(whole);
  BrickStore split(test::sphereLayout(mpi::size()), mpi::rank());
  test::fillSphere(split);
  for (bool byImages : {false, true}) {
    const ControlSet c = controlSet(7, 5000);
    const RigidSums expected = rigidSumsOneByOne(whole, c, settings(byImages));
    ASSERT_GT(expected.count, 1000);
    for (const RigidSums& got : {correspondenceSums(whole, c.points, c.normals, c.weights,
                                                    settings(byImages), MPI_COMM_SELF),
                                 correspondenceSums(split, c.points, c.normals, c.weights,
                                                    settings(byImages), MPI_COMM_WORLD)})
      expectSameBits(got, expected);
  }
}

}  // namespace
}  // namespace rangefuse
