// What a structured-light depth camera (a Kinect v1) does to the depth it measures, beyond
// Gaussian noise, for synthetic streams as hard to track and fuse as real ones: depth from a
// disparity rounded to 1/8 pixel, disparity noise, the projector's shadows, no return at
// grazing angles, on dark surfaces or beyond the working range, holes and mixed returns at
// depth edges, a blank band of columns, rows read over time (rolling shutter) and depth taken
// later than the pose reported for it. docs/sensor.md compares the preset with real frames.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace rangefuse {

struct DepthSensorModel {
  double baseline = 0;        ///< projector to camera along +x, world units (0: no model)
  double disparityNoise = 0;  ///< Gaussian disparity noise before rounding, pixels
  double quantum = 0.125;     ///< disparity step, pixels (0: not rounded)
  double nearest = 0;         ///< depths nearer than this return nothing (world units)
  double farthest = 0;        ///< depths farther than this return nothing (0: any)
  double grazingCos = 0;      ///< no return where the ray meets the surface below this cosine
  double darkShare = 0;       ///< share of the surface (in cells of darkCell) that returns nothing
  double darkCell = 0;        ///< side of those cells, world units
  double edgeHoles = 0;       ///< chance a pixel within a pixel of a depth edge has no depth
  double flying = 0;          ///< chance such a pixel takes a depth between the edge's sides
  int blankColumns = 0;       ///< the rightmost columns of a 640-wide image carry no depth
  double rollingShutter = 0;  ///< frame intervals the rows are read over, top to bottom
  double timeOffset = 0;      ///< frame intervals the depth is taken after its reported pose
  bool shadows = true;        ///< no return where the projector cannot see (needs a baseline)

  /// True when the model applies (a baseline is set).
  bool active() const { return baseline > 0; }

  /// A named sensor: "kinect" (calibrated against 7-Scenes' Kinect v1 frames) or "none".
  /// Lengths are metres: scale the scene to metres. Throws InputError for another name.
  static DepthSensorModel preset(const std::string& name);

  /// The same without the faults named in `list` (comma-separated faultNames()), to find out
  /// which of them costs what. Throws InputError naming an unknown one.
  DepthSensorModel without(const std::string& list) const;
};

/// The names DepthSensorModel::without takes, in words ("noise, steps, ... or offset"):
/// disparity noise, disparity steps, projector shadows, grazing rays, dark surface, edge holes
/// and mixed returns, the blank band, the working range, the rolling shutter, the time offset.
std::string faultNames();

/// Whether a surface point is on a dark cell (no return): a hash of its cell of side
/// `m.darkCell`, the same from every view.
bool onDarkSurface(double x, double y, double z, const DepthSensorModel& m);

/// Applies the image's own faults to `depth` (cols x rows, row major, along the camera axis,
/// 0: no return): holes and mixed returns at depth edges, the blank columns, then disparity
/// noise and rounding for a focal length of `fx` pixels. Depths stay 0 where there is none.
void applyImageFaults(std::vector<double>& depth, int cols, int rows, double fx,
                      const DepthSensorModel& m, std::mt19937_64& rng);

}  // namespace rangefuse
