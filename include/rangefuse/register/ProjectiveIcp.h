// Frame-to-frame alignment of two depth images by projective data association (the pixel grid
// finds each point's partner: project it into the other image), point-to-plane Gauss-Newton
// with Huber weights, coarse to fine over an image pyramid. Its reach, several centimetres and
// degrees at the coarse levels, is what a narrow-band field cannot give: the tracker starts each
// frame's fit to the field from here.
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/core/Pose.h"

namespace rangefuse {

/// A depth image in camera coordinates (OpenCV: x right, y down, z forward), depth 0 where
/// nothing was measured.
struct DepthMap {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<float> depth;  ///< row-major, world units

  float at(int u, int v) const { return depth[static_cast<size_t>(v) * width + u]; }
};

struct ProjectiveIcpSettings {
  int levels = 3;                 ///< pyramid levels used: halvings of the image
  int skipFinest = 1;             ///< finest levels left out (the field refines)
  int iterations = 10;            ///< Gauss-Newton steps per level
  double maxDistance = 0.1;       ///< partners farther apart are not partners, world units
  double maxNormalAngleDeg = 30;  ///< ... nor those whose normals differ more
  double huber = 0.01;            ///< Huber's threshold on the point-to-plane residual
  double minShare = 0.1;          ///< fewer partners than this share of points: no result
};

struct FrameAlignment {
  bool ok = false;
  Pose motion;       ///< current camera to previous camera
  double share = 0;  ///< share of the last level's points with a partner
};

/// The Gauss-Newton step x of A x = b (x: translation, then rotation vector) along the motions
/// the data pin down only. Rotation is scaled by `length` (the data's lever arm) so that both
/// halves compare as lengths; directions whose curvature is below 1e-3 of the strongest (a
/// sphere turning about its centre, a corridor along its axis) get no step rather than noise.
Eigen::Matrix<double, 6, 1> solveWellPosed(const Eigen::Matrix<double, 6, 6>& A,
                                           const Eigen::Matrix<double, 6, 1>& b, double length);

/// Half the size: each 2 x 2 block's mean depth over its pixels within 3 % of the block's first
/// measured depth (a block straddling an edge does not blend foreground and background).
DepthMap halve(const DepthMap& map);

/// The motion mapping `current`'s points onto `previous`'s surface, from `guess`. Deterministic
/// (one thread, fixed order): the same bits on any rank.
FrameAlignment alignFrames(const DepthMap& previous, const DepthMap& current, const Pose& guess,
                           const ProjectiveIcpSettings& settings);

}  // namespace rangefuse
