// Which space the scans hid: behind surfaces most scans saw and looked through by none, as
// VRIP's space carving decides it. Closing holes (--fill-holes) counts that space as inside.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "rangefuse/robust/SightMap.h"

namespace rangefuse {

/// The scans' sight maps, asked about points in boxes.
class SpaceCarving {
 public:
  /// `margin`: how far in front of what a scan saw a point must lie for the scan to have
  /// looked through it (as SightMap::lookedThrough). Keeps a reference to `sights`.
  SpaceCarving(const std::vector<SightMap>& sights, double margin);

  /// For each point (world, every one within `box`): 1 when it lies inside — no scan looked
  /// through it and at least two thirds of the scans saw a surface in front of it (the
  /// quorum) — else 0 (empty or unknown space).
  std::vector<uint8_t> inside(const Eigen::AlignedBox3d& box,
                              const std::vector<Eigen::Vector3d>& points) const;

 private:
  const std::vector<SightMap>& sights_;
  double margin_;
  int quorum_ = 1;  ///< scans that must have seen a surface in front of a point inside
};

}  // namespace rangefuse
