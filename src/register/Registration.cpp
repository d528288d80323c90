#include "rangefuse/register/Registration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "JointRegistration.h"
#include "rangefuse/io/Json.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/register/ControlRouting.h"

namespace rangefuse {
namespace {

Twist twistOf(const Pose& delta, const Eigen::Vector3d& centre, double radius) {
  const Eigen::AngleAxisd aa(delta.R);
  Twist t;
  t.rotation = aa.angle() * aa.axis();
  t.shift = delta.apply(centre) - centre;
  t.radius = radius;
  return t;
}

Pose poseOf(const Twist& t, const Eigen::Vector3d& centre, double scale) {
  Pose p;
  const double angle = t.rotation.norm() * scale;
  if (angle > 0) p.R = Eigen::AngleAxisd(angle, t.rotation.normalized()).toRotationMatrix();
  p.t = centre + scale * t.shift - p.R * centre;
  return p;
}

/// The extrapolation factor for this fit given the previous one (1: none).
Eigen::Matrix<double, 6, 1> asVector(const Twist& t) {
  Eigen::Matrix<double, 6, 1> v;
  v << t.radius * t.rotation, t.shift;
  return v;
}

double acceleration(const Twist& now, const FitHistory& h) {
  if (!h.have) return 1;
  const auto a = asVector(now), b = asVector(h.last);
  if (!(a.norm() > 0 && b.norm() > 0) || a.dot(b) < 0.95 * a.norm() * b.norm()) return 1;
  const double r = a.norm() / b.norm();
  return r < 0.95 ? std::min(8.0, 1 / (1 - r)) : 1;
}

/// How far to extrapolate a fit: the acceleration, but no farther than maxExtrapolation (noisy
/// fits can look steady enough to be stretched eightfold, and then leave the field's reach).
double extrapolation(const Twist& now, const FitHistory& h, const FitControl& o) {
  const double scale = o.accelerate ? acceleration(now, h) : 1.0;
  const double length = asVector(now).norm();
  if (scale <= 1 || !(length > 0)) return 1;
  return std::max(1.0, std::min(scale, o.maxExtrapolation / length));
}

/// One fit of scan i against the field: correspondences, sums across ranks, rigid update.
RegistrationStep fitOnce(size_t i, Pose& pose, const BrickStore& field, ControlRouting& control,
                         const FitControl& o, MPI_Comm comm, FitHistory& history) {
  const ControlPoints c = control.at(i, pose, field);
  const RigidSums sums =
      correspondenceSums(field, c.points, c.normals, c.weights, o.correspondences, comm);
  RegistrationStep step;
  step.correspondences = static_cast<uint64_t>(sums.count);
  step.rms = sums.rms();
  if (sums.count < o.minCorrespondences) return step;
  const Eigen::Vector3d centre = sums.wp / sums.w;
  const double radius =
      std::sqrt(std::max(1e-30, sums.wpq.trace() / sums.w - centre.squaredNorm()));
  const Twist twist = twistOf(fitRigid(sums), centre, radius);
  Pose delta = poseOf(twist, centre, extrapolation(twist, history, o));
  const Eigen::Vector3d& origin = field.grid().origin;  // the sums' frame, back to world
  delta.t += origin - delta.R * origin;
  history = FitHistory{true, twist};
  pose = delta * pose;
  step.rotationDeg = rotationDegrees(delta.R);
  step.translation = delta.t.norm();
  step.applied = true;
  return step;
}

bool converged(const RegistrationStep& s, const FitControl& o) {
  if (!s.applied) return true;
  if (s.algorithm == FitAlgorithm::Joint)  // Gauss-Newton: later steps only follow the noise
    return s.rotationDeg < o.jointRotationTolDeg && s.translation < o.jointTranslationTol;
  return s.rotationDeg < o.rotationTolDeg && s.translation < o.translationTol;
}

void incremental(const ScanSource& scans, std::vector<Pose>& poses, const FitControl& o,
                 RegistrationField& field, ControlRouting& control, MPI_Comm comm,
                 const std::function<void(const RegistrationStep&)>& onStep,
                 RegistrationProgress& progress, const BoundaryCallback& onBoundary) {
  // The scans placed so far, in the order they joined: the anchor, then by index.
  std::vector<size_t> fused = {o.anchor};
  for (size_t j = 0; j < progress.nextScan; ++j)
    if (j != o.anchor) fused.push_back(j);
  const BrickStore* store = &field.build(fused, poses);
  for (size_t i = progress.nextScan; i < scans.size(); ++i) {
    if (i == o.anchor) continue;
    control.route({i}, poses, *store);
    FitHistory history;
    for (int it = 1; it <= o.maxIterations; ++it) {
      RegistrationStep step = fitOnce(i, poses[i], *store, control, o, comm, history);
      step.algorithm = FitAlgorithm::Incremental;
      step.iteration = it;
      step.scan = i;
      onStep(step);
      if (converged(step, o)) break;
    }
    fused.push_back(i);
    store = &field.add(i, poses);
    progress.latticeOrigin = field.latticeOrigin();
    progress.nextScan = i + 1;
    onBoundary(progress, poses);
  }
}

bool samePose(const Pose& a, const Pose& b) {
  return a.R == b.R && a.t == b.t;
}

/// Moves the scans this round moved by the motion that returns the anchor to where the round
/// began: the anchor registers like the others, then the frame it fixes is restored for the
/// group. Scans no fit moved (no overlap) stay as given.
void returnAnchor(std::vector<Pose>& poses, const std::vector<Pose>& roundPoses, size_t anchor) {
  const Pose a = poses[anchor], given = roundPoses[anchor];
  if (samePose(a, given)) return;  // not even rounding when the anchor did not move
  Pose g;
  g.R = given.R * a.R.transpose();
  g.t = given.t - g.R * a.t;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (samePose(poses[i], roundPoses[i])) continue;
    poses[i] = g * poses[i];
  }
  poses[anchor] = given;
}

/// Collective: the largest mean displacement of a scan's vertices between two sets of poses.
double largestMotion(const ScanSource& scans, const std::vector<Pose>& from,
                     const std::vector<Pose>& to, MPI_Comm comm) {
  const std::vector<double> motion = scanMotions(scans, from, to, comm);
  return motion.empty() ? 0 : *std::max_element(motion.begin(), motion.end());
}

void startRound(RegistrationProgress& p, const std::vector<Pose>& poses) {
  p.iteration = 0;
  p.roundMoved = false;
  p.lastMoved = true;
  p.roundPoses = poses;
  p.history.assign(poses.size(), FitHistory{});
}

/// One iteration of Algorithm 2's fits: every scan's, jointly or one by one.
std::vector<RegistrationStep> fitAll(std::vector<Pose>& poses, const BrickStore& store,
                                     ControlRouting& control, const FitControl& o, MPI_Comm comm,
                                     std::vector<FitHistory>& history) {
  if (o.solve == RegistrationSolve::Joint) {
    const JointStepSettings settings{o.anchor, o.minCorrespondences, o.maxExtrapolation,
                                     o.correspondences};
    std::vector<RegistrationStep> steps = jointStep(poses, store, control, settings, comm);
    for (RegistrationStep& step : steps) step.algorithm = FitAlgorithm::Joint;
    return steps;
  }
  std::vector<RegistrationStep> steps;
  for (size_t i = 0; i < poses.size(); ++i) {
    steps.push_back(fitOnce(i, poses[i], store, control, o, comm, history[i]));
    steps.back().algorithm = FitAlgorithm::Simultaneous;
    steps.back().scan = i;
  }
  return steps;
}

void simultaneous(const ScanSource& scans, std::vector<Pose>& poses, FitControl o,
                  RegistrationField& field, ControlRouting& control, MPI_Comm comm,
                  const std::function<void(const RegistrationStep&)>& onStep,
                  RegistrationProgress& p, const BoundaryCallback& onBoundary) {
  // The field holds each scan itself: only voxels another image also saw are overlap. Foot
  // points from voxels more images saw are less noisy (in Algorithm 1 too, but there it moved
  // the noise-free known-motion case past 0.05 voxel: docs/registration.md).
  o.correspondences.minImages = 2;
  o.correspondences.weightByImages = true;
  const std::vector<size_t> all = everyScan(scans.size());
  while (p.phase == RegistrationPhase::Simultaneous) {
    if (p.iteration < o.maxIterations && p.lastMoved) {
      const BrickStore& store = field.build(all, p.roundPoses);
      p.latticeOrigin = field.latticeOrigin();
      control.route(all, poses, store);
      while (p.iteration < o.maxIterations && p.lastMoved) {
        bool moved = false;
        for (RegistrationStep& step : fitAll(poses, store, control, o, comm, p.history)) {
          step.round = p.round;
          step.iteration = p.iteration + 1;
          onStep(step);
          moved |= !converged(step, o);
        }
        if (++p.iteration == 1) p.roundMoved = moved;
        p.lastMoved = moved;
        onBoundary(p, poses);
      }
    }
    returnAnchor(poses, p.roundPoses, o.anchor);
    const double motion = largestMotion(scans, p.roundPoses, poses, comm);
    // Done when a rebuilt field moved nothing or a round moved no scan past the tolerance:
    // later rounds only wander within the noise (docs/registration.md).
    const int round = p.round;
    if (!p.roundMoved || motion < o.roundTolerance || p.round >= o.maxRounds) {
      p.phase = RegistrationPhase::Done;
    } else {
      ++p.round;
      startRound(p, poses);
    }
    p.ended = RoundEnd{round, motion};
    onBoundary(p, poses);
    p.ended.reset();
  }
}

}  // namespace

