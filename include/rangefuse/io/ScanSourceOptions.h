// How a scan list is read beyond its own contents: the settings `fuse --scan-format`,
// `--intrinsics`, `--depth-max` and `--depth-scale` set, and the library's Fusion::addScans,
// described once (settings()).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "rangefuse/core/Setting.h"

namespace rangefuse::io {

/// The values of --scan-format: auto (from the path), then one per kind of scan list.
inline constexpr std::array<const char*, 7> kScanFormats = {"auto", "conf",    "ptx",    "e57",
                                                            "tum",  "redwood", "7scenes"};

/// kScanFormats in words: "auto, conf, ptx, e57, tum, redwood or 7scenes".
std::string scanFormatWords();

/// How to read a scan list beyond its own contents.
struct ScanSourceOptions {
  std::string format = "auto";  ///< one of kScanFormats
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
