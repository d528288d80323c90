// How well scans agree with one another under a set of poses, judged without any fused field:
// point-to-plane distances from each scan's vertices to the nearest vertex of every other scan.
#pragma once

#include <vector>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

struct ConsistencySettings {
  double maxDistance = 1;    ///< pairs farther apart along the normal are not overlap
  double maxTangential = 1;  ///< nor those farther apart across it (past the other's edge)
  double minCosine = 0.866;  ///< nor those whose normals differ by more than 30 degrees
  size_t stride = 4;         ///< every k-th vertex of a scan is measured
};

/// One scan's agreement with all the others, and with each.
struct ScanConsistency {
  double rms = 0;      ///< RMS point-to-plane distance over its overlap pairs
  size_t pairs = 0;    ///< vertices with an overlapping vertex in another scan, over all others
  size_t sampled = 0;  ///< vertices measured (every stride-th)
  /// Per other scan j: vertices of this scan with a partner in j, and their RMS. Poses that
  /// slide scans along their surfaces leave point-to-plane RMS as it was but lose partners.
  std::vector<size_t> pairsWith;
  std::vector<double> rmsWith;
};

/// Per scan (already in the world), the RMS of n_j . (p - q) over its vertices p and, in each
/// other scan j, the vertex q nearest to p (normal n_j) when the pair passes the settings.
std::vector<ScanConsistency> poseConsistency(const std::vector<ScanSurface>& world,
                                             const ConsistencySettings& settings);

/// The same with probe i (scan i elsewhere, e.g. at an estimated pose) measured against every
/// other scan of `world`: how far a pose leaves a scan from the surfaces the others give.
std::vector<ScanConsistency> poseConsistency(const std::vector<ScanSurface>& probes,
                                             const std::vector<ScanSurface>& world,
                                             const ConsistencySettings& settings);

}  // namespace rangefuse
