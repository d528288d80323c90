// What a grid's shape says about its triangles (private to the surface stage): whether a
// station's columns close a full turn, which way its cells face the sensor, which triangles
// stay.
#pragma once

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::internal {

/// True when a spherical grid's columns close a full turn about the station's z axis.
/// `turnColumns` (default: the grid's) is the column count of the whole turn, for a sample of
/// a grid's columns whose empty columns separate runs of consecutive ones.
bool wrapsAround(const RangeGrid& grid, int turnColumns = -1);

/// True when most cells' triangles (r,c),(r,c+1),(r+1,c) face the sensor as wound.
bool facesSensor(const RangeGrid& grid);

/// d.norm() > limit, the same answer exactly: squares are compared, and only lengths within a
/// part in 10^12 of the limit take the root (two triangles a cell test three edges each, and
/// nearly every edge is far from the limit).
bool longerThan(const Eigen::Vector3d& d, double limit);

/// True when triangle a, b, c has no edge longer than `maxEdge` and its normal makes a cosine
/// of at least `minCos` with the line of sight at its centroid.
bool keepsTriangle(const RangeGrid& grid, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c, double maxEdge, double minCos);

}  // namespace rangefuse::internal
