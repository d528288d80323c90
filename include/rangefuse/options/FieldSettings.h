// The field stage's settings: its lattice, its method and the method's parameters, with the
// one description of each (settings()): the fuse command's options, the library's Fusion and
// the Python module's keywords all read it, so each default, check and help is written here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/Setting.h"
#include "rangefuse/options/FieldMethod.h"

namespace rangefuse {

/// The field: its lattice, its method and the method's parameters.
struct FieldSettings {
  FieldMethod method = FieldMethod::Prism;
  double voxel = 0;                              ///< in the scans' units
  double envelope = 3;                           ///< prism half-thickness, in voxels
  int brick = 8;                                 ///< voxels per brick edge
  uint64_t maxVoxels = InputLimits{}.maxVoxels;  ///< refuse fields needing more (--max-voxels)
  int threads = 0;              ///< per rank (0: the rank's share of its node's CPUs)
  std::string colour = "auto";  ///< auto, rgb, intensity or none
  double quorum = -1;           ///< consensus: summed confidence needed (-1: autoQuorum)
  int minViews = 2;             ///< consensus and robust: views an agreement needs
  double edgeAngle = 78;        ///< consensus: degrees from the normal beside an edge
  double sameDistance = 2;      ///< consensus and robust: delta_d, voxels
  double sameAngle = 45;        ///< consensus and robust: theta_n, degrees
  double freeMargin = -1;       ///< robust: looked-through depth, voxels (-1: the envelope)
  bool fillHoles = false;       ///< every scan's sight map kept on every rank, for carving

  /// Every setting above a user gives (all but maxVoxels, an input limit), in --help's order.
  static const std::vector<Setting<FieldSettings>>& settings();
  /// Throws InputError with the message the fuse command gives for the first bad value.
  void validate() const;

  double eps() const { return envelope * voxel; }
  /// How far before what a scan saw a point must lie for the scan to have looked through it.
  double lookedThroughMargin() const { return (freeMargin == -1 ? envelope : freeMargin) * voxel; }
};

inline void FieldSettings::validate() const {
  validateSettings(settings(), *this);
}

}  // namespace rangefuse
