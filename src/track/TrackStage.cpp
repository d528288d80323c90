#include "rangefuse/track/TrackStage.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <future>
#include <memory>
#include <sstream>

#include "FollowedFolder.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/DepthPng.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/io/Trajectory.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/pipeline/Checkpointing.h"
#include "rangefuse/pipeline/RunLines.h"
#include "rangefuse/pipeline/VoxelCheck.h"
#include "rangefuse/register/ProjectiveIcp.h"
#include "rangefuse/render/Render.h"
#include "rangefuse/track/LoopClosure.h"
#include "rangefuse/track/PixelMotion.h"
#include "rangefuse/track/StreamColour.h"
#include "rangefuse/track/TrackingField.h"

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

LoopSettings loopSettings(const StreamSettings& t, double voxel, double eps) {
  LoopSettings s;
  s.enabled = t.closeLoops;
  s.voxel = voxel;
  s.eps = eps;
  return s;
}

TrackerSettings trackingSettings(const StreamSettings& t, int controlStride, double voxel,
                                 double eps) {
  TrackerSettings s;
  FitControl& f = s.fit;
  f.controlStride = controlStride;
  f.rotationTolDeg = 0.01;
  f.translationTol = 0.01 * voxel;
  f.correspondences.maxDistance = eps;
  f.correspondences.huber = voxel;
  f.maxExtrapolation = voxel;
  s.minInliers = t.minInliers;
  s.maxStep = t.maxStep * voxel;
  s.skipLost = t.skipLost;
  // A voxel's rounding error, the field's own: points noisier than that weigh less.
  s.noiseFloor = voxel / std::sqrt(12.0);
  return s;
}

namespace {

/// Every frame at the first camera's pose, or (a trajectory guides the tracking) the given poses
/// moved so that the first is there: the guide's relative motion is kept.
std::vector<Pose> startingPoses(const std::string& firstPose, const LoadedScans& scans) {
  const Pose first = io::scanPose(firstPose.empty() ? Pose{} : parseCameraPose(firstPose));
  std::vector<Pose> poses(scans.poses.size(), first);
  if (!scans.posed) return poses;
  const Pose shift{first.R * scans.poses[0].R.transpose(),
                   first.t - first.R * scans.poses[0].R.transpose() * scans.poses[0].t};
  for (size_t i = 0; i < poses.size(); ++i) poses[i] = shift * scans.poses[i];
  return poses;
}

/// The frames of a stream on their readers: each read once, the next one this rank reads
/// prepared on a thread of its own while the frames before it are tracked (reading is a
/// rank's own work; tracking a frame makes every rank wait in turn on the others).
class FrameReader {
 public:
  FrameReader(LoadedScans& scans, MPI_Comm comm) : scans_(scans), comm_(comm) {}
  ~FrameReader() {
    if (ahead_.valid()) ahead_.wait();
  }

  /// Waits for a read ahead still under way (before the list of frames grows).
  void settle() {
    if (ahead_.valid()) ahead_.wait();
  }

  /// Collective: frame i is about to be tracked (done false) or has been (done true).
  void operator()(size_t i, bool done) {
    if (done) return scans_.held->release(i);
    mpi::collectivelyOrThrow(comm_, [&] {
      if (!scans_.holds(i)) return;
      if (ahead_.valid() && aheadFrame_ == i)
        scans_.held->offer(i, ahead_.get());
      else
        scans_.held->readAndOffer(i);
      readAhead(i);
    });
  }

 private:
  /// Starts reading the next frame after i that this rank reads.
  void readAhead(size_t i) {
    for (size_t j = i + 1; j < scans_.names.size(); ++j)
      if (scans_.holds(j)) {
        aheadFrame_ = j;
        const HeldScans* held = scans_.held.get();
        ahead_ = std::async(std::launch::async, [held, j] {
          const IdleWorker idle;  // in the time the rank waits for its peers
          return held->get(j);
        });
        return;
      }
  }

  LoadedScans& scans_;
  MPI_Comm comm_;
  std::future<std::shared_ptr<const PrismScan>> ahead_;
  size_t aheadFrame_ = 0;
};

/// "40 key frames, 3 loops measured, 1 closed (0.52 s)".
std::string loopLine(const LoopClosure& loops) {
  char text[120];
  std::snprintf(text, sizeof text, "%zu key frames, %zu loops measured, %zu closed (%.2f s)",
                loops.keyFrames(), loops.loops(), loops.closures(), loops.seconds());
  return text;
}

/// Prints frames' lines on rank 0: every frame, or (not `everyFrame`) a frame a second, every
/// lost or re-localised frame and the last.
class FrameLines {
 public:
  FrameLines(const LoadedScans& scans, double voxel, bool everyFrame)
      : scans_(scans), voxel_(voxel), everyFrame_(everyFrame) {}

