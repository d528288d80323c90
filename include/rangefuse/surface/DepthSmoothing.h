// Depths averaged where a scan's noise is large against the voxel: a depth camera's far walls.
// There one frame's triangles are steeper than the wall itself (neighbouring depths differ by
// more than the cells are apart), their filtered normals point anywhere, and each voxel's
// nearest triangle lies a noise's width from the wall; the fused surface then wanders several
// voxels off it, however many frames saw it (docs/algorithms.md, "Noisy depths smoothed").
#pragma once

#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/surface/RangeNoise.h"

namespace rangefuse {

/// How smoothDepths treats a grid.
struct DepthSmoothing {
  double target = 0;  ///< smooth until a depth's noise is about this (world units; 0: never)
  double edge = 0;    ///< neighbours further apart than this plus 3 sqrt(2) noises: another surface
  double scale = 1;   ///< the grid's noise is `noise` times this (merged cells: 1 / k)
  int maxHalfWidth = 8;  ///< the widest window is 2 * this + 1 cells
};

/// The half-width of the window that brings noise `sigma` to about `target`: a window of w
/// cells along a row and w down a column averages w * w depths, 1 / w of their noise.
int smoothingHalfWidth(double sigma, double target, int maxHalfWidth);

/// The grid with each depth replaced by a least-squares line through its neighbours along the
/// row, then through the row-smoothed neighbours down the column, evaluated at the cell: over
/// the cells within the half-width its noise at that depth asks for (smoothingHalfWidth), walked
/// outward while they stay on its surface (two cells in a row further in depth than the edge
/// limit plus 3 sqrt(2) noises from the last one taken end the walk). Points
/// move along their lines of sight. Pinhole grids and stations fit inverse depth, which is
/// linear across a plane; others fit depth. Depths whose noise is within the target, and
/// grids without a measured noise, keep their values bit for bit.
RangeGrid smoothDepths(const RangeGrid& grid, const RangeNoise& noise, const DepthSmoothing& how);

}  // namespace rangefuse
