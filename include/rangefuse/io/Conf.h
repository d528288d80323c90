// Stanford .conf scan lists: `bmesh FILE tx ty tz qx qy qz qw`.
#pragma once

#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/E57.h"
#include "rangefuse/io/Ptx.h"

namespace rangefuse::io {

/// A scan handed over in memory: a grid as it is or, for a scan with a depth camera, a depth
/// image (and a colour image registered to it, or none) that becomes a grid when read, so that
/// the ranks' readers convert frames in parallel as they convert files.
struct MemoryScan {
  RangeGrid grid;
  DepthImage depth;
  Image colour;
};

struct ConfScan {
  std::string name;  ///< as written in the .conf
  std::string path;  ///< resolved against the .conf's folder
  Pose pose;         ///< scan to world
  /// Set for one scan of a PTX file (named FILE.ptx#K in a .conf; `path` is then the file's).
  std::optional<PtxScan> ptx = std::nullopt;
  /// Set for a depth image (16-bit PNG) of a sequence: the camera that took it.
  std::optional<DepthCamera> depth = std::nullopt;
  /// A PTX scan too large for one rank is read as `bands` bands of columns; this is `band`.
  int band = 0, bands = 1;
  /// A depth frame's time in seconds (TUM: its timestamp; Redwood: its index / 30).
  double time = 0;
  /// A depth frame's colour image (8-bit PNG, registered to the depth), resolved; empty: none.
  std::string colour = {};
  /// Set for one scan of an E57 file (named FILE.e57#K in a .conf; `path` is then the file's).
  std::optional<E57Scan> e57 = std::nullopt;
  /// Set for a scan handed over in memory (the library's frames): read from here, not `path`.
  std::shared_ptr<const MemoryScan> memory = nullptr;
};

struct ConfFile {
  std::vector<ConfScan> scans;
  std::vector<std::string> warnings;  ///< e.g. skipped `mesh` lines
  /// False for a depth sequence without a trajectory: every pose is the first camera's, and the
  /// frames must be tracked.
  bool posed = true;
};

/// Reads a .conf in the Stanford convention p_world = R(q)^T p + t (measured on the bunny).
/// Throws InputError naming the file and line; does not open the scan files.
ConfFile readConf(const std::string& path);

/// The same from a stream; `path` heads every message and scan names resolve against its folder.
ConfFile parseConf(const std::string& path, std::istream& in);

/// Writes scans in the same convention, so that readConf gives back the same transforms and
/// files: a scan with a resolved path is named relative to the new file's folder (nameFor),
/// one without keeps its name.
void writeConf(const std::string& path, const std::vector<ConfScan>& scans);

/// The name a .conf at `confPath` gives the scan `name` that resolves to `path`: `path`
/// relative to that .conf's folder, with the name's scan suffix (`#K` of a PTX file) kept; an
/// absolute name unchanged.
std::string nameFor(const std::string& name, const std::string& path, const std::string& confPath);

}  // namespace rangefuse::io
