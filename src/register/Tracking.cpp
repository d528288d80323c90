#include "rangefuse/register/Tracking.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rangefuse/register/ControlRouting.h"
#include "rangefuse/register/Correspondences.h"
#include "rangefuse/register/ProjectiveIcp.h"

namespace rangefuse {
namespace {

/// a b, its rotation made orthonormal again: a prediction composes three rotations, and
/// rounding errors grown that way would double with every frame.
Pose compose(const Pose& a, const Pose& b) {
  const Eigen::Quaterniond q(a.R * b.R);
  return Pose{q.normalized().toRotationMatrix(), a.R * b.t + a.t};
}

/// V(w) of SE(3)'s exponential: t = V(w) v for the twist (w, v).
Eigen::Matrix3d twistV(const Eigen::Vector3d& w) {
  const double a = w.norm();
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  if (a < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * W;
  return Eigen::Matrix3d::Identity() + (1 - std::cos(a)) / (a * a) * W +
         (a - std::sin(a)) / (a * a * a) * W * W;
}

/// The rigid motion `scale` times as far along the same screw (exp(scale log m)).
Pose scaledMotion(const Pose& m, double scale) {
  const Eigen::AngleAxisd turn(m.R);
  const Eigen::Vector3d w = turn.angle() * turn.axis();
  const Eigen::Vector3d v = twistV(w).lu().solve(m.t);
  const Eigen::Vector3d ws = scale * w;
  const double a = ws.norm();
  const Eigen::Matrix3d R =
      a > 0 ? Eigen::AngleAxisd(a, ws / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
  return Pose{R, twistV(ws) * (scale * v)};
}

bool settled(const RegistrationStep& s, const FitControl& o) {
  return s.rotationDeg < o.rotationTolDeg && s.translation < o.translationTol;
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f%%", 100 * share);
  return text;
}

/// True when the last step, shorter than `reach`, went back to where the fit was two steps
/// before: a point or two entering and leaving the band flip a weakly pinned direction back and
/// forth, and the fit would never settle by the step rule. The pose is then put halfway between
/// the two places, where the fit would settle.
bool cycled(const std::vector<Pose>& path, Pose& pose, double reach) {
  if (path.size() < 3) return false;
  const Pose& back = path[path.size() - 3];
  const Pose& previous = path[path.size() - 2];
  const Pose step = relative(previous, pose), loop = relative(back, pose);
  if (!(step.t.norm() < reach && loop.t.norm() < 0.25 * step.t.norm() &&
        rotationDegrees(loop.R) <= 0.25 * rotationDegrees(step.R) + 1e-9))
    return false;
  pose = compose(previous, scaledMotion(step, 0.5));
  return true;
}

/// One frame's fit from one start: coarse level, then every control point.
class FrameFit {
 public:
  /// `predicted`: where the camera's motion so far puts the frame.
  /// `usual`: the inlier share of the frames before (0: none yet).
  FrameFit(const TrackerSettings& s, ControlRouting& control, const BrickStore& store,
           const Pose& predicted, double usual, MPI_Comm comm)
      : s_(s),
        control_(control),
        store_(store),
        predicted_(predicted),
        usual_(usual),
        comm_(comm) {}

  /// Fits frame i from `start`; the report's `why` is empty when the fit holds.
  FrameReport fit(size_t i, std::vector<Pose>& poses, const Pose& start, size_t last,
                  FrameReport report) {
    poses[i] = start;
    control_.route({i}, poses, store_);
    bool converged = false;
    RegistrationStep final;
    for (const int every : {s_.coarse, 1}) {
      if (every == 1 && s_.coarse == 1 && converged) break;
      const int iterations = every == 1 ? s_.fineIterations : s_.coarseIterations;
      converged = false;
      std::vector<Pose> path{poses[i]};
      for (int it = 0; it < iterations && !converged; ++it) {
        final = planeStep(i, poses[i], every);
        path.push_back(poses[i]);
        ++report.fits;
        if (!final.applied) break;
        converged = settled(final, s_.fit) || cycled(path, poses[i], s_.fit.correspondences.huber);
      }
      if (!final.applied) break;
    }
    const double count = control_.count(i);
    report.inliers = count > 0 ? static_cast<double>(final.correspondences) / count : 0;
    report.rms = final.rms;
    const Pose motion = relative(poses[last], poses[i]);
    report.step = motion.t.norm();
    report.turnDeg = rotationDegrees(motion.R);
    report.surprise = relative(predicted_, poses[i]).t.norm();
    report.why = judge(final, converged, report, static_cast<double>(i - last));
    return report;
  }

 private:
  /// One Gauss-Newton step of frame i's control points (every `every`-th) against the field's
  /// distance and gradient, point to plane, about the camera centre; reports the sums before.
  RegistrationStep planeStep(size_t i, Pose& pose, int every) {
    const ControlPoints c = control_.at(i, pose, store_, every);
    const Eigen::Vector3d centre = c.sensor.isPoint ? c.sensor.point : pose.t;
    const PlaneSums sums =
        planeSums(store_, c.points, c.normals, c.weights, centre, s_.fit.correspondences, comm_);
    RegistrationStep step;
    step.correspondences = static_cast<uint64_t>(sums.count);
    step.rms = sums.rms();
    if (sums.count < static_cast<double>(s_.fit.minCorrespondences)) return step;
    const Eigen::Matrix<double, 6, 1> x = solveWellPosed(sums.A, -sums.b, sums.wLever / sums.w);
    const Eigen::Vector3d w = x.tail<3>();
    const double angle = w.norm();
    const Eigen::Matrix3d R = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                        : Eigen::Matrix3d::Identity();
    const Pose delta{R, centre + x.head<3>() - R * centre};
    pose = compose(delta, pose);
    step.rotationDeg = angle * 180 / M_PI;
    step.translation = x.head<3>().norm();
    step.applied = true;
    return step;
  }

  /// Why the fit is not to be trusted, or empty.
  std::string judge(const RegistrationStep& last, bool converged, const FrameReport& r,
                    double frames) const {
    char text[160];
    if (!last.applied)
      return "too few points on the field (" + std::to_string(last.correspondences) + ")";
    if (r.inliers < s_.minInliers)
      return "only " + percent(r.inliers) + " of its points lie on the field (needs " +
             percent(s_.minInliers) + ")";
    // A frame that does not belong here (another scene, a glitch) finds the field with far
    // fewer of its points than the frames before; new surface coming into view costs a few.
    if (r.inliers < s_.inlierDrop * usual_)
      return "only " + percent(r.inliers) + " of its points lie on the field against " +
             percent(usual_) + " for the frames before";
    if (s_.maxResidual > 0 && r.rms > s_.maxResidual) {
      std::snprintf(text, sizeof text, "residual %.3g above %.3g", r.rms, s_.maxResidual);
      return text;
    }
    // A hand-held camera cannot change its velocity by much in a frame: a fit that lands far
    // from the prediction has more likely slid along the surface (a wall, a floor) than moved.
    if (s_.maxStep > 0 && r.surprise > s_.maxStep * frames) {
      std::snprintf(text, sizeof text, "landed %.3g from where its motion predicted it",
                    r.surprise);
      return text;
    }
    if (r.turnDeg > s_.maxTurnDeg * frames) {
      std::snprintf(text, sizeof text, "turned %.3g deg since the last frame", r.turnDeg);
      return text;
    }
    // Still moving after every fit: the fit slides along the surface rather than settling.
    if (!converged && last.translation > 30 * s_.fit.translationTol) {
      std::snprintf(text, sizeof text, "did not converge (last step %.3g)", last.translation);
      return text;
    }
    return "";
  }

  const TrackerSettings& s_;
  ControlRouting& control_;
  const BrickStore& store_;
  Pose predicted_;
  double usual_;
  MPI_Comm comm_;
};

/// The median of the shares (0 when there are none).
double medianShare(std::vector<double> shares) {
  if (shares.empty()) return 0;
  const auto mid = shares.begin() + static_cast<std::ptrdiff_t>(shares.size() / 2);
  std::nth_element(shares.begin(), mid, shares.end());
  return *mid;
}

/// True when two starts lie within the convergence tolerance of each other.
bool samePlace(const Pose& a, const Pose& b, const FitControl& o) {
  const Pose d = relative(a, b);
  return rotationDegrees(d.R) < 10 * o.rotationTolDeg && d.t.norm() < 10 * o.translationTol;
}

/// Whether fit a is to be preferred to fit b: one that holds, then the one more of whose points
/// lie on the field, then (as many within 1 %) the smaller residual.
bool better(const FrameReport& a, const FrameReport& b) {
  if (a.why.empty() != b.why.empty()) return a.why.empty();
  if (std::abs(a.inliers - b.inliers) > 0.01) return a.inliers > b.inliers;
  return a.rms < b.rms;
}

/// The frames tracked so far, in order, for rebuilding the field.
std::vector<size_t> fusedBefore(const TrackingState& state) {
  std::vector<size_t> fused;
  for (size_t j = 0; j < state.nextFrame; ++j)
    if (!state.lost[j]) fused.push_back(j);
  return fused;
}

}  // namespace

Pose predictPose(const std::vector<Pose>& poses, const std::vector<Pose>* guide, long prev,
                 size_t last, size_t next, const std::vector<double>& times) {
  if (guide) return compose(poses[last], relative((*guide)[last], (*guide)[next]));
  if (prev < 0) return poses[last];
  const size_t p = static_cast<size_t>(prev);
  auto time = [&](size_t k) { return times.empty() ? static_cast<double>(k) : times[k]; };
  const double before = time(last) - time(p), after = time(next) - time(last);
  Pose motion = relative(poses[p], poses[last]);
  if (!(before > 0 && after > 0)) return poses[last];
  // The same velocity over the next interval: the motion scaled by the ratio of the intervals
  // (frames dropped by the sensor, or left out as lost), at most three times over.
  const double scale = std::min(3.0, after / before);
  if (scale != 1) motion = scaledMotion(motion, scale);
  return compose(poses[last], motion);
}

FrameTracker::FrameTracker(const ScanSource& frames, std::vector<Pose>& poses,
                           const std::vector<double>& times, const std::vector<Pose>* guide,
                           const TrackerSettings& s, RegistrationField& field, MPI_Comm comm,
                           TrackingState& state, const StreamCalls& calls)
    : frames_(frames),
      poses_(poses),
      times_(times),
      guide_(guide),
      s_(s),
      field_(field),
      comm_(comm),
      state_(state),
      calls_(calls),
      control_(std::make_unique<ControlRouting>(frames, s.fit.controlStride, comm, true,
                                                s.noiseFloor)) {}

FrameTracker::~FrameTracker() = default;

bool FrameTracker::start() {
  state_.lost.resize(frames_.size(), 0);
  calls_.frame(0, false);
  control_->learn({0});
  if (control_->count(0) == 0) {
    state_.failure = "the first frame has no depth to start the field from";
    state_.failedFrame = 0;
    return false;
  }
  state_.latticeOrigin = field_.fixLattice(state_.latticeOrigin, poses_);
  if (state_.nextFrame == 0) {  // the first frame defines the world frame
    store_ = &field_.build({0}, poses_);
    if (calls_.closeLoops) calls_.closeLoops(0, poses_, *store_);  // the first key frame
    calls_.frame(0, true);
    state_.nextFrame = 1;
    FrameReport first;
    first.fused = true;
    first.inliers = 1;
    calls_.onFrame(first);
    calls_.onBoundary(state_);
  } else {
    store_ = &field_.build(fusedBefore(state_), poses_);
  }
  fused_ = fusedBefore(state_);
  return true;
}

void FrameTracker::grew() {
  // New frames start where the last one was; tracking puts them where they belong.
  poses_.resize(frames_.size(), poses_[fused_.back()]);
  state_.lost.resize(frames_.size(), 0);
  control_->follow();
}

bool FrameTracker::next() {
  const size_t i = state_.nextFrame;
  const size_t last = fused_.back();
  const long prev = fused_.size() > 1 ? static_cast<long>(fused_[fused_.size() - 2]) : -1;
  double start = MPI_Wtime();
  calls_.frame(i, false);
  const double read = MPI_Wtime() - start;
  start += read;
  FrameReport report;
  report.frame = i;
  // The start: the motion so far continued. When that is a weak guess (no motion known yet),
  // or the fit from it failed or went farther than the field's band reaches, the pixels of
  // the last frame and this one give a second start (they reach farther, but are blind along
  // directions the view does not pin down), and the field decides between the two.
  const Pose predicted = predictPose(poses_, guide_, prev, last, i, times_);
  FrameFit fit(s_, *control_, *store_, predicted, medianShare(state_.recentInliers), comm_);
  report = fit.fit(i, poses_, predicted, last, report);
  Pose chosen = poses_[i];
  const Pose moved = relative(predicted, chosen);
  const bool doubtful =
      prev < 0 || !report.why.empty() || moved.t.norm() > s_.fit.correspondences.maxDistance;
  auto tryFrom = [&](const Pose& other) {
    if (samePlace(other, predicted, s_.fit)) return;
    FrameReport alternative = fit.fit(i, poses_, other, last, report);
    alternative.fits += report.fits;
    if (better(alternative, report)) {
      report = alternative;
      chosen = poses_[i];
    } else {
      report.fits = alternative.fits;
    }
  };
  if (calls_.motion && doubtful)
    tryFrom(compose(poses_[last], calls_.motion(last, i, relative(poses_[last], predicted))));
  if (!report.why.empty()) {  // re-localise from where the camera last was
    tryFrom(poses_[last]);
    report.recovered = report.why.empty();
  }
  poses_[i] = chosen;
  control_->release(i);
  report.readSeconds = read;
  report.fitSeconds = MPI_Wtime() - start;
  start += report.fitSeconds;
  report.fused = report.why.empty();
  state_.nextFrame = i + 1;
  if (report.fused) {
    fused_.push_back(i);
    store_ = &field_.add(i, poses_);
    if (calls_.closeLoops && calls_.closeLoops(i, poses_, *store_)) {
      store_ = &field_.build(fused_, poses_);
      report.closedLoop = true;
    }
    state_.latticeOrigin = field_.latticeOrigin();
    report.addSeconds = MPI_Wtime() - start;
    state_.lostInRow = 0;
    state_.recentInliers.push_back(report.inliers);
    if (state_.recentInliers.size() > kRecentFrames)
      state_.recentInliers.erase(state_.recentInliers.begin());
  } else {
    poses_[i] = poses_[last];
    state_.lost[i] = 1;
    ++state_.lostInRow;
  }
  calls_.frame(i, true);
  calls_.onFrame(report);
  if (!report.fused && !s_.skipLost) {
    state_.failure = "frame " + std::to_string(i) + ": tracking lost: " + report.why;
    state_.failedFrame = i;
    return false;
  }
  if (state_.lostInRow > s_.maxLostInRow) {
    state_.failure = "frame " + std::to_string(i) + ": tracking lost for " +
                     std::to_string(state_.lostInRow) + " frames in a row: " + report.why;
    state_.failedFrame = i;
    return false;
  }
  calls_.onBoundary(state_);
  return true;
}

void FrameTracker::finish() {
  if (calls_.finishLoops && calls_.finishLoops(poses_)) store_ = &field_.build(fused_, poses_);
}

bool trackFrames(const ScanSource& frames, std::vector<Pose>& poses,
                 const std::vector<double>& times, const std::vector<Pose>* guide,
                 const TrackerSettings& s, RegistrationField& field, MPI_Comm comm,
                 TrackingState& state, const StreamCalls& calls) {
  FrameTracker tracker(frames, poses, times, guide, s, field, comm, state, calls);
  if (!tracker.start()) return false;
  for (;;) {
    if (state.nextFrame == frames.size()) {
      if (!calls.moreFrames || !calls.moreFrames() || state.nextFrame == frames.size()) break;
      tracker.grew();
    }
    if (!tracker.next()) return false;
  }
  tracker.finish();
  return true;
}

}  // namespace rangefuse