  void operator()(const FrameReport& r) {
    ++done_;
    const double now = MPI_Wtime(), seconds = now - start_;
    if (!everyFrame_ && r.fused && !r.recovered && !r.closedLoop && now - lastLine_ < 1 &&
        r.frame + 1 < scans_.names.size())
      return;
    lastLine_ = now;
    std::printf(
        "[track] %zu/%zu %-24s %s fits %2d inliers %3.0f%% rms %.2f vox step %.2f vox "
        "%.2f deg  %.1f frames/s%s%s\n",
        r.frame + 1, scans_.names.size(), scans_.names[r.frame].c_str(),
        r.fused ? "fused" : "LOST ", r.fits, 100 * r.inliers, r.rms / voxel_, r.step / voxel_,
        r.turnDeg, seconds > 0 ? done_ / seconds : 0.0,
        r.recovered    ? "  (re-localised from the last good pose)"
        : r.closedLoop ? "  (closed a loop: the frames so far moved, the field built again)"
                       : "",
        r.fused ? "" : ("  " + r.why).c_str());
    std::fflush(stdout);
  }

 private:
  const LoadedScans& scans_;
  double voxel_;
  bool everyFrame_;
  double start_ = MPI_Wtime(), lastLine_ = -INFINITY;
  size_t done_ = 0;
};

/// Collective: the partial model seen from `camera` (a 320 x 240 view with a 60-degree field
/// of view, up to 1000 voxels deep), written to `path` by rank 0.
void previewFrom(const BrickStore& store, const Pose& camera, double voxel, float minWeight,
                 const std::string& path, MPI_Comm comm) {
  ViewSettings view;
  view.width = 320, view.height = 240;
  view.camera = camera;
  view.focal = 0.5 * view.width / std::tan(M_PI / 6);
  view.farthest = 1000 * voxel;
  const Image picture = renderDistributed(store, minWeight, view, 0, comm);
  mpi::collectivelyOrThrow(comm, [&] {
    if (mpi::rank(comm) == 0) io::writePng(path, picture);
  });
}

nlohmann::json toJson(const TrackingState& s) {
  std::vector<int> lost(s.lost.begin(), s.lost.end());
  return {{"next_frame", s.nextFrame},
          {"lost", lost},
          {"lost_in_row", s.lostInRow},
          {"lattice_origin", s.latticeOrigin},
          {"recent_inliers", s.recentInliers}};
}

/// A stream's state from its checkpoint; throws InputError naming the checkpoint when it does
/// not fit a stream of `frames` frames.
TrackingState trackingState(const io::CheckpointMeta& meta, size_t frames,
                            const std::string& checkpoint) {
  TrackingState s;
  try {
    const nlohmann::json& j = meta.progress.at("tracking");
    s.nextFrame = j.at("next_frame").get<size_t>();
    for (const int v : j.at("lost").get<std::vector<int>>()) s.lost.push_back(v ? 1 : 0);
    s.lostInRow = j.at("lost_in_row").get<int>();
    s.latticeOrigin = j.at("lattice_origin").get<std::vector<double>>();
    // A checkpoint written before the judge compared frames with the ones before has none.
    if (j.contains("recent_inliers"))
      s.recentInliers = j.at("recent_inliers").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(checkpoint + ": tracking progress unreadable (" + e.what() + ")");
  }
  if (s.nextFrame < 1 || s.nextFrame > frames || s.lost.size() != frames ||
      s.latticeOrigin.size() != 3 || meta.poses.size() != frames)
    throw InputError(checkpoint + ": its tracking progress does not fit this stream of " +
                     std::to_string(frames) + " frames");
  return s;
}

/// Writes a stream's progress (its poses so far and TrackingState) to --checkpoint between
/// frames, every --checkpoint-every seconds; every rank decides alike.
class StreamCheckpointer {
 public:
  StreamCheckpointer(CheckpointWriting c, const LoadedScans& scans, const LoopClosure& loops,
                     MPI_Comm comm)
      : c_(std::move(c)), scans_(scans), loops_(loops), comm_(comm), last_(MPI_Wtime()) {
    MPI_Bcast(&last_, 1, MPI_DOUBLE, 0, comm_);
  }

