// What one rank did in a run, gathered into the run report.
#pragma once

#include <cstdint>

#include "rangefuse/robust/SurfaceHypotheses.h"

namespace rangefuse {

/// Per-rank counters of a run, gathered into the report.
struct RankCounters {
  uint64_t bricks = 0, prisms = 0, voxelUpdates = 0, haloBricks = 0, triangles = 0;
  uint64_t evaluatedPoints = 0;  ///< consensus and naive: distance evaluations
  uint64_t routedBytes = 0;      ///< streamed: scan bytes this rank sent to other ranks
  /// Prism fields: the voxel updates the planner's cost model gave this rank's bricks (their
  /// work over kWorkPerUpdate, prism set-up included), and the seconds the rank spent adding
  /// images to them (its own work, not waiting for other ranks).
  uint64_t predictedUpdates = 0;
  double addSeconds = 0;
  /// Streamed prism fields: seconds the rank spent predicting its prisms' cost for the brick
  /// plan (its own work), and routing its scans to the brick owners (waits for them included).
  double planSeconds = 0, routeSeconds = 0;
  /// Tracked streams: seconds the rank spent waiting for frames to be read, fitting them and
  /// adding them (FrameReport's, summed; waits for other ranks included).
  double trackReadSeconds = 0, trackFitSeconds = 0, trackAddSeconds = 0;
  HypothesisStats robust;  ///< robust: how this rank's voxels were decided
};

}  // namespace rangefuse
