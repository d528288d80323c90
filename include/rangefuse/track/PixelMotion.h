// The motion between two depth frames from their pixels : the
// second start a tracked frame gets when the field's fit from the predicted pose fails.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <utility>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/register/ProjectiveIcp.h"

namespace rangefuse::internal {

/// Projective ICP between frames, computed by rank 0 alone and shared: the same bits on any
/// number of ranks, and each image decoded once (the later frame is the earlier one of the next
/// pair). Frames come from the run's list: `read.list` when set (frames in memory, a list that
/// may grow), else the folder `read.scans`, read again when a followed stream grows.
class PixelMotion {
 public:
  PixelMotion(const ReadSettings& read, double voxel, MPI_Comm comm);

  /// Collective: the motion from frame `last` to `next` (scan frames), starting from `guess`.
  Pose operator()(size_t last, size_t next, const Pose& guess);

 private:
  /// Frame i's depths in its camera (the last two kept: each frame is asked for twice).
  const DepthMap& depthMap(size_t i);

  MPI_Comm comm_;
  ReadSettings read_;
  std::shared_ptr<const io::ConfFile> list_;
  ProjectiveIcpSettings settings_;
  std::pair<size_t, DepthMap> cache_[2] = {{SIZE_MAX, {}}, {SIZE_MAX, {}}};
  int next_ = 0;
};

}  // namespace rangefuse::internal
