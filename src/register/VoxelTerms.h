// The normal-equation terms of one voxel of the joint solve (private to the register stage),
// with the voxel's unknown offset eliminated.
#pragma once

#include <vector>

#include "rangefuse/register/JointSolve.h"

namespace rangefuse::internal {

/// The terms one voxel adds (shares in increasing scan order, one per scan). The voxel's offset
/// μ = Σ m r̄ / W is eliminated: the cost Σ_s m_s (r̄_s + ā_s δ_s − μ(δ))² has the Hessian
/// Bᵀ(M − m mᵀ/W)B. A voxel one scan alone fell into adds nothing.
template <class Block, class Gradient, class Residual>
void voxelTerms(const std::vector<VoxelShare>& shares, Block&& block, Gradient&& gradient,
                Residual&& residual) {
  if (shares.size() < 2) return;
  double W = 0, R = 0;
  for (const VoxelShare& s : shares) W += s.weight, R += s.residual;
  const double mean = R / W;
  for (size_t i = 0; i < shares.size(); ++i) {
    const VoxelShare& a = shares[i];
    const double e = a.residual / a.weight - mean;
    block(a.scan, a.scan, Matrix6d(a.jacobian * a.jacobian.transpose() * (1 / a.weight - 1 / W)));
    for (size_t j = i + 1; j < shares.size(); ++j)
      block(a.scan, shares[j].scan, Matrix6d(-a.jacobian * shares[j].jacobian.transpose() / W));
    gradient(a.scan, Vector6d(a.jacobian * e));
    residual(a, e);
  }
}

}  // namespace rangefuse::internal
