// The main job: scans + poses -> prism fields on distributed bricks -> stitched mesh. The
// options are the table's (FuseParameters.h); runFuse completes them into the run's settings
// (RunSettings.h) once, then runs one of four paths: a streamed field at the given poses,
// registration then a streamed field, a tracked depth stream, or a resumed checkpoint.
#pragma once

#include <mpi.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "rangefuse/consensus/NearSurface.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/fuse/FieldMethod.h"
#include "rangefuse/fuse/FuseParameters.h"
#include "rangefuse/fuse/HeldScans.h"
#include "rangefuse/fuse/Progress.h"
#include "rangefuse/fuse/TrackingSummary.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

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

/// The fused field of one job: every rank holds its own bricks, and all scans only when the
/// field was built from replicated scans (registration, closest-surface methods).
struct FusedField {
  /// Every scan, placed; when streamed, empty (prism) or, while the closest-surface field is
  /// evaluated, the triangles routed to this rank.
  std::vector<PrismScan> scans;
  size_t scanCount = 0;
  uint64_t scanTriangles = 0;
  uint64_t routedBytes = 0, routedCopies = 0;  ///< streamed: all ranks, to other ranks
  BrickLayout layout;
  std::unique_ptr<BrickStore> store;
  /// --fill-holes: every scan's sight map (the same on every rank), for carving.
  std::vector<SightMap> sights;
  /// A tracked stream: its frames' outcomes (rank 0's, for the report).
  std::optional<TrackingSummary> tracking;
};

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
  HypothesisStats robust;  ///< robust: how this rank's voxels were decided
};

/// Runs the whole job on every rank of comm. Returns the process exit code: 0 on success, 1
/// when any rank failed (the failure is printed once, by the lowest failing rank).
int runFuse(const FuseOptions& options, MPI_Comm comm);

}  // namespace rangefuse
