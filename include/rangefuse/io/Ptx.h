// Leica PTX (ASCII) terrestrial laser scans: one or more scans a file, each a header (columns,
// rows, scanner position, scanner X/Y/Z axes, a 4 x 4 transform with the translation in its
// last row: world = [x y z 1] M) and columns x rows lines "x y z intensity [r g b]",
// column-major, "0 0 0" where the laser saw nothing. Files reach gigabytes: they are indexed in
// one streaming pass and each scan is read on its own, never the whole file at once.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::io {

/// Where one scan of a PTX file lies and how it is placed.
struct PtxScan {
  uint64_t offset = 0;  ///< byte offset of its first point line
  uint64_t line = 0;    ///< line number of its first point line (from 1), for messages
  int cols = 0, rows = 0;
  Pose pose;                      ///< scanner frame to world, from the transform
  std::vector<uint64_t> columns;  ///< byte offset of each column's first point line
  uint64_t end = 0;               ///< byte offset just past the scan's last point line
  bool intensity = false;  ///< read the intensity even where lines give r g b (--colour intensity)
};

/// The scans of a PTX file: headers parsed, point lines counted but not parsed. Throws
/// InputError naming the file and line for a malformed header, a scan cut short or a grid
/// larger than `limits`.
std::vector<PtxScan> indexPtx(const std::string& path, const InputLimits& limits = {});

/// Reads one scan of a PTX file as a spherical grid (points in the scanner frame; row r, column
/// c is file line c·rows + r of the scan), each point coloured by its line's r g b (0-255;
/// colourKind rgb when any line has them), else by its intensity (colourKind intensity;
/// [0, 1] as it is, else read as [-2048, 2047]). Throws InputError naming the file and line for a
/// line without 4 or 7 numbers, a non-finite number, or an early end.
RangeGrid readPtxScan(const std::string& path, const PtxScan& scan);

/// Columns [first, first + count) of one scan as a spherical grid of `count` columns, read from
/// their own bytes only (the index's column offsets), with readPtxScan's checks.
RangeGrid readPtxColumns(const std::string& path, const PtxScan& scan, int first, int count);

/// Writes scans (each grid's missing cells as "0 0 0") with their poses; the scanner position
/// and axes are the pose's; a grid's colours as r g b (rgb) or intensity, else intensity 0.5.
/// Atomic.
void writePtx(const std::string& path, const std::vector<RangeGrid>& grids,
              const std::vector<Pose>& poses);

}  // namespace rangefuse::io
