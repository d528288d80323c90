// The field stage's settings: its lattice, its method and the method's parameters. The fuse
// command converts its options into them (RunSettings.h); the library's Fusion takes them as
// they are (rangefuse/rangefuse.h).
#pragma once

#include <cstdint>
#include <string>

#include "rangefuse/fuse/FieldMethod.h"

namespace rangefuse {

/// The field: its lattice, its method and the method's parameters.
struct FieldSettings {
  FieldMethod method = FieldMethod::Prism;
  double voxel = 0;                 ///< in the scans' units
  double envelope = 3;              ///< prism half-thickness, in voxels
  int brick = 8;                    ///< voxels per brick edge
  uint64_t maxVoxels = 1000000000;  ///< refuse fields needing more (--max-voxels)
  int threads = 1;
  std::string colour = "auto";  ///< auto, rgb, intensity or none
  double quorum = -1;           ///< consensus: summed confidence needed (-1: autoQuorum)
  int minViews = 2;             ///< consensus and robust: views an agreement needs
  double edgeAngle = 78;        ///< consensus: degrees from the normal beside an edge
  double sameDistance = 2;      ///< consensus and robust: delta_d, voxels
  double sameAngle = 45;        ///< consensus and robust: theta_n, degrees
  double freeMargin = -1;       ///< robust: looked-through depth, voxels (-1: the envelope)
  bool fillHoles = false;       ///< every scan's sight map kept on every rank, for carving

  double eps() const { return envelope * voxel; }
  /// How far before what a scan saw a point must lie for the scan to have looked through it.
  double lookedThroughMargin() const { return (freeMargin == -1 ? envelope : freeMargin) * voxel; }
};

}  // namespace rangefuse
