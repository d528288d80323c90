#include "rangefuse/fuse/TrackStage.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/fuse/TrackingField.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/Trajectory.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

using mpi::collectively;

bool tracksFrames(const std::string& track, bool posed, const std::string& scans) {
  if (!posed && track == "off")
    throw InputError(scans +
                     ": a depth stream without a trajectory (no groundtruth.txt or .log) needs "
                     "tracking: leave out --track off");
  return track == "on" || (track == "auto" && !posed);
}

Pose parseCameraPose(const std::string& text) {
  std::vector<double> v;
  std::istringstream in(text);
  std::string word;
  bool numbers = true;
  while (std::getline(in, word, ',')) {
    char* end = nullptr;
    v.push_back(std::strtod(word.c_str(), &end));
    numbers &= !word.empty() && *end == '\0' && std::isfinite(v.back());
  }
  if (v.size() != 7 || !numbers)
    throw InputError("--first-pose " + text + ": expected 7 numbers 'tx,ty,tz,qx,qy,qz,qw'");
  const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  if (std::abs(q.norm() - 1) > 0.01)
    throw InputError("--first-pose " + text + ": the quaternion is not of unit length");
  return Pose{q.normalized().toRotationMatrix(), Eigen::Vector3d(v[0], v[1], v[2])};
}

namespace {

TrackingSettings trackingSettings(const FuseOptions& o) {
  TrackingSettings s;
  RegistrationOptions& f = s.fit;
  f.controlStride = o.controlStride;
  f.rotationTolDeg = 0.01;
  f.translationTol = 0.01 * o.voxel;
  f.correspondences.maxDistance = o.envelope * o.voxel;
  f.correspondences.huber = o.voxel;
  f.maxExtrapolation = o.voxel;
  s.minInliers = o.minInliers;
  s.maxStep = o.maxStep * o.voxel;
  s.skipLost = o.skipLost;
  return s;
}

/// Every frame at the first camera's pose, or (a trajectory guides the tracking) the given poses
/// moved so that the first is there: the guide's relative motion is kept.
std::vector<Pose> startingPoses(const FuseOptions& o, const LoadedScans& scans) {
  const Pose first = io::scanPose(o.firstPose.empty() ? Pose{} : parseCameraPose(o.firstPose));
  std::vector<Pose> poses(scans.poses.size(), first);
  if (!scans.posed) return poses;
  const Pose shift{first.R * scans.poses[0].R.transpose(),
                   first.t - first.R * scans.poses[0].R.transpose() * scans.poses[0].t};
  for (size_t i = 0; i < poses.size(); ++i)
    poses[i] = Pose{shift.R * scans.poses[i].R, shift.R * scans.poses[i].t + shift.t};
  return poses;
}

/// Prints one frame's line on rank 0.
class FrameLines {
 public:
  FrameLines(const LoadedScans& scans, double voxel) : scans_(scans), voxel_(voxel) {}

  void operator()(const FrameReport& r) {
    ++done_;
    const double seconds = MPI_Wtime() - start_;
    std::printf(
        "[track] %zu/%zu %-24s %s fits %2d inliers %3.0f%% rms %.2f vox step %.2f vox "
        "%.2f deg  %.1f frames/s%s%s\n",
        r.frame + 1, scans_.names.size(), scans_.names[r.frame].c_str(),
        r.fused ? "fused" : "LOST ", r.fits, 100 * r.inliers, r.rms / voxel_, r.step / voxel_,
        r.turnDeg, seconds > 0 ? done_ / seconds : 0.0,
        r.recovered ? "  (re-localised from the last good pose)" : "",
        r.fused ? "" : ("  " + r.why).c_str());
    std::fflush(stdout);
  }

 private:
  const LoadedScans& scans_;
  double voxel_;
  double start_ = MPI_Wtime();
  size_t done_ = 0;
};

}  // namespace

bool trackStream(const FuseOptions& o, MPI_Comm comm, Progress& progress, LoadedScans& scans,
                 std::vector<char>& lost, FusedField& field, RankCounters& counters) {
  TrackingSettings settings;
  std::vector<Pose> guide;
  if (!collectively(comm, [&] {
        settings = trackingSettings(o);
        if (scans.posed) guide = scans.poses;
        scans.poses = startingPoses(o, scans);
      }))
    return false;
  const TrackingFieldSettings fieldSettings{o.voxel, o.brick, o.envelope * o.voxel,
                                            o.limits.maxVoxels, o.threads};
  TrackingField tracked(fieldSettings, scans, comm);
  TrackingState state;
  FrameLines lines(scans, o.voxel);
  size_t lostCount = 0;
  bool ok = false;
  try {
    ok = trackFrames(
        *scans.held, scans.poses, scans.posed ? &guide : nullptr, settings, tracked, comm, state,
        [&](const FrameReport& r) {
          lostCount += !r.fused;
          if (progress.isRoot()) lines(r);
        },
        [](const TrackingState&) {});
  } catch (const mpi::Reported&) {
    return false;
  }
  lost = state.lost;
  if (!ok) {
    if (progress.isRoot())
      std::fprintf(stderr, "rangefuse: error: %s: %s%s\n", scans.paths[state.failedFrame].c_str(),
                   state.failure.c_str(),
                   o.skipLost ? "" : " (--skip-lost leaves such frames out and goes on)");
    return false;
  }
  field.scanCount = scans.names.size() - lostCount;
  counters.voxelUpdates = tracked.voxelUpdates();
  field.store = tracked.release();
  field.layout = field.store->layout();
  counters.bricks = field.store->brickCount();
  progress.stage("track", std::to_string(field.scanCount) + " of " +
                              std::to_string(scans.names.size()) + " frames tracked and fused" +
                              (lostCount ? ", " + std::to_string(lostCount) + " lost and left out"
                                         : std::string()) +
                              "; " + std::to_string(field.layout.codes.size()) + " bricks");
  return true;
}

bool writeTrajectoryFile(const std::string& path, const LoadedScans& scans,
                         const std::vector<char>& lost, MPI_Comm comm) {
  if (path.empty()) return true;
  return collectively(comm, [&] {
    if (mpi::rank(comm) != 0) return;
    std::vector<io::TimedPose> out;
    for (size_t i = 0; i < scans.poses.size(); ++i)
      if (lost.empty() || !lost[i]) out.push_back({scans.times[i], io::cameraPose(scans.poses[i])});
    io::writeTrajectory(path, out);
  });
}

}  // namespace rangefuse