  /// Collective; throws mpi::Reported when writing failed on any rank (printed once).
  void operator()(const TrackingState& state) {
    if (c_.path.empty()) return;
    double now = MPI_Wtime();
    MPI_Bcast(&now, 1, MPI_DOUBLE, 0, comm_);
    if (now - last_ < c_.every) return;
    last_ = now;
    mpi::collectivelyOrThrow(comm_, [&] {
      if (hashes_.size() < scans_.paths.size()) {  // a followed stream grew
        const std::vector<std::string> fresh(
            scans_.paths.begin() + static_cast<std::ptrdiff_t>(hashes_.size()), scans_.paths.end());
        const std::vector<std::string> more = hashScans(fresh, comm_);
        hashes_.insert(hashes_.end(), more.begin(), more.end());
      }
      nlohmann::json progress = {{"stage", "tracking"}, {"tracking", toJson(state)}};
      progress["tracking"]["loops"] = loops_.state();
      io::writeCheckpoint(c_.path, checkpointMeta(c_.recorded, scans_, hashes_, progress, nullptr),
                          nullptr, comm_);
    });
    faultPoint("checkpoint");  // tests stop a run right after a given checkpoint
  }

 private:
  const CheckpointWriting c_;
  const LoadedScans& scans_;
  const LoopClosure& loops_;
  MPI_Comm comm_;
  double last_;
  std::vector<std::string> hashes_;
};

/// The colour the tracking field fuses. When another field follows the tracking (refined
/// poses), that field reads the colour itself and the tracking field fuses none.
ColourKind trackedColour(const RunSettings& s, const io::ConfFile& conf) {
  if (s.registration.mode == RegistrationMode::Simultaneous) return ColourKind::none;
  StreamFrames frames;
  for (const io::ConfScan& scan : conf.scans) {
    frames.names.push_back(scan.path);
    frames.coloured.push_back(!scan.colour.empty());
  }
  frames.moreLater = s.track.follow;
  return streamColour(s.field, frames, s.read.scans);
}

/// The voxel checked against the first frame's extent, as scans are against theirs: a stream
/// in metres fused at --voxel 10 would otherwise only fail later as lost tracking.
void warnOfVoxel(const io::ConfFile& conf, const ReadSettings& o) {
  if (conf.scans.empty()) return;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : io::readScanGrid(conf.scans.front(), o.limits).points)
    box.extend(p);
  const std::string slip = voxelUnitWarning(o.voxel, box);
  if (!slip.empty())
    std::fprintf(stderr, "rangefuse: warning: %s: %s\n", conf.scans.front().path.c_str(),
                 slip.c_str());
}

}  // namespace

bool openStream(const RunSettings& s, MPI_Comm comm, Progress& progress, LoadedScans& scans) {
  const ReadSettings& o = s.read;
  io::ConfFile conf;
  if (s.track.follow) progress.stage("follow", o.scans + ": waiting for the first frames");
  if (!collectively(comm, [&] {
        conf = s.track.follow ? internal::FollowedFolder(o, s.track.followTimeout, comm).first()
                              : io::readScanList(o.scans, o.limits, o.source);
        scans.colour = trackedColour(s, conf);
        if (scans.colour == ColourKind::none) io::dropColourImages(conf);
      }))
    return false;
  if (progress.isRoot())
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
  if (!collectively(comm, [&] {
        if (progress.isRoot()) warnOfVoxel(conf, o);
      }))
    return false;
  scans.rank = mpi::rank(comm);
  scans.posed = conf.posed;
  for (size_t i = 0; i < conf.scans.size(); ++i)
    scans.add(conf.scans[i], readerOf(i, mpi::size(comm)));
  scans.held = heldScans(conf.scans, scans.readers, scans.rank, o);
  progress.stage("open", std::to_string(conf.scans.size()) + " frames, each read when it comes");
  return true;
}