const char* toString(FitAlgorithm algorithm) {
  switch (algorithm) {
    case FitAlgorithm::Incremental:
      return "incremental";
    case FitAlgorithm::Joint:
      return "joint";
    case FitAlgorithm::Simultaneous:
      return "simultaneous";
    case FitAlgorithm::Others:
      return "others";
  }
  return "?";
}

const char* toString(RegistrationPhase phase) {
  switch (phase) {
    case RegistrationPhase::Start:
      return "start";
    case RegistrationPhase::Incremental:
      return "incremental";
    case RegistrationPhase::Simultaneous:
      return "simultaneous";
    case RegistrationPhase::Done:
      return "done";
  }
  return "?";
}

RegistrationPhase parseRegistrationPhase(const std::string& text) {
  for (RegistrationPhase p : {RegistrationPhase::Start, RegistrationPhase::Incremental,
                              RegistrationPhase::Simultaneous, RegistrationPhase::Done})
    if (text == toString(p)) return p;
  throw std::runtime_error("unknown registration phase '" + text + "'");
}

double rotationDegrees(const Eigen::Matrix3d& R) {
  return std::abs(Eigen::AngleAxisd(R).angle()) * 180 / M_PI;
}

std::vector<double> scanMotions(const ScanSource& scans, const std::vector<Pose>& from,
                                const std::vector<Pose>& to, MPI_Comm comm) {
  std::vector<double> motion(scans.size(), 0);
  // A scan read again may fail on one rank: every rank then throws here.
  mpi::collectivelyOrThrow(comm, [&] {
    for (size_t i = 0; i < scans.size(); ++i) {
      if (!scans.holds(i)) continue;
      const std::shared_ptr<const PrismScan> scan = scans.get(i);
      const auto& points = scan->surface.points;
      double sum = 0;
      size_t n = 0;
      for (size_t v = 0; v < points.size(); v += 16, ++n)
        sum += (to[i].apply(points[v]) - from[i].apply(points[v])).norm();
      if (n > 0) motion[i] = sum / n;
    }
  });
  // A rank holds only the scans it read: the largest over ranks is the holder's.
  MPI_Allreduce(MPI_IN_PLACE, motion.data(), static_cast<int>(motion.size()), MPI_DOUBLE, MPI_MAX,
                comm);
  return motion;
}

