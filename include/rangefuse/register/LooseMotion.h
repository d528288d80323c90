// A scan's motion that its overlap barely constrains. Where a scan sees only surfaces symmetric
// about an axis (a torus and a sphere on that axis, a cylinder), turning it about that axis
// leaves every point on the others' surfaces: no fit can find its pose along that turn, and its
// residual and overlap look like everyone else's. The joint solve's block of the scan says so:
// its least eigenvalue is far below its largest.
#pragma once

#include <Eigen/Core>

#include "rangefuse/register/JointSolve.h"

namespace rangefuse {

/// A scan's least-held motion: how firmly the fit holds it and which way it goes.
struct LooseMotion {
  /// sqrt(least / largest eigenvalue) of the scan's block: a motion along the loosest way
  /// changes the fit's residuals this share as much as the same motion along the firmest.
  double hold = 1;
  int looseWays = 0;  ///< independent motions held less than kLooseHold (0 to 6)
  bool turn = false;  ///< the loosest way is a turn (about `axis` through `through`), else a slide
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit: turn axis or slide direction
  Eigen::Vector3d through =
      Eigen::Vector3d::Zero();  ///< the turn axis's point nearest the frame's centre
};

/// Below this hold a motion is loose. On 24 and 12 views of the composite shape the scans that
/// saw only its torus and the sphere on the torus's axis held their turn about that axis at
/// 0.007-0.0095, every other scan held every motion at 0.03 or more; a sphere's views, 0.0015.
constexpr double kLooseHold = 1.0 / 64;

/// The loosest motion of a scan whose joint block (H_ss, motions in `frame`) is `block`.
/// An all-zero block (no overlap) holds nothing: hold 0, six loose ways.
LooseMotion loosestMotion(const Matrix6d& block, const MotionFrame& frame);

}  // namespace rangefuse
