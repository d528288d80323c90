// Tracking a depth stream against the field (Tubic et al.'s self-referencing, Algorithm 1 run
// as the frames arrive): each frame starts where the camera's motion so far predicts, is fitted
// to the field of the frames before it, coarse control points then all, and joins that field
// only when the fit holds. Frames that do not fit are reported and left out.
#pragma once

#include <mpi.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// The frame tracker's parameters: its fits, levels and when a frame is lost (the user's are
/// StreamSettings, converted by the tracking stage).
struct TrackerSettings {
  FitControl fit;             ///< correspondences and the convergence rule of one fit
  int coarse = 4;             ///< the coarse level takes every coarse-th control point
  int coarseIterations = 12;  ///< fits at the coarse level
  int fineIterations = 12;    ///< fits with every control point
  double minInliers = 0.25;   ///< share of control points that must find the field
  /// A frame is lost when its inlier share falls below this times the median of the last
  /// kRecentFrames fused frames' (it does not belong where the fit put it).
  double inlierDrop = 0.6;
  /// The field's own error (world units): a control point weighs floor / (floor + sigma),
  /// sigma its frame's measured depth noise at its depth (0: evenly).
  double noiseFloor = 0;
  double maxResidual = 0;  ///< RMS residual a frame may keep, world units (0: any)
  double maxStep = 0;      ///< camera motion a frame may make, world units (0: any)
  /// Camera turn a frame may make, degrees: 15 is 450 deg/s at 30 frames/s, three times the
  /// fastest hand-held turns recorded (TUM fr1/rpy: 5.5 deg a frame).
  double maxTurnDeg = 15;
  bool skipLost = false;  ///< go on past a lost frame (else the stream ends there)
  int maxLostInRow = 30;  ///< with skipLost: give up after this many lost frames in a row
};

/// What became of one frame.
struct FrameReport {
  size_t frame = 0;
  bool fused = false;            ///< fitted and added to the field
  bool recovered = false;        ///< the predicted start failed; the last good pose's worked
  int fits = 0;                  ///< fits made, both starts and levels
  double inliers = 0;            ///< share of control points with a correspondence
  double rms = 0;                ///< RMS residual at the last fit, world units
  double step = 0, turnDeg = 0;  ///< camera motion from the last good frame
  double surprise = 0;           ///< distance of the fitted camera from the predicted one
  bool closedLoop = false;       ///< it closed a loop: the frames before moved, the field rebuilt
  std::string why;               ///< why it was lost (empty when fused)
  /// This rank's seconds on the frame: waiting for it to be read, fitting it, adding it to the
  /// field (loop closing included); each with the waits for other ranks it holds.
  double readSeconds = 0, fitSeconds = 0, addSeconds = 0;
};

/// How many fused frames' inlier shares the judge remembers.
inline constexpr size_t kRecentFrames = 10;

/// Where a stream stands, enough to continue it (checkpoints).
struct TrackingState {
  size_t nextFrame = 0;
  std::vector<char> lost;  ///< per frame: 1 when left out
  int lostInRow = 0;
  std::vector<double> latticeOrigin;  ///< the field's lattice (empty: not chosen yet)
  std::vector<double> recentInliers;  ///< inlier shares of the last fused frames, oldest first
  std::string failure;                ///< set when the stream was given up ...
  size_t failedFrame = 0;             ///< ... at this frame
};

/// Collective: the motion from frame `last` to frame `next` (poses[last]^-1 poses[next]) that
/// their images show, given a guess; the guess when they show none. Every rank returns the same.
using FrameMotion = std::function<Pose(size_t last, size_t next, const Pose& guess)>;

/// Collective: called before a frame is first needed (`done` false: the stream may read it)
/// and once it is fused or left out (`done` true: it may be forgotten).
using FrameHook = std::function<void(size_t frame, bool done)>;

