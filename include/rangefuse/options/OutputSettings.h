// Where a fuse run writes and what it resumes from, each setting described once (settings()).
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Setting.h"

namespace rangefuse {

/// Where the run writes, and what it resumes from.
struct OutputSettings {
  std::string out;             ///< mesh .ply or .xdmf
  std::string report;          ///< run report .json (empty: none)
  std::string preview;         ///< rendered picture .png (empty: none)
  std::string previewView;     ///< "AZIMUTH,ELEVATION", or "" for the scans' own choice
  std::string up = "auto";     ///< the world's up axis of the preview: y, z or auto
  std::string posesOut;        ///< refined poses .conf (empty: none)
  std::string trajectoryOut;   ///< camera trajectory, TUM text or .log (empty: none)
  std::string checkpoint;      ///< HDF5 checkpoint to write (empty: none)
  double checkpointEvery = 0;  ///< seconds between registration and tracking checkpoints
  bool overwrite = false;      ///< an existing checkpoint not resumed may be replaced
  std::string resume;          ///< checkpoint the run continues from (empty: none)
  std::string config;          ///< the options file the run read (an input; empty: none)

  /// Every setting above a user gives (all but config), in --help's order.
  static const std::vector<Setting<OutputSettings>>& settings();
};

}  // namespace rangefuse
