// Range grids brought to the voxel's scale before prisms are built: where a scan's cells are
// much smaller than a voxel, ten triangles cover what one would, and every stage pays per
// triangle. Blocks of k x k cells become one cell, so the grid stays a grid.
#pragma once

#include <array>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/surface/TexelImage.h"

namespace rangefuse {

/// The block edge k for a grid with lateral step `spacing` and `shortSide` cells across its
/// shorter side: the largest k whose merged cells stay within `target` (world units; 0 or a
/// coarse grid: 1, nothing merged), and that leaves at least 16 cells across.
int mergeFactor(double spacing, double target, int shortSide);

/// The median step between grid neighbours across the line of sight (the part along it
/// removed): the pixel footprint, which range noise does not inflate as it does gridSpacing.
/// `downEvery` as in medianNeighbourStep.
double lateralSpacing(const RangeGrid& grid, int downEvery = 1);

/// lateralSpacing(grid) and gridSpacing(grid), in that order, the same values from one pass
/// over the grid's neighbours (a depth frame's reading takes both).
std::array<double, 2> lateralAndGridSpacing(const RangeGrid& grid);

/// The median angle (radians) between grid neighbours' directions from the scan frame's
/// origin: a station's angular step, whatever the range.
double angularSpacing(const RangeGrid& grid, int downEvery = 1);

/// The longest triangle edge a grid merged in blocks of k keeps: maxEdgeFactor times the
/// larger of its own step and k fine steps. Averaging removes range noise, which had lengthened
/// the fine grid's median step (twice over at noise of a cell's size), so the merged grid's own
/// step alone would drop oblique triangles that the fine grid keeps: far floors seen by a
/// scanner station.
double mergedEdgeLimit(double mergedStep, double fineStep, int k, double maxEdgeFactor);

/// The grid's colours, cell by cell (alpha 0 where a cell has no point); empty without colour.
TexelImage cellTexels(const RangeGrid& grid);

/// The grid with each k x k block of cells merged into one: the mean of the block's points that
/// lie on the surface of its most central point (within maxEdgeFactor grid steps per cell of
/// separation, the triangulation's own test), so that a block across a depth edge keeps only the
/// side of its centre. Pinhole intrinsics are scaled to the new cells. k = 1 returns the grid.
/// With `texels` and a coloured grid, it gets the grid's colours, cell by cell (alpha 0 for
/// cells without a point or off their block centre's surface).
RangeGrid mergeCells(const RangeGrid& grid, int k, double spacing, double maxEdgeFactor,
                     TexelImage* texels = nullptr);

}  // namespace rangefuse
