// The scans of a run as read: names, files, poses and which rank holds each.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/pipeline/HeldScans.h"

namespace rangefuse {

/// Scans as read: each in its own frame, with its name and current pose.
struct LoadedScans {
  std::vector<std::string> names;
  std::vector<std::string> paths;
  std::shared_ptr<HeldScans> held;  ///< the scans this rank read (registration)
  std::vector<Pose> poses;
  std::vector<int> readers;              ///< the rank holding each scan
  int rank = 0;                          ///< this rank
  std::vector<double> times;             ///< depth frames: their times, seconds
  bool posed = true;                     ///< false for a depth stream without a trajectory
  ColourKind colour = ColourKind::none;  ///< tracked streams: what their frames bring to fuse

  bool holds(size_t i) const { return readers[i] == rank; }
};

}  // namespace rangefuse
