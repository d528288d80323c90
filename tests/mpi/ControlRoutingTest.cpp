// Routed control points against brute force: whatever the pose, every rank holds each control
// point whose nearest voxel it owns, in scan order, though only one rank holds the scan.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "SphereField.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/register/ControlRouting.h"

namespace rangefuse {
namespace {

/// Points on the test sphere (every third one with no confidence), in their own frame.
PrismScan sphereScan() {
  PrismScan scan;
  ScanSurface& s = scan.surface;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 80; ++j) {
      const double theta = M_PI * (i + 0.5) / 40, phi = 2 * M_PI * j / 80;
      const Eigen::Vector3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
      s.points.push_back(test::kCentre + test::kRadius * n);
      s.normals.push_back(n);
      s.confidence.push_back(s.points.size() % 3 == 0 ? 0.0 : 0.5 + 0.01 * i);
    }
  return scan;
}

/// A rotation by `degrees` about the sphere's centre and then a shift.
Pose turned(double degrees, const Eigen::Vector3d& shift) {
  Pose p;
  p.R = Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  p.t = test::kCentre - p.R * test::kCentre + shift;
  return p;
}

/// Whether every point of `all` (a pose applied to every scan point) that this rank must
/// evaluate is in `held`, and `held` keeps scan order.
void expectOwnedPointsHeld(const BrickStore& store, const PrismScan& scan, const Pose& pose,
                           const ControlPoints& held) {
  size_t k = 0, owned = 0;
  for (size_t v = 0; v < scan.surface.points.size(); ++v) {
    const Eigen::Vector3d p = pose.apply(scan.surface.points[v]);
    const bool mine =
        store.localBrick(mortonEncode(brickOf(store.grid().nearest(p), store.grid().brick))) >= 0;
    const bool kept = k < held.points.size() && held.points[k] == p;
    if (kept) {
      EXPECT_EQ(held.weights[k], scan.surface.confidence[v]);
      EXPECT_EQ(held.normals[k], pose.rotate(scan.surface.normals[v]));
      ++k;
    }
    if (mine && scan.surface.confidence[v] > 0) {
      EXPECT_TRUE(kept) << "point " << v << " missing on rank " << mpi::rank();
      ++owned;
    }
  }
  EXPECT_EQ(k, held.points.size()) << "held points out of scan order";
  EXPECT_GT(owned, 0u);
}

/// Scans that are never kept: each get() reads a fresh copy, as past the memory budget.
class ReadAgain : public ScanSource {
 public:
  explicit ReadAgain(std::vector<PrismScan> scans) : scans_(std::move(scans)) {}
  size_t size() const override { return scans_.size(); }
  bool holds(size_t i) const override { return !scans_[i].surface.points.empty(); }
  bool kept(size_t) const override { return false; }
  std::shared_ptr<const PrismScan> get(size_t i) const override {
    return std::make_shared<const PrismScan>(scans_[i]);
  }

 private:
  std::vector<PrismScan> scans_;
};

class ControlRoutingTest : public ::testing::TestWithParam<bool> {};

TEST_P(ControlRoutingTest, EveryRankHoldsThePointsItOwnsWhereverTheScanMoves) {
  const BrickLayout layout = test::sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  const PrismScan whole = sphereScan();
  // Scan 1 is held by the last rank alone; scan 0 is empty everywhere.
  std::vector<PrismScan> given(2);
  if (mpi::rank() == mpi::size() - 1) given[1] = whole;
  const bool kept = GetParam();
  std::unique_ptr<ScanSource> scans;
  if (kept)
    scans = std::make_unique<ScansInMemory>(given);
  else
    scans = std::make_unique<ReadAgain>(given);
  ControlRouting routing(*scans, 1, MPI_COMM_WORLD);
  std::vector<Pose> poses(2);
  routing.route({0, 1}, poses, store);
  // Within the reach (a brick of 4 voxels less one), then past it, then back.
  const std::vector<Pose> path = {Pose{},
                                  turned(2, {0.5, -0.5, 1}),
                                  turned(0, {2.9, 0, 0}),
                                  turned(15, {0, 3, 0}),
                                  turned(15, {0, 3.5, 0}),
                                  Pose{}};
  for (const Pose& pose : path) {
    expectOwnedPointsHeld(store, whole, pose, routing.at(1, pose, store));
    EXPECT_TRUE(routing.at(0, pose, store).points.empty());
  }
  EXPECT_EQ(routing.reroutes(), 2u);  // to the 15-degree turn and back
}

INSTANTIATE_TEST_SUITE_P(KeptOrReadAgain, ControlRoutingTest, ::testing::Bool());

}  // namespace
}  // namespace rangefuse