std::vector<RegistrationStep> fitAgainstOthers(const ScanSource& scans,
                                               const std::vector<Pose>& poses, const FitControl& o,
                                               RegistrationField& field,
                                               const std::vector<size_t>& which, MPI_Comm comm) {
  ControlRouting control(scans, o.controlStride, comm);
  std::vector<Pose> moved = poses;
  std::vector<RegistrationStep> out;
  for (size_t i : which) {
    if (i == o.anchor) continue;
    std::vector<size_t> others;
    for (size_t j = 0; j < scans.size(); ++j)
      if (j != i) others.push_back(j);
    const BrickStore& store = field.build(others, poses);
    control.route({i}, poses, store);
    FitHistory history;
    RegistrationStep check;
    check.algorithm = FitAlgorithm::Others;
    check.scan = i;
    for (int it = 1; it <= o.maxIterations; ++it) {
      const RegistrationStep step = fitOnce(i, moved[i], store, control, o, comm, history);
      if (it == 1) check.rms = step.rms, check.correspondences = step.correspondences;
      if (converged(step, o)) break;
    }
    out.push_back(check);
  }
  const std::vector<double> motion = scanMotions(scans, poses, moved, comm);
  for (RegistrationStep& s : out) s.othersMotion = motion[s.scan];
  return out;
}

