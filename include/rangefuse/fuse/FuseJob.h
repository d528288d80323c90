// The main job: scans + poses -> prism fields on distributed bricks -> stitched mesh. The
// options are the table's (FuseParameters.h); runFuse turns them into each stage's settings
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
#include "rangefuse/fuse/HeldScans.h"
#include "rangefuse/fuse/Progress.h"
#include "rangefuse/fuse/TrackingSummary.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

struct FuseOptions {
  std::string scans;             ///< .conf, .ptx or depth-sequence folder
  io::ScanSourceOptions source;  ///< how to read it (format, depth cameras)
  std::string out;               ///< mesh .ply
  std::string report;            ///< run report .json (optional)
  std::string preview;           ///< rendered picture .png (optional)
  std::string previewView;       ///< "AZIMUTH,ELEVATION" of --preview ("": chosen by the scans)
  std::string up = "auto";       ///< the world's up axis of previews: y, z or auto
  FieldMethod method = FieldMethod::Prism;
  std::string colour = "auto";  ///< auto, rgb, intensity or none
  double voxel = 0;             ///< in the scans' units
  double envelope = 3.0;        ///< prism half-thickness, in voxels
  int brick = 8;                ///< voxels per brick edge
  float minWeight = 0.0f;       ///< voxels with summed weight not above this are unobserved
  bool normals = true;          ///< write vertex normals
  bool quiet = false;           ///< print nothing but warnings and errors
  bool verbose = false;         ///< print every registration fit and tracked frame
  SurfaceOptions surface;       ///< mergeTarget is set from mergeCells: see surfaceOptions
  double mergeCells = 1;        ///< merge grid cells up to this many voxels (0: never)
  double smoothNoise = 1;       ///< smooth depths noisier than this many voxels (0: never)
  double bandCells = 4e6;       ///< PTX scans of more cells are read in bands by several ranks
  double quorum = -1;           ///< consensus: summed confidence needed; -1: autoQuorum
  int minViews = 2;             ///< consensus: views a consensus needs (1: the quorum alone)
  double edgeAngle = 78;        ///< consensus: beyond this angle from the normal, beside an edge
  double sameDistance = 2.0;    ///< consensus: delta_d, voxels
  double sameAngle = 45.0;      ///< consensus: theta_n, degrees
  double freeMargin = -1;       ///< robust: looked-through depth, voxels (-1: the envelope)
  bool fillHoles = false;       ///< close the mesh by carving the space the scans saw through
  RegistrationMode registration = RegistrationMode::None;
  std::string anchor;           ///< scan name that fixes the frame (default: the first)
  int controlStride = 1;        ///< registration: every k-th vertex is a control point
  int maxIterations = 100;      ///< registration: fits per scan (per round in Alg. 2)
  int maxRounds = 8;            ///< registration: field rebuilds in Algorithm 2
  double roundTolerance = 0.1;  ///< registration: Algorithm 2 ends below this, voxels
  RegistrationFieldMode registerField = RegistrationFieldMode::Grow;  ///< registration
  RegistrationSolve registerSolve = RegistrationSolve::Joint;         ///< registration
  std::string posesOut;        ///< refined poses .conf (optional)
  std::string track = "auto";  ///< depth streams: on, off, auto (on when there is no trajectory)
  std::string firstPose;       ///< tracking: the first camera's pose "tx,ty,tz,qx,qy,qz,qw"
  double minInliers = 0.25;    ///< tracking: share of a frame's points that must find the field
  double maxStep = 10;         ///< tracking: how far from its prediction a frame may land, voxels
  bool skipLost = false;       ///< tracking: leave lost frames out and go on
  std::string trajectoryOut;   ///< camera trajectory, TUM text or .log (optional)
  int previewEvery = 0;        ///< tracking: --preview from the current camera every N frames
  bool follow = false;         ///< tracking: read frames that appear while the stream runs
  double followTimeout = 10;   ///< tracking: --follow ends after this long with no new frame, s
  std::string checkpoint;      ///< HDF5 checkpoint to write (optional)
  std::string resume;          ///< HDF5 checkpoint to continue from (optional)
  bool overwrite = false;      ///< replace an existing --checkpoint that is not resumed
  std::string config;          ///< the --config file the options came from (an input)
  double checkpointEvery = 0;  ///< seconds between registration checkpoints (0: each)
  InputLimits limits;          ///< refuse input that would need more memory than this
  double scanMemory = 1024;    ///< MiB of prepared scans a rank keeps between passes
  int threads = 0;             ///< threads per rank (0: its CPUs shared on the node)
  std::vector<std::string>
      givenOptions;  ///< options the user set (the rest may come from a checkpoint)
};

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