/// What the stream around trackFrames does at each point; every call is collective.
struct StreamCalls {
  FrameHook frame;     ///< before a frame is needed and once it is done
  FrameMotion motion;  ///< optional: a second start from the pixels
  std::function<void(const FrameReport&)> onFrame;       ///< every frame's outcome
  std::function<void(const TrackingState&)> onBoundary;  ///< where a checkpoint may be taken
  /// Optional, once a frame is fused into `field` (and still held): true when it moved the
  /// poses of the frames so far (it closed a loop); the field is then built again at them.
  std::function<bool(size_t frame, std::vector<Pose>& poses, const BrickStore& field)> closeLoops;
  /// Optional, once the last frame is tracked: true when it moved the poses (the loops
  /// measured since the last closed one); the field is then built again at them.
  std::function<bool(std::vector<Pose>& poses)> finishLoops;
  /// Optional: once every frame is tracked, whether more have joined `frames` (and `times`);
  /// false ends the stream.
  std::function<bool()> moreFrames;
};

class ControlRouting;

/// Tracks a stream frame by frame (trackFrames is its loop; the library's Fusion calls it as
/// frames arrive). Every call is collective; the references must outlive it.
class FrameTracker {
 public:
  FrameTracker(const ScanSource& frames, std::vector<Pose>& poses, const std::vector<double>& times,
               const std::vector<Pose>* guide, const TrackerSettings& settings,
               RegistrationField& field, MPI_Comm comm, TrackingState& state,
               const StreamCalls& calls);
  ~FrameTracker();
  FrameTracker(const FrameTracker&) = delete;
  FrameTracker& operator=(const FrameTracker&) = delete;

  /// Starts the field from frame 0 (which fixes the world frame at poses[0]), or rebuilds it
  /// from the frames before state.nextFrame when resuming. False (state.failure set) when the
  /// first frame has no depth.
  bool start();
  /// Frames were appended to `frames` (and `times`): they start where the last fused one was.
  void grew();
  /// Tracks frame state.nextFrame (which `frames` must hold) and fuses it when the fit holds.
  /// False, with state.failure set, when the stream is to be given up.
  bool next();
  /// The stream has ended: loops measured and not yet closed are closed (calls.finishLoops).
  void finish();

 private:
  const ScanSource& frames_;
  std::vector<Pose>& poses_;
  const std::vector<double>& times_;
  const std::vector<Pose>* guide_;
  const TrackerSettings& s_;
  RegistrationField& field_;
  MPI_Comm comm_;
  TrackingState& state_;
  const StreamCalls& calls_;
  std::unique_ptr<ControlRouting> control_;
  const BrickStore* store_ = nullptr;
  std::vector<size_t> fused_;  ///< frames fused so far, in order
};

/// Collective: tracks frames nextFrame.. of `frames` (taken at `times`) into `field`, starting from
/// the field of the frames before (rebuilt from their poses when resuming). Frame 0 fixes the world
/// frame at poses[0]. `guide`, when given, is a trajectory whose relative motion predicts each
/// start; without it, the camera's last motion is assumed to continue; `calls.motion`, when given,
/// refines that start from the pixels of the last frame and this one. Every rank ends with the same
/// poses and state. Returns false, with state.failure set, when a lost frame ends the stream.
bool trackFrames(const ScanSource& frames, std::vector<Pose>& poses,
                 const std::vector<double>& times, const std::vector<Pose>* guide,
                 const TrackerSettings& settings, RegistrationField& field, MPI_Comm comm,
                 TrackingState& state, const StreamCalls& calls);

/// The pose the motion so far predicts for a frame after `last`: the guide's motion from frame
/// `last` to `next`, or (no guide) the velocity from `prev` to `last` kept for the time from
/// `last` to `next` (frame times, or their indices when `times` is empty); `last` itself when
/// there is no `prev` (-1).
Pose predictPose(const std::vector<Pose>& poses, const std::vector<Pose>* guide, long prev,
                 size_t last, size_t next, const std::vector<double>& times = {});

}  // namespace rangefuse
