// Accuracy of a mesh against a reference mesh, and of poses against reference poses.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/eval/SeenSurface.h"

namespace rangefuse {

struct MeshComparison {
  DistanceStats accuracy;      ///< samples on the mesh to the reference
  DistanceStats completeness;  ///< samples on the reference to the mesh
  double chamfer = 0;          ///< mean of the two means
  double precision = 0;        ///< fraction of accuracy samples within tau
  double recall = 0;           ///< fraction of completeness samples within tau
  double fscore = 0;
  double spuriousAreaFraction = 0;  ///< mesh area farther than spuriousDistance from reference
  double seenFraction = 1;          ///< share of the reference's area the completeness covers
};

struct CompareSettings {
  double tau = 1;               ///< F-score threshold, model units
  double spuriousDistance = 3;  ///< model units
  size_t samples = 200000;      ///< area-weighted samples on each mesh
  uint64_t seed = 1;
};

/// Accuracy, completeness and F-score of a mesh against a reference. With `seen`, completeness
/// and recall count only the reference's samples near a scan point (the surface measured).
MeshComparison compareMeshes(const TriangleMesh& mesh, const TriangleMesh& reference,
                             const CompareSettings& settings, const SeenCells* seen = nullptr);

struct PoseError {
  std::string name;
  double rotationDeg = 0;                            ///< angle of R_est R_ref^T
  double translation = 0;                            ///< |t_est - t_ref|, model units
  double displacementMean = 0, displacementMax = 0;  ///< over the scan's points, model units
  size_t points = 0;
};

/// Errors of one pose against its reference; displacement over the given scan-frame points.
PoseError comparePose(const Pose& estimate, const Pose& reference,
                      const std::vector<Eigen::Vector3d>& points);

/// The rigid motion G that brings the estimated scans best onto their references (least
/// squares over every `stride`-th point of each scan): what all estimates share, a drift of
/// the whole group rather than an error of the scans relative to one another. Compare G·estimate
/// with the reference to see the relative errors alone.
Pose commonMotion(const std::vector<Pose>& estimates, const std::vector<Pose>& references,
                  const std::vector<std::vector<Eigen::Vector3d>>& points, size_t stride = 16);

}  // namespace rangefuse
