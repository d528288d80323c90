// Evaluating a distance field only near the surface: coarse-to-fine over each brick (the
// role of the octree in Wheeler et al. §4.3).
#pragma once

#include <cstdint>

#include "rangefuse/consensus/Consensus.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {

/// A signed distance function evaluated brick by brick.
class FieldSampler {
 public:
  virtual ~FieldSampler() = default;
  /// Called before the points of a brick (world bounds of its voxel centres).
  virtual void enterBrick(const Eigen::AlignedBox3d& /*bounds*/) {}
  /// The distance at x; false when undefined there.
  virtual bool sample(const Eigen::Vector3d& x, SignedDistance& out) = 0;
};

struct EvaluationStats {
  uint64_t points = 0;  ///< samples taken (cells and voxels)
  uint64_t voxels = 0;  ///< voxels given a value
};

/// Starting from each local brick as one cell, splits a cell into octants when |d| at its
/// centre is within (its centre-to-corner-voxel distance + sqrt(3) + 0.5) voxels: every
/// voxel within sqrt(3) voxels of the surface - every corner of a cube the surface crosses -
/// is reached, and the count grows with the surface area, not the volume. Reached voxels
/// store w d, w, w f.
EvaluationStats evaluateNearSurface(BrickStore& store, FieldSampler& sampler);

/// Reference for evaluateNearSurface: every voxel of every local brick.
EvaluationStats evaluateAllVoxels(BrickStore& store, FieldSampler& sampler);

}  // namespace rangefuse
