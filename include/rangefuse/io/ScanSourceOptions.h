// How a scan list is read beyond its own contents: the settings `fuse --scan-format`,
// `--intrinsics`, `--depth-max` and `--depth-scale` set, and the library's Fusion::addScans.
#pragma once

#include <string>

namespace rangefuse::io {

/// How to read a scan list beyond its own contents.
struct ScanSourceOptions {
  std::string format = "auto";  ///< auto (from the path), conf, ptx, tum or redwood
  std::string intrinsics;       ///< depth cameras: "fx,fy,cx,cy" or a json file ("": the folder's)
  double maxDepth = 0;          ///< depth cameras: farther measurements are dropped (0: none)
  double depthScale = 0;        ///< depth images: counts per metre (0: the layout's own)
};

}  // namespace rangefuse::io
