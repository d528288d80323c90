// Larger triangles where a scan's surface is flat. A prism's set-up costs about what its voxel
// updates cost, and a grid triangulated at the voxel's scale gives each prism only a few; where
// the surface is flat, a block of 2 x 2 cells described by two triangles loses nothing a voxel
// can see, and its prisms pay their set-up over four times the voxels.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// A grid's triangulation with what the surface stage keeps beside it: each vertex's filtered
/// normal and its index among the grid's points.
struct GridSurface {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> normals;
  std::vector<int32_t> sources;
};

/// Replaces the triangles of each flat block of 2 x 2 cells (rows and columns from even
/// indices) with triangles between its corners. A block is flat when all eight of its triangles
/// were kept and the chord its corners span departs from the surface by at most `tolerance`
/// (world units), as its filtered normals tell: the diagonal's length times the largest angle
/// between the block's nine normals, over 8. The normals are the fine grid's, filtered over
/// more samples than one noisy depth, so noise does not pass for flatness; curvature within a
/// block sets the chord's error. Where a joined block meets cells that stay fine it keeps the
/// shared side's middle vertex, so the surface has no crack. Triangles keep the grid's order
/// (a joined block's where its first cell's were). The vertices stay, those inside joined
/// blocks too: they are registration's and tracking's control points, whose fits should not
/// lose the flat surfaces that hold them best. Grids that close a full turn are left as they
/// are.
void joinFlatBlocks(const RangeGrid& grid, const GridTriangulation& rules, double tolerance,
                    GridSurface& surface);

}  // namespace rangefuse
