// Range grid to oriented, weighted triangle surface (Tubic et al. §4.3).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/surface/TexelImage.h"

namespace rangefuse {

class RangeNoise;

struct SurfaceOptions {
  double maxEdgeFactor = 4.0;  ///< drop triangles with an edge longer than this x grid spacing
  double minCosine = 0.15;     ///< drop triangles seen more obliquely than acos(this)
  int normalPasses = 2;        ///< neighbour-averaging passes over vertex normals
  /// The same for a depth camera's frames (-1: normalPasses). Their normals are noisier, and
  /// prisms along them twist: each costs more to solve and holds fewer voxels. Frames held for
  /// registration or tracking keep normalPasses (heldScans, decision 51).
  int depthNormalPasses = 6;
  /// Merge blocks of k x k grid cells while k cells span no more than this (world units; 0:
  /// never), so that dense grids reach the field at about the voxel's scale.
  double mergeTarget = 0;
  /// Join flat blocks of 2 x 2 cells into two triangles where their chord stays within this
  /// of the surface (world units; 0: never): FlatBlocks.h.
  double flatTolerance = 0;
  /// Smooth depths whose measured noise exceeds this (world units; 0: never): DepthSmoothing.h.
  double smoothTarget = 0;
  bool sightMap = false;  ///< also map what the scan saw along its lines of sight (robust)
  /// Measure each scan's depth noise (PrismScan::noise), which registration weighs control
  /// points by; depth images and sight maps measure it whatever this says.
  bool measureNoise = true;
};

/// One scan as a triangle surface in world coordinates. Normals are unit, point toward
/// the sensor and are filtered; confidence is the cosine between normal and viewing ray.
struct ScanSurface {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> confidence;
  std::vector<Triangle> triangles;
  std::vector<Colour> colours;               ///< empty, or one per point
  ColourKind colourKind = ColourKind::none;  ///< what the scan's grid carried
  /// Colour finer than the triangles, kept when merged k x k cells (texelSide = k) or joined
  /// flat blocks coarsened a coloured grid: the grid's own colours, and each point's block
  /// (row, column) in the merged grid. Both empty otherwise.
  int texelSide = 1;
  TexelImage texels;
  std::vector<std::array<int32_t, 2>> blocks;  ///< one per point
  Sensor sensor;  ///< where the lines of sight come from, in the same frame
};

/// What surfaceColour needs of one triangle, prepared once for the many feet of its prism: its
/// corners' blocks in original-cell coordinates (when the surface has texels).
struct ColourTriangle {
  const ScanSurface* surface = nullptr;
  Triangle corners{};
  bool texels = false;    ///< false: the corners' colours are interpolated
  double row[3], col[3];  ///< each corner's block centre
  /// The original cells of the blocks between the corners, [top, bottom) x [left, right): a
  /// triangle's feet take texels from there only, never from a block across a depth edge.
  long top = 0, left = 0, bottom = 0, right = 0;
};

ColourTriangle colourTriangle(const ScanSurface& s, const Triangle& t);

/// The scan's colour at barycentric point `bary` of a triangle: the nearest original cell's
/// when the surface has texels (a merged cell then shows the texture at the grid's own
/// resolution), else the corners' colours interpolated.
Colour surfaceColour(const ColourTriangle& triangle, const Eigen::Vector3d& bary);

/// The same for triangle `t` of `s`, prepared for one foot.
Colour surfaceColour(const ScanSurface& s, const Triangle& t, const Eigen::Vector3d& bary);

/// Forgets the surface's colours and texels (a job that fuses no colour carries none).
void dropColour(ScanSurface& s);

/// Median distance between grid neighbours (the lateral sampling step), or 0 if none.
/// `downEvery` as in medianNeighbourStep.
double gridSpacing(const RangeGrid& grid, int downEvery = 1);

/// What triangulateGrid decides about a grid as a whole; given, for a band of a larger grid.
struct GridTriangulation {
  double maxEdge = 0;    ///< longest edge kept (maxEdgeFactor x grid spacing)
  double minCosine = 0;  ///< least cosine with the line of sight kept
  bool forward = true;   ///< (r,c),(r,c+1),(r+1,c) is wound toward the sensor
  bool wraps = false;    ///< the last column's neighbour is the first
};

/// The grid's own triangulation rules: its spacing, winding and seam.
GridTriangulation gridTriangulation(const RangeGrid& grid, const SurfaceOptions& options);

/// The same with the longest edge kept given (a merged grid's, mergedEdgeLimit).
GridTriangulation gridTriangulation(const RangeGrid& grid, const SurfaceOptions& options,
                                    double maxEdge);

/// Two triangles per full grid cell, filtered by edge length and obliqueness; only the
/// vertices some triangle uses are kept. Coordinates stay in the scan frame. Triangles are wound
/// to face the sensor whichever way the grid's columns run, and a station's full turn is
/// closed across its 0/360 degree seam.
TriangleMesh triangulateGrid(const RangeGrid& grid, const SurfaceOptions& options);

/// The same under given rules; `cellColumns` (if set) gets each triangle's cell column, and
/// `sources` (if set) each vertex's index among the grid's points.
TriangleMesh triangulateGrid(const RangeGrid& grid, const GridTriangulation& rules,
                             std::vector<int>* cellColumns = nullptr,
                             std::vector<int32_t>* sources = nullptr);

/// The surface of a triangulated grid: normals (scan frame, filtered) turned by the pose,
/// confidence against `sensor`'s line of sight, points moved to world.
ScanSurface orientedSurface(TriangleMesh&& mesh, const std::vector<Eigen::Vector3d>& normals,
                            const Sensor& sensor, const Pose& pose);

/// Vertex normals as the mean of their triangles' normals, then `passes` rounds of
/// averaging with the neighbouring vertices' normals.
std::vector<Eigen::Vector3d> filteredVertexNormals(const TriangleMesh& mesh, int passes);

/// Triangulates, filters normals, computes confidence and moves everything to world; depths
/// are smoothed first where `options.smoothTarget` asks (DepthSmoothing.h), against `noise`,
/// the grid's measured noise, when the caller already has it (else it is measured here).
ScanSurface buildScanSurface(const RangeGrid& grid, const Pose& pose, const SurfaceOptions& options,
                             const RangeNoise* noise = nullptr);

}  // namespace rangefuse
