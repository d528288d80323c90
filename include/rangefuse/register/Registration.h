// Registration of every scan against the fused field: Tubic et al. Algorithm 1 (incremental)
// and Algorithm 2 (simultaneous), with correspondence sums reduced across ranks.
#pragma once

#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/register/Correspondences.h"

namespace rangefuse {

struct RegistrationOptions {
  std::string mode = "none";       ///< none, incremental, simultaneous or both
  size_t anchor = 0;               ///< the scan that fixes the frame
  int controlStride = 1;           ///< every k-th vertex is a control point
  int maxIterations = 30;          ///< fits per scan (Algorithm 1) or per round (Algorithm 2)
  int maxRounds = 8;               ///< Algorithm 2: field rebuilds
  double rotationTolDeg = 1e-3;    ///< converged when a fit turns less than this ...
  double translationTol = 0;       ///< ... and moves less than this (world units)
  size_t minCorrespondences = 50;  ///< fewer: the scan is reported and left where it is
  bool accelerate = true;          ///< extrapolate steadily converging fits
  CorrespondenceSettings correspondences;
};

/// One fit of one scan, for the report and the progress lines.
struct RegistrationStep {
  std::string algorithm;  ///< "incremental" or "simultaneous"
  int round = 0, iteration = 0;
  size_t scan = 0;
  uint64_t correspondences = 0;
  double rms = 0;          ///< weighted RMS distance to the correspondences, before the fit
  double rotationDeg = 0;  ///< the fit's rotation
  double translation = 0;  ///< the fit's translation, world units
  bool applied = false;    ///< false when too few correspondences
};

/// Builds the field of the listed scans at the given poses (collective) and returns it.
using FieldFactory =
    std::function<const BrickStore&(const std::vector<size_t>& scans, const std::vector<Pose>&)>;

/// Collective: refines `poses` (the anchor never moves). `scans` are in their own frames.
/// `onStep` sees every fit (rank 0 prints it). Every rank ends with the same poses.
void registerScans(const std::vector<PrismScan>& scans, std::vector<Pose>& poses,
                   const RegistrationOptions& options, const FieldFactory& buildField,
                   MPI_Comm comm, const std::function<void(const RegistrationStep&)>& onStep);

/// The change a fit makes: rotation angle (degrees) and translation length.
double rotationDegrees(const Eigen::Matrix3d& R);

}  // namespace rangefuse
