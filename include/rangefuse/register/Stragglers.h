// Scans registration left out of line with the rest: their last fit's residual far above the
// other scans', or their overlap (correspondences) far below, so that a user sees which scan
// to check instead of a mesh that is blurred in one place.
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// Fewer scans than this are not judged: a median of their fits means nothing.
constexpr size_t kFewestJudged = 4;

/// Registration's scans checked against the other scans alone: those it moved farthest. Each
/// costs a field of all the others.
constexpr size_t kOthersChecked = 3;

/// A scan that a fit against the other scans alone (Registration.h, fitAgainstOthers) moves
/// farther than this, in voxels, was left out of line by registration.
constexpr double kOthersMotion = 0.12;

/// How a scan ended registration: its last fit, before that fit moved it.
struct ScanStanding {
  size_t scan = 0;
  double rms = 0;                ///< weighted RMS distance to its correspondences
  uint64_t correspondences = 0;  ///< its overlap with the field, in control points
  double rmsScore = 0;           ///< (rms - median) / (1.4826 MAD): a robust z-score
  double overlapShare = 1;       ///< correspondences / the median scan's
  LooseMotion loose;             ///< its last joint fit's loosest motion
};

/// Each scan's last registration fit among `steps` (not the Others checks), applied or not (too
/// few correspondences to move it: its overlap is what is out of line), in scan order; scans
/// never fitted are left out.
std::vector<ScanStanding> lastStandings(const std::vector<RegistrationStep>& steps);

/// The standings out of line: a residual more than 5 robust deviations above the median and
/// 25 % above it (so that a set whose scans all fit alike flags none), or correspondences under
/// a third of the median scan's. Needs four scans or more (fewer: none).
std::vector<ScanStanding> findStragglers(const std::vector<ScanStanding>& standings);

/// The scans whose fit against the other scans alone (the Others steps) moves them more than
/// kOthersMotion voxels of `voxel`, and that are neither loose nor among findStragglers: named
/// out of line by that fit. In scan order.
std::vector<RegistrationStep> findOthersStragglers(const std::vector<RegistrationStep>& steps,
                                                   double voxel);

/// The standings whose last joint fit held some motion less than kLooseHold: their pose along
/// it rests on where they started (LooseMotion.h). Any number of scans.
std::vector<ScanStanding> findLooseScans(const std::vector<ScanStanding>& standings);

}  // namespace rangefuse