bool trackStream(const RunSettings& s, MPI_Comm comm, Progress& progress, LoadedScans& scans,
                 std::vector<char>& lost, FusedField& field, RankCounters& counters,
                 const io::CheckpointMeta* resumed) {
  const FieldSettings& f = s.field;
  const StreamSettings& t = s.track;
  TrackerSettings settings;
  std::vector<Pose> guide;
  TrackingState state;
  if (!collectively(comm, [&] {
        settings = trackingSettings(t, s.registration.controlStride, f.voxel, f.eps());
        if (scans.posed) guide = scans.poses;
        scans.poses = startingPoses(t.firstPose, scans);
        if (!resumed) return;
        state = trackingState(*resumed, scans.names.size(), s.outputs.resume);
        checkScanHashes(*resumed, scans, hashScans(scans.paths, comm));
        scans.poses = resumed->poses;
      }))
    return false;
  if (resumed)
    progress.stage("resume", s.outputs.resume + ": tracking from frame " +
                                 std::to_string(state.nextFrame + 1) + " (the " +
                                 std::to_string(state.nextFrame) + " before fused again)");
  const TrackingLattice fieldSettings{f.voxel,     f.brick,   f.eps(),
                                      f.maxVoxels, f.threads, scans.colour};
  TrackingField tracked(fieldSettings, scans, comm);
  LoopClosure loops(loopSettings(t, f.voxel, f.eps()), *scans.held, comm);
  if (resumed && !collectively(comm, [&] {
        const nlohmann::json& j = resumed->progress.at("tracking");
        // A checkpoint written before loops were closed has no key frames.
        if (j.contains("loops")) loops.restore(j.at("loops"), s.outputs.resume);
      }))
    return false;
  StreamCheckpointer checkpointer(s.checkpoints(), scans, loops, comm);
  FrameLines lines(scans, f.voxel, progress.shows(Verbosity::verbose));
  FrameReader reader(scans, comm);
  internal::FollowedFolder folder(s.read, t.followTimeout, comm);
  std::unique_ptr<internal::PixelMotion> pixels;
  if (!collectively(
          comm, [&] { pixels = std::make_unique<internal::PixelMotion>(s.read, f.voxel, comm); }))
    return false;
  size_t lostCount = 0, fused = 0;
  TrackingSummary summary;
  bool ok = false;
  try {
    StreamCalls calls;
    calls.frame = [&](size_t i, bool done) { reader(i, done); };
    calls.motion = [&](size_t last, size_t next, const Pose& guess) {
      return (*pixels)(last, next, guess);
    };
    double lastOutcome = MPI_Wtime();
    calls.onFrame = [&](const FrameReport& r) {
      const double now = MPI_Wtime();
      summary.add(r, scans.paths[r.frame], now - lastOutcome);
      counters.trackReadSeconds += r.readSeconds;
      counters.trackFitSeconds += r.fitSeconds;
      counters.trackAddSeconds += r.addSeconds;
      lastOutcome = now;
      lostCount += !r.fused;
      if (progress.shows(Verbosity::normal)) lines(r);
      fused += r.fused;
      if (r.fused && t.previewEvery > 0 && fused % t.previewEvery == 0)
        previewFrom(tracked.store(), io::cameraPose(scans.poses[r.frame]), f.voxel,
                    s.mesh.minWeight, s.outputs.preview, comm);
    };
    calls.onBoundary = [&](const TrackingState& now) { checkpointer(now); };
    calls.closeLoops = [&](size_t i, std::vector<Pose>& poses, const BrickStore& field) {
      return loops.fused(i, poses, field);
    };
    calls.finishLoops = [&](std::vector<Pose>& poses) { return loops.finish(poses); };
    if (t.follow)
      calls.moreFrames = [&] {
        reader.settle();
        return folder.more(scans);
      };
    ok = trackFrames(*scans.held, scans.poses, scans.times, scans.posed ? &guide : nullptr,
                     settings, tracked, comm, state, calls);
  } catch (const mpi::Reported&) {
    return false;
  }
  lost = state.lost;
  if (!ok) {
    if (progress.isRoot())
      std::fprintf(stderr, "rangefuse: error: %s: %s%s\n", scans.paths[state.failedFrame].c_str(),
                   state.failure.c_str(),
                   t.skipLost ? "" : " (--skip-lost true leaves such frames out and goes on)");
    return false;
  }
  field.scanCount = scans.names.size() - lostCount;
  summary.setLoops(loops.keyFrames(), loops.loops(), loops.closures(), loops.seconds());
  field.tracking = summary;
  counters.voxelUpdates = tracked.voxelUpdates();
  counters.prisms = tracked.prisms();
  field.store = tracked.release();
  field.layout = field.store->layout();
  counters.bricks = field.store->brickCount();
  // How evenly the ranks shared the frames' voxels: the rank with fewer waits at every frame.
  const std::string updates = "voxels updated per rank " +
                              internal::perRank(comm, counters.voxelUpdates) +
                              internal::balance(comm, counters.voxelUpdates);
  progress.stage("track", std::to_string(field.scanCount) + " of " +
                              std::to_string(scans.names.size()) + " frames tracked and fused" +
                              (lostCount ? ", " + std::to_string(lostCount) + " lost and left out"
                                         : std::string()) +
                              "; " + std::to_string(field.layout.totalBricks()) + " bricks; " +
                              updates + "; " + summary.frameTimes() + "; " + loopLine(loops));
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
