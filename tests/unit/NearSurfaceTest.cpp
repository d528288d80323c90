#include <gtest/gtest.h>

#include "rangefuse/consensus/NearSurface.h"

using namespace rangefuse;

namespace {

/// The exact signed distance of a sphere: a field whose evaluation count is predictable.
class SphereSampler : public FieldSampler {
 public:
  SphereSampler(const Eigen::Vector3d& c, double r) : c_(c), r_(r) {}
  bool sample(const Eigen::Vector3d& x, SignedDistance& out) override {
    out.d = (x - c_).norm() - r_;
    out.gradient = (x - c_).normalized();
    out.weight = 1;
    return true;
  }

 private:
  Eigen::Vector3d c_;
  double r_;
};

/// Every brick of 8^3 voxels of size `voxel` that a sphere of radius r can touch.
BrickLayout sphereBricks(double voxel, const Eigen::Vector3d& c, double r) {
  BrickLayout l;
  l.grid.voxel = voxel;
  l.grid.brick = 8;
  const int n = static_cast<int>(std::ceil(2.5 * r / (8 * voxel))) + 1;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const Eigen::Vector3d centre =
            voxel * (8.0 * Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(3.5));
        if (std::abs((centre - c).norm() - r) < 8 * voxel)
          l.codes.push_back(mortonEncode({x, y, z}));
      }
  std::sort(l.codes.begin(), l.codes.end());
  l.work.assign(l.codes.size(), 1);
  l.setRuns({0, l.codes.size()});
  return l;
}

}  // namespace

TEST(NearSurface, FastPathMatchesFullEvaluationVoxelByVoxel) {
  const Eigen::Vector3d c(30.3, 29.6, 31.2);
  const BrickLayout layout = sphereBricks(1, c, 20);
  BrickStore fast(layout, 0), full(layout, 0);
  SphereSampler sampler(c, 20);
  const EvaluationStats f = evaluateNearSurface(fast, sampler);
  const EvaluationStats a = evaluateAllVoxels(full, sampler);
  EXPECT_LT(f.voxels, a.voxels / 2);  // it really skips
  size_t needed = 0;
  for (size_t i = 0; i < full.sums().size(); ++i) {
    const VoxelSums &x = fast.sums()[i], &y = full.sums()[i];
    if (x.w > 0) {
      EXPECT_EQ(x.wd, y.wd);  // same value where both evaluated
      EXPECT_EQ(x.wf[0], y.wf[0]);
    }
    if (std::abs(y.wd / y.w) <= std::sqrt(3.0)) {
      ++needed;
      EXPECT_GT(x.w, 0) << "a voxel within sqrt(3) of the surface was skipped";
    }
  }
  EXPECT_GT(needed, 5000u);
}

TEST(NearSurface, EvaluatedVoxelsGrowWithAreaNotVolume) {
  const Eigen::Vector3d c(40.3, 39.6, 41.2);
  uint64_t counts[2];
  for (int k = 0; k < 2; ++k) {
    const double voxel = k == 0 ? 1.0 : 0.5;
    BrickStore store(sphereBricks(voxel, c, 25), 0);
    SphereSampler sampler(c, 25);
    counts[k] = evaluateNearSurface(store, sampler).voxels;
  }
  const double ratio = double(counts[1]) / counts[0];
  EXPECT_GE(ratio, 3.5);
  EXPECT_LE(ratio, 4.5);
}
