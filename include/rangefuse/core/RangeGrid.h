// A range image as read from a range-grid PLY: points on a rows x cols grid.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/Sensor.h"

namespace rangefuse {

/// Pinhole intrinsics in pixels (obj_info pinhole_fx/fy/cx/cy). The sensor sits at
/// the scan frame's origin looking toward -z.
struct Pinhole {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

/// Row r grows with +y, column c with +x; the sensor is on the +z side.
struct RangeGrid {
  int cols = 0;
  int rows = 0;
  std::vector<Eigen::Vector3d> points;       ///< in the scan frame
  std::vector<int32_t> cell;                 ///< rows*cols entries: point index or -1
  std::vector<Colour> colours;               ///< empty, or one per point
  ColourKind colourKind = ColourKind::none;  ///< what `colours` holds
  std::optional<Pinhole> pinhole;
  bool spherical = false;  ///< a scanner station at the origin (PTX): rows and columns are angles

  int32_t at(int r, int c) const { return cell[static_cast<size_t>(r) * cols + c]; }

  /// The sensor in the scan frame: a pinhole or a station at the origin, else looking along -z.
  Sensor sensor() const { return Sensor{pinhole.has_value() || spherical}; }

  /// Unit direction from point p toward the sensor.
  Eigen::Vector3d towardSensor(const Eigen::Vector3d& p) const { return sensor().toward(p); }
};

/// The number of column bands for a grid of cols x rows cells: 1 up to maxCells (0: always 1),
/// else enough that each holds about maxCells, with at least kMinBandColumns columns each.
int bandCount(int cols, int rows, uint64_t maxCells);

/// Bands narrower than this would read more halo than cells of their own.
constexpr int kMinBandColumns = 128;

}  // namespace rangefuse
