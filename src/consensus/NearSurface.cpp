#include "rangefuse/consensus/NearSurface.h"

#include <cmath>

namespace rangefuse {
namespace {

constexpr float kMinWeight = 1e-6f;  // a voxel with a value counts as observed

void store(BrickStore& s, size_t b, const VoxelIndex& v, const SignedDistance& sd) {
  VoxelSums& acc = s.sums()[s.offset(b, v)];
  const float w = std::max(kMinWeight, static_cast<float>(sd.weight));
  acc.w = w;
  acc.wd = w * static_cast<float>(sd.d);
  for (int k = 0; k < 3; ++k) acc.wf[k] = w * static_cast<float>(sd.gradient[k]);
  acc.images = static_cast<float>(sd.views);
}

/// Cell [lo, hi] (inclusive voxel ranges) of local brick b.
void refine(BrickStore& s, size_t b, const VoxelIndex& lo, const VoxelIndex& hi, FieldSampler& fn,
            EvaluationStats& stats) {
  const VoxelGrid& g = s.grid();
  const Eigen::Vector3d centreLattice = 0.5 * (lo + hi).cast<double>();
  SignedDistance sd;
  ++stats.points;
  if (!fn.sample(g.origin + g.voxel * centreLattice, sd)) return;
  if (lo == hi) {
    store(s, b, lo, sd);
    ++stats.voxels;
    return;
  }
  const double reach = 0.5 * (hi - lo).cast<double>().norm() + std::sqrt(3.0) + 0.5;
  if (std::abs(sd.d) > reach * g.voxel) return;
  const VoxelIndex mid = lo + (hi - lo) / 2;  // children [lo, mid] and [mid+1, hi] per axis
  for (int o = 0; o < 8; ++o) {
    VoxelIndex clo, chi;
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (o >> a) & 1;
      clo[a] = upper ? mid[a] + 1 : lo[a];
      chi[a] = upper ? hi[a] : mid[a];
      empty |= clo[a] > chi[a];
    }
    if (!empty) refine(s, b, clo, chi, fn, stats);
  }
}

Eigen::AlignedBox3d brickBounds(const BrickStore& s, size_t b) {
  const int B = s.grid().brick;
  const VoxelIndex lo = mortonDecode(s.code(b)) * B;
  return Eigen::AlignedBox3d(s.grid().centre(lo),
                             s.grid().centre(lo + VoxelIndex::Constant(B - 1)));
}

}  // namespace

EvaluationStats evaluateNearSurface(BrickStore& s, FieldSampler& fn) {
  EvaluationStats stats;
  const int B = s.grid().brick;
  for (size_t b = 0; b < s.brickCount(); ++b) {
    const VoxelIndex lo = mortonDecode(s.code(b)) * B;
    fn.enterBrick(brickBounds(s, b));
    refine(s, b, lo, lo + VoxelIndex::Constant(B - 1), fn, stats);
  }
  return stats;
}

EvaluationStats evaluateAllVoxels(BrickStore& s, FieldSampler& fn) {
  EvaluationStats stats;
  const int B = s.grid().brick;
  for (size_t b = 0; b < s.brickCount(); ++b) {
    const VoxelIndex base = mortonDecode(s.code(b)) * B;
    fn.enterBrick(brickBounds(s, b));
    VoxelIndex v;
    for (v.z() = base.z(); v.z() < base.z() + B; ++v.z())
      for (v.y() = base.y(); v.y() < base.y() + B; ++v.y())
        for (v.x() = base.x(); v.x() < base.x() + B; ++v.x()) {
          SignedDistance sd;
          ++stats.points;
          if (!fn.sample(s.grid().centre(v), sd)) continue;
          store(s, b, v, sd);
          ++stats.voxels;
        }
  }
  return stats;
}

}  // namespace rangefuse
