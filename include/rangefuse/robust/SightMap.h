// What a scan saw along its lines of sight: the depth of what it hit on a raster, so that any
// point can be asked whether the scan looked through it (free-space evidence).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/surface/RangeNoise.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// A scan's surface depth along its lines of sight: rays through a pinhole at the scan frame's
/// origin looking toward -z, parallel to -z (near-orthographic range grids), or from a scanner
/// station at the origin in every direction (cells of azimuth and elevation, depth the range).
/// Depth is -z for the first two; the nearest per cell.
class SightMap {
 public:
  SightMap() = default;

  /// What a pixel without a return says of its ray.
  enum class NoReturn : uint8_t {
    /// Nothing lies along it: a scanner whose returns stop only at empty space.
    SawNothing,
    /// A depth image's 0, a measurement the camera did not make: a dark, shiny or grazing
    /// surface, a projector's shadow, a surface out of range, a blind band at the image's
    /// side. It says the ray is empty only in front of the frame's reach, and only where the
    /// hole opens to the frame's border (a view past what the frame saw), not in a blind band.
    DepthCamera,
  };

  /// A pinhole grid's own pixels, in blocks of k x k (scan frame): a block without a return
  /// saw through everything (free to infinity) as `noReturn` says, else is unknown; outside
  /// the frame: unknown.
  static SightMap fromPinholeGrid(const RangeGrid& grid, int k,
                                  NoReturn noReturn = NoReturn::SawNothing);
  /// A near-orthographic scan's triangles (scan frame) on cells `cell` wide. With the scan's
  /// `grid`, when its points lie on a regular lattice of columns and rows, the cells of its
  /// frame where the scanner got no return saw nothing (free to infinity); other cells no
  /// triangle covers are unknown.
  static SightMap fromSurface(const ScanSurface& surface, double cell,
                              const RangeGrid* grid = nullptr);

  /// A station's triangles (scan frame) on cells `angle` radians wide in azimuth (about the
  /// frame's z axis) and elevation: cells no triangle covers are unknown, and so is a thin
  /// strip at the azimuth seam (triangles across it are left out).
  static SightMap fromStation(const ScanSurface& surface, double angle);

  /// The same map for the scan placed at `pose` (scan to world).
  void place(const Pose& pose);

  /// Adds what `other` saw (a map of another part of the same scan, on the same raster, cropped
  /// anywhere; an empty map takes it whole): the nearest depth where both know, else the one
  /// that knows.
  void join(SightMap&& other);

  /// How far p (world) lies in front of what the scan saw along its line of sight, against the
  /// nearest depth of the 3 x 3 cells around p's ray (so only clear evidence counts): +inf
  /// where they all saw nothing, NaN where any is unknown.
  double clearance(const Eigen::Vector3d& p) const;

  /// False when clearance() is NaN everywhere in `box` (world): the box lies off the raster or,
  /// for a pinhole, wholly behind the sensor. True when it may not be (stations: always).
  bool mayCover(const Eigen::AlignedBox3d& box) const;

  /// The scan's depth noise (RangeNoise::measure of its grid) and the share of it left in its
  /// triangles' points (1 / k when k x k cells were merged into one point).
  void setNoise(RangeNoise noise, double sampleShare);

  /// The deviation of the scan's own depth at p's depth along its line of sight (0 unknown).
  double noiseAt(const Eigen::Vector3d& p) const;
  /// The deviation of the distances the scan's triangles give a voxel near p.
  double sampleNoiseAt(const Eigen::Vector3d& p) const { return sampleShare_ * noiseAt(p); }

  /// True when the scan looked through p by more than `margin` plus three deviations of its
  /// own noise at that depth (clear evidence of free space; false where unknown).
  bool lookedThrough(const Eigen::Vector3d& p, double margin) const;

  /// What the scan says of the space at p: looked through (as lookedThrough), behind what it
  /// saw along its line of sight (hidden by a surface), or neither (unknown, or too close to
  /// call).
  enum class Sight : uint8_t { Unknown, Through, Behind };
  Sight sightOf(const Eigen::Vector3d& p, double margin) const;

  /// Serialised form, for sending to other ranks.
  void pack(std::vector<char>& out) const;
  static SightMap unpack(const std::vector<char>& in, size_t& pos);

  int width() const { return width_; }
  /// Bytes it holds.
  uint64_t bytes() const { return sizeof(*this) + sizeof(float) * depth_.capacity(); }
  int height() const { return height_; }

 private:
  /// clearance(p), and p's depth along the scan's line of sight.
  double clearanceAt(const Eigen::Vector3d& p, double& depth) const;
  /// Raster coordinates (cells) and depth of a point in the scan frame.
  Eigen::Vector3d project(const Eigen::Vector3d& q) const;
  /// Marks the raster cells of `grid`'s frame (x = fit[0] col + fit[1], y = fit[2] row +
  /// fit[3]) where it got no return and nothing else is known as having seen nothing.
  void markNoReturns(const RangeGrid& grid, const Eigen::Vector4d& fit);
  /// Marks unknown the cells wholly inside a pinhole grid's blind lines (pixels counted from
  /// each side: left, right, top, bottom), for blocks of k x k of a `cols` x `rows` grid.
  void markBlind(const std::array<int, 4>& lines, int k, int cols, int rows);
  /// Marks unknown the holes the raster's border does not reach through 4-connected cells
  /// without a return: inside what a depth camera saw, a hole is a dropout, which says
  /// nothing of what lies along its rays.
  void forgetEnclosedHoles();
  void rasterize(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
  void allocate(int width, int height, float fill);
  /// Drops the rows and columns on the raster's borders where nothing is known: clearance
  /// needs all 3 x 3 cells known, and answers unknown off the raster as for unknown cells, so
  /// every answer stays the same (a station band's map keeps its own azimuths only).
  void cropUnknown();
  float& depthAt(int x, int y) { return depth_[static_cast<size_t>(y) * width_ + x]; }
  float depthAt(int x, int y) const { return depth_[static_cast<size_t>(y) * width_ + x]; }

  enum class Rays : uint8_t { Parallel, Pinhole, Station };

  Pose toScan_;  ///< world -> scan frame
  Rays rays_ = Rays::Parallel;
  /// Cell coordinates: (au X + bu, av Y + bv), X, Y = x, y (orthographic), x, y / depth
  /// (pinhole) or azimuth, elevation (station).
  double au_ = 1, bu_ = 0, av_ = 1, bv_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<float> depth_;  ///< NaN: unknown; +inf: saw nothing
  /// Where cells that saw nothing stop being evidence: a depth image's reach (farDepth),
  /// infinite for scanners that report no return only where nothing is.
  double reach_ = std::numeric_limits<double>::infinity();
  RangeNoise noise_;
  double sampleShare_ = 1;
};

}  // namespace rangefuse
