// The scans a job reads, whatever files hold them: a Stanford .conf naming range-grid PLY files
// (or scans of PTX files, as FILE.ptx#K, or depth images), a Leica PTX file, or a folder holding
// a depth-image sequence (TUM RGB-D or Redwood layout).
#pragma once

#include <string>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/ScanSourceOptions.h"

namespace rangefuse::io {

/// The scans `path` lists: a .ptx file gives all its scans, named FILE.ptx#1, #2, ..., posed by
/// their transforms; a folder is a depth-image sequence, one scan per frame, named by its image;
/// anything else is read as a .conf, whose FILE.ptx#K names are looked up in their files and
/// whose .png names are depth images of the sequence folder above them. Throws InputError
/// naming the file at fault.
ConfFile readScanList(const std::string& path, const InputLimits& limits = {},
                      const ScanSourceOptions& source = {});

/// Every file reading the list `path` may open, found without opening a scan: the list itself,
/// the files a .conf names, or every file under a sequence folder (and under the sequence
/// folder of a depth image a .conf names). A list that cannot be read gives its own path only:
/// reading it later says what is wrong.
std::vector<std::string> scanListFiles(const std::string& path);

/// Marks every PTX and E57 scan of `conf` to be read with its intensity where it also has
/// colour (--colour intensity on a station that recorded both).
void preferIntensity(ConfFile& conf);

/// Forgets every depth frame's colour image, so that a job fusing no colour decodes none.
void dropColourImages(ConfFile& conf);

/// The list with each PTX scan of more than maxCells cells (0: none) made several entries, one
/// per band of columns (ColumnBands.h), in order, sharing the scan's name, file and pose.
ConfFile splitIntoBands(const ConfFile& conf, uint64_t maxCells);

/// What took a listed scan, told by its file: a scanner station (PTX), a depth camera (a depth
/// image) or a range grid seen from outside (PLY). A scan's name (FILE.ptx#K) is told alike.
enum class SensorKind { grid, station, camera };
SensorKind sensorKindOf(const std::string& path);

/// The grid of one listed scan, in its own frame (not of a band: that is read by columns).
RangeGrid readScanGrid(const ConfScan& scan, const InputLimits& limits = {});

}  // namespace rangefuse::io