void registerScans(const ScanSource& scans, std::vector<Pose>& poses, const FitControl& o,
                   RegistrationField& field, MPI_Comm comm,
                   const std::function<void(const RegistrationStep&)>& onStep,
                   RegistrationProgress& p, const BoundaryCallback& onBoundary) {
  p.latticeOrigin = field.fixLattice(p.latticeOrigin, poses);
  const bool first = o.mode == RegistrationMode::Incremental || o.mode == RegistrationMode::Both;
  const bool second = o.mode == RegistrationMode::Simultaneous || o.mode == RegistrationMode::Both;
  using Phase = RegistrationPhase;
  if (p.phase == Phase::Start) p.phase = first ? Phase::Incremental : Phase::Simultaneous;
  if (p.phase == Phase::Simultaneous && p.roundPoses.empty()) startRound(p, poses);
  ControlRouting control(scans, o.controlStride, comm);
  if (p.phase == Phase::Incremental) {
    incremental(scans, poses, o, field, control, comm, onStep, p, onBoundary);
    p.phase = second ? Phase::Simultaneous : Phase::Done;
    if (second) startRound(p, poses);
    onBoundary(p, poses);
  }
  if (p.phase == Phase::Simultaneous)
    simultaneous(scans, poses, o, field, control, comm, onStep, p, onBoundary);
}

nlohmann::json RegistrationProgress::toJson() const {
  auto vec = [](const Eigen::Vector3d& v) { return std::vector<double>{v.x(), v.y(), v.z()}; };
  nlohmann::json poses = nlohmann::json::array(), hist = nlohmann::json::array();
  for (const Pose& q : roundPoses) poses.push_back(io::poseNumbers(q));
  for (const FitHistory& h : history)
    hist.push_back({{"have", h.have},
                    {"rotation", vec(h.last.rotation)},
                    {"shift", vec(h.last.shift)},
                    {"radius", h.last.radius}});
  return {{"phase", toString(phase)}, {"next_scan", nextScan},           {"round", round},
          {"iteration", iteration},   {"round_moved", roundMoved},       {"last_moved", lastMoved},
          {"round_poses", poses},     {"lattice_origin", latticeOrigin}, {"history", hist}};
}

RegistrationProgress RegistrationProgress::fromJson(const nlohmann::json& j) {
  auto vec = [](const nlohmann::json& a) {
    const auto v = a.get<std::vector<double>>();
    if (v.size() != 3) throw std::runtime_error("a vector needs 3 numbers");
    return Eigen::Vector3d(v[0], v[1], v[2]);
  };
  RegistrationProgress p;
  p.phase = parseRegistrationPhase(j.at("phase").get<std::string>());
  p.nextScan = j.at("next_scan").get<size_t>();
  p.round = j.at("round").get<int>();
  p.iteration = j.at("iteration").get<int>();
  p.roundMoved = j.at("round_moved").get<bool>();
  p.lastMoved = j.at("last_moved").get<bool>();
  for (const auto& v : j.at("round_poses")) p.roundPoses.push_back(io::poseFromNumbers(v));
  p.latticeOrigin = j.value("lattice_origin", std::vector<double>{});
  if (!p.latticeOrigin.empty() && p.latticeOrigin.size() != 3)
    throw std::runtime_error("a lattice origin needs 3 numbers");
  for (const auto& h : j.at("history"))
    p.history.push_back(
        FitHistory{h.at("have").get<bool>(),
                   Twist{vec(h.at("rotation")), vec(h.at("shift")), h.at("radius").get<double>()}});
  return p;
}

}  // namespace rangefuse
