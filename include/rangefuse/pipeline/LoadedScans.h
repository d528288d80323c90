// The scans of a run as read: names, files, poses and which rank holds each.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/io/Conf.h"
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
  /// Appends a scan of the list: its name, file, pose and time, read by rank `reader`.
  void add(const io::ConfScan& scan, int reader) {
    readers.push_back(reader);
    names.push_back(scan.name);
    paths.push_back(scan.path);
    poses.push_back(scan.pose);
    times.push_back(scan.time);
  }
};

/// The rank that reads the i-th scan of a list on `ranks` ranks: scans are dealt out in turn,
/// so each rank reads a share and which one is known without asking.
inline int readerOf(size_t i, int ranks) {
  return static_cast<int>(i % static_cast<size_t>(ranks));
}

}  // namespace rangefuse
