// Which part of a reference surface the scans saw: completeness measured only there.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse {

/// The cells of a regular grid (edge `cell`) that a scan's surface crosses. A scene's
/// truth mesh has surface no scanner reaches (under a desk, behind a cabinet); judged against
/// all of it, a perfect fusion still misses that area. Completeness restricted to the seen
/// cells says how much of what was measured the mesh keeps.
class SeenCells {
 public:
  explicit SeenCells(double cell) : cell_(cell) {}

  /// Marks the cells of this surface (a triangulated scan moved to the world by `pose`),
  /// sampling each triangle no coarser than the cell, so sparse grids cover what they span.
  void addSurface(const TriangleMesh& mesh, const Pose& pose);

  /// True when p's cell or one of its 26 neighbours is marked: every p within `cell` of the
  /// surfaces counts, none farther than 2√3 `cell`.
  bool near(const Eigen::Vector3d& p) const;

  size_t cells() const { return keys_.size(); }

 private:
  uint64_t key(const Eigen::Vector3d& p, int dx, int dy, int dz) const;
  void merge(std::vector<uint64_t>& fresh);

  double cell_;
  std::vector<uint64_t> keys_;  // sorted, unique
};

}  // namespace rangefuse
