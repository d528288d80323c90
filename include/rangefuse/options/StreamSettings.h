// The settings of a depth stream tracked without poses, each described once (settings()).
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Setting.h"

namespace rangefuse {

/// Depth streams: whether to track them, from where, and when a frame is lost.
struct StreamSettings {
  std::string track = "auto";  ///< on, off, auto (on when there is no trajectory)
  std::string firstPose;       ///< "tx,ty,tz,qx,qy,qz,qw" (empty: the identity)
  double minInliers = 0.25;    ///< share of a frame's points that must find the field
  double maxStep = 10;         ///< how far from its prediction a frame may land, voxels
  bool skipLost = true;        ///< leave lost frames out and go on (false: stop at the first)
  bool closeLoops = false;     ///< keep key frames and close loops between them
  bool follow = false;         ///< read frames that appear while the stream runs
  double followTimeout = 10;   ///< --follow ends after this long with no new frame, seconds
  int previewEvery = 0;        ///< frames between previews (0: none)

  /// Every setting above, in --help's order.
  static const std::vector<Setting<StreamSettings>>& settings();
  /// Throws InputError with the message the fuse command gives for the first bad value.
  void validate() const;
};

inline void StreamSettings::validate() const {
  validateSettings(settings(), *this);
}

}  // namespace rangefuse
