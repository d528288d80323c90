// The tracking stage of a fuse run over a depth stream: options, progress lines and the
// trajectory around trackFrames.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Tracking.h"
#include "rangefuse/track/LoopClosure.h"

namespace rangefuse {

/// True when a run tracks its frames: `track` is "on", or "auto" and the scans have no
/// trajectory. Throws InputError naming `scans` when they need tracking and `track` is "off".
bool tracksFrames(const std::string& track, bool posed, const std::string& scans);

/// The camera pose "tx,ty,tz,qx,qy,qz,qw" (camera to world). Throws InputError naming --first-pose.
Pose parseCameraPose(const std::string& text);

/// When key frames are kept and loops closed: the stream's settings, the voxel and the prism
/// envelope (world units).
LoopSettings loopSettings(const StreamSettings& track, double voxel, double eps);

/// How each frame is fitted: the stream's settings, the control points' stride, the voxel and
/// the prism envelope (world units).
TrackerSettings trackingSettings(const StreamSettings& track, int controlStride, double voxel,
                                 double eps);

/// Collective: the frames of the stream listed in `scans` (names, paths, times, readers), none
/// read yet: each is read by its reader when tracking comes to it. False on failure (printed).
bool openStream(const RunSettings& settings, MPI_Comm comm, Progress& progress, LoadedScans& scans);

/// Collective: tracks the frames of `scans` (their poses updated; lost frames keep the last
/// good pose and are marked in `lost`), printing a line per frame on rank 0, and leaves the
/// tracked field in `field`. With --checkpoint, the stream's progress is checkpointed between
/// frames (every --checkpoint-every seconds); `resumed`, a checkpoint at stage "tracking",
/// continues a stream from its next frame. False when any rank failed or tracking was lost
/// (printed once).
bool trackStream(const RunSettings& settings, MPI_Comm comm, Progress& progress, LoadedScans& scans,
                 std::vector<char>& lost, FusedField& field, RankCounters& counters,
                 const io::CheckpointMeta* resumed = nullptr);

/// Collective: rank 0 writes the camera trajectory of the frames not lost to `path` (TUM text,
/// or .log by extension). False on failure (printed once).
bool writeTrajectoryFile(const std::string& path, const LoadedScans& scans,
                         const std::vector<char>& lost, MPI_Comm comm);

}  // namespace rangefuse
