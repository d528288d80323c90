// How a scan list is read beyond its own contents: the settings `fuse --scan-format`,
// `--intrinsics`, `--depth-max` and `--depth-scale` set, and the library's Fusion::addScans,
// described once (settings()).
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Setting.h"

namespace rangefuse::io {

/// How to read a scan list beyond its own contents.
struct ScanSourceOptions {
  std::string format = "auto";  ///< auto (from the path), conf, ptx, e57, tum or redwood
  std::string intrinsics;       ///< depth cameras: "fx,fy,cx,cy" or a json file ("": the folder's)
  double depthMax = 0;          ///< depth cameras: farther measurements are dropped (0: none)
  double depthScale = 0;        ///< depth images: counts per metre (0: the layout's own)

  /// Every setting above, in --help's order.
  static const std::vector<Setting<ScanSourceOptions>>& settings();
  /// Throws InputError with the message the fuse command gives for the first bad value.
  void validate() const;
};

inline void ScanSourceOptions::validate() const {
  validateSettings(settings(), *this);
}

}  // namespace rangefuse::io
