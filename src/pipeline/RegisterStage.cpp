#include "rangefuse/pipeline/RegisterStage.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/Checkpointing.h"
#include "rangefuse/pipeline/RegistrationField.h"
#include "rangefuse/register/PairOverlap.h"
#include "rangefuse/register/Stragglers.h"
#include "rangefuse/route/ScanLoader.h"

namespace rangefuse {

using mpi::collectively;

namespace {

FitControl registrationOptions(const RegistrationSettings& o, double voxel, double eps,
                               const LoadedScans& scans) {
  FitControl r;
  r.mode = o.mode;
  r.controlStride = o.controlStride;
  r.maxIterations = o.maxIterations;
  r.maxRounds = o.maxRounds;
  r.solve = o.solve;
  r.translationTol = 1e-3 * voxel;
  r.jointTranslationTol = 0.01 * voxel;
  r.correspondences.maxDistance = eps;
  r.roundTolerance = o.roundTolerance * voxel;
  r.maxExtrapolation = voxel;  // well inside the envelope the correspondences come from
  if (!o.anchor.empty()) {
    auto it = std::find(scans.names.begin(), scans.names.end(), o.anchor);
    if (it == scans.names.end())
      throw InputError("--anchor " + o.anchor + ": no scan of that name");
    r.anchor = static_cast<size_t>(it - scans.names.begin());
  }
  return r;
}

void printStep(const RegistrationStep& s, const LoadedScans& scans, double voxel) {
  std::printf(
      "[register] %-12s round %d it %2d %-14s %8llu corr  rms %.4f vox  dR %.5f deg  dt %.4f "
      "vox%s\n",
      toString(s.algorithm), s.round, s.iteration, scans.names[s.scan].c_str(),
      static_cast<unsigned long long>(s.correspondences), s.rms / voxel, s.rotationDeg,
      s.translation / voxel, s.applied ? "" : "  (too few correspondences: left as given)");
  std::fflush(stdout);
}

void printRoundEnd(const RegistrationProgress& p, double voxel) {
  std::printf(
      "[register] simultaneous round %d done: scans moved up to %.4f vox (mean over "
      "vertices); %s\n",
      p.ended->round, p.ended->motion / voxel,
      p.phase == RegistrationPhase::Done ? "registration done" : "rebuilding the field");
  std::fflush(stdout);
}

/// What a loose scan's warning says of its loosest motion.
std::string describeLooseMotion(const LooseMotion& m) {
  char text[400];
  const Eigen::Vector3d &a = m.axis, &p = m.through;
  if (m.turn)
    std::snprintf(
        text, sizeof text,
        "is held loosely: turning it about the axis (%.3f, %.3f, %.3f) through "
        "(%.4g, %.4g, %.4g) changes its fit %.3f times as much as its best-held "
        "motion (the surfaces it shares are nearly symmetric about that axis), so the data "
        "cannot fix its pose along that turn; its surface fits",
        a.x(), a.y(), a.z(), p.x(), p.y(), p.z(), m.hold);
  else
    std::snprintf(text, sizeof text,
                  "is held loosely: sliding it along (%.3f, %.3f, %.3f) changes its fit %.3f "
                  "times as much as its best-held motion (the surfaces it shares run along "
                  "that way), so the data cannot fix its pose along that slide; its "
                  "surface fits",
                  a.x(), a.y(), a.z(), m.hold);
  return text;
}

/// One warning per scan out of line with the others (on rank 0; every rank holds the steps).
void warnStragglers(const std::vector<RegistrationStep>& steps, const LoadedScans& scans,
                    double voxel, const Progress& progress) {
  const std::vector<ScanStanding> standings = lastStandings(steps);
  if (!progress.isRoot()) return;
  std::vector<double> rms;
  for (const ScanStanding& s : standings) rms.push_back(s.rms);
  std::sort(rms.begin(), rms.end());
  for (const ScanStanding& s : findStragglers(standings))
    std::fprintf(stderr,
                 "rangefuse: warning: registration: %s is out of line: residual %.3f voxel "
                 "against a median of %.3f, overlap %llu control points (%.0f %% of the "
                 "median scan's); check its pose, or give it a better start\n",
                 scans.names[s.scan].c_str(), s.rms / voxel, rms[rms.size() / 2] / voxel,
                 static_cast<unsigned long long>(s.correspondences), 100 * s.overlapShare);
  // A depth stream of a room may have hundreds of frames that saw one wall: name a few.
  constexpr size_t kNamed = 5;
  const std::vector<ScanStanding> loose = findLooseScans(standings);
  for (size_t k = 0; k < std::min(loose.size(), kNamed); ++k)
    std::fprintf(stderr, "rangefuse: warning: registration: %s %s\n",
                 scans.names[loose[k].scan].c_str(), describeLooseMotion(loose[k].loose).c_str());
  if (loose.size() > kNamed)
    std::fprintf(stderr,
                 "rangefuse: warning: registration: %zu more scans are held loosely (the "
                 "report's registration.scans lists them)\n",
                 loose.size() - kNamed);
}

/// Collective: the kOthersChecked scans registration moved farthest from `given` (the scans
/// that started farthest off, nearest the edge of its basin) fitted against the others' field
/// (Registration.h, fitAgainstOthers), each fit added to `steps`; rank 0
/// warns for each findOthersStragglers names. Returns false when a rank failed.
bool checkAgainstOthers(std::vector<RegistrationStep>& steps, const LoadedScans& scans,
                        const std::vector<Pose>& given, const FitControl& r,
                        RegistrationField& field, double voxel, MPI_Comm comm, Progress& progress) {
  if (lastStandings(steps).size() < kFewestJudged) return true;
  std::vector<RegistrationStep> fits;
  try {
    const std::vector<double> moved = scanMotions(*scans.held, given, scans.poses, comm);
    std::vector<size_t> order;
    for (size_t i = 0; i < moved.size(); ++i)
      if (i != r.anchor) order.push_back(i);
    // Farthest first; ties by index, so that every rank picks the same scans.
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return moved[a] > moved[b]; });
    order.resize(std::min(order.size(), kOthersChecked));
    fits = fitAgainstOthers(*scans.held, scans.poses, r, field, order, comm);
  } catch (const mpi::Reported&) {
    return false;
  }
  double largest = 0;
  size_t at = 0;
  for (const RegistrationStep& f : fits) {
    steps.push_back(f);
    if (f.othersMotion > largest) largest = f.othersMotion, at = f.scan;
  }
  char text[400];
  std::snprintf(text, sizeof text,
                "the %zu scans that moved most, each against the others' field: largest "
                "motion %.3f voxel (%s)",
                fits.size(), largest / voxel, scans.names[at].c_str());
  progress.stage("register", text);
  if (!progress.isRoot()) return true;
  for (const RegistrationStep& s : findOthersStragglers(steps, voxel))
    std::fprintf(stderr,
                 "rangefuse: warning: registration: %s is out of line: fitted against the other "
                 "scans alone it moves %.3f voxel (residual %.3f voxel over %llu control "
                 "points); check its pose, or give it a better start\n",
                 scans.names[s.scan].c_str(), s.othersMotion / voxel, s.rms / voxel,
                 static_cast<unsigned long long>(s.correspondences));
  return true;
}

/// The overlap the joint solve kept: pairs of scans sharing voxels at its first and last step.
void reportOverlap(const std::vector<RegistrationStep>& steps, const Progress& progress) {
  const std::vector<PairOverlap> pairs = pairOverlaps(steps);
  if (pairs.empty() || !progress.shows(Verbosity::normal)) return;
  const auto [first, last] = overlappingPairs(pairs);
  std::printf(
      "[register] overlap: %zu pairs of scans overlap (%zu at the first joint step); %zu kept "
      "less than half their overlap (report: registration.pairs)\n",
      last, first, pairsLosing(pairs, 0.5));
  std::fflush(stdout);
}

/// Adds the time from its construction to its destruction to `total`.
struct Stopwatch {
  double& total;
  double start = MPI_Wtime();
  ~Stopwatch() { total += MPI_Wtime() - start; }
};

/// Forwards to a field and adds up the time its calls take: building, not fitting.
class TimedField : public RegistrationField {
 public:
  explicit TimedField(RegistrationField& field) : field_(field) {}
  double seconds() const { return seconds_; }

  std::vector<double> fixLattice(const std::vector<double>& origin,
                                 const std::vector<Pose>& poses) override {
    Stopwatch w{seconds_};
    return field_.fixLattice(origin, poses);
  }
  const BrickStore& build(const std::vector<size_t>& which,
                          const std::vector<Pose>& poses) override {
    Stopwatch w{seconds_};
    return field_.build(which, poses);
  }
  const BrickStore& add(size_t i, const std::vector<Pose>& poses) override {
    Stopwatch w{seconds_};
    return field_.add(i, poses);
  }
  std::vector<double> latticeOrigin() const override { return field_.latticeOrigin(); }

 private:
  RegistrationField& field_;
  double seconds_ = 0;
};

/// Writes registration checkpoints at boundaries, at most one per `every` seconds.
class RegistrationCheckpointer {
 public:
  RegistrationCheckpointer(const CheckpointWriting& c, const LoadedScans& scans, MPI_Comm comm)
      : c_(c), scans_(scans), comm_(comm), last_(MPI_Wtime()) {
    MPI_Bcast(&last_, 1, MPI_DOUBLE, 0, comm_);  // every rank decides alike
  }

  bool ok() const { return ok_; }

  void operator()(const RegistrationProgress& p, const std::vector<Pose>& poses) {
    if (c_.path.empty() || !ok_) return;
    double now = MPI_Wtime();
    MPI_Bcast(&now, 1, MPI_DOUBLE, 0, comm_);  // one decision for all ranks
    if (p.phase != RegistrationPhase::Done && now - last_ < c_.every) return;
    last_ = now;
    LoadedScans current = scans_;
    current.poses = poses;
    ok_ = collectively(comm_, [&] {
      if (hashes_.empty()) hashes_ = hashScans(scans_.paths, comm_);
      const nlohmann::json progress = {{"stage", "registration"}, {"registration", p.toJson()}};
      io::writeCheckpoint(c_.path, checkpointMeta(c_.recorded, current, hashes_, progress, nullptr),
                          nullptr, comm_);
    });
    if (ok_) faultPoint("checkpoint");  // tests stop a run right after a given checkpoint
  }

 private:
  const CheckpointWriting& c_;
  const LoadedScans& scans_;
  MPI_Comm comm_;
  double last_;
  bool ok_ = true;
  std::vector<std::string> hashes_;
};

}  // namespace

bool registerPoses(const RegistrationSettings& o, const FieldSettings& f,
                   const CheckpointWriting& checkpoints, const std::string& resumed, MPI_Comm comm,
                   Progress& progress, LoadedScans& scans, RegistrationProgress& state,
                   std::vector<RegistrationStep>& steps) {
  if (o.mode == RegistrationMode::None) return true;
  FitControl r;
  if (!collectively(comm, [&] { r = registrationOptions(o, f.voxel, f.eps(), scans); }))
    return false;
  const std::unique_ptr<RegistrationField> grown =
      makeRegistrationField(f, o.field, resumed, scans, comm);
  TimedField field(*grown);
  const std::vector<Pose> given = scans.poses;
  const double start = MPI_Wtime();
  RegistrationCheckpointer checkpointer(checkpoints, scans, comm);
  try {
    registerScans(
        *scans.held, scans.poses, r, field, comm,
        [&](const RegistrationStep& s) {
          steps.push_back(s);
          if (progress.shows(Verbosity::verbose))
            printStep(s, scans, f.voxel);
          else
            progress.update("register", std::string(toString(s.algorithm)) + " round " +
                                            std::to_string(s.round) + ": " +
                                            std::to_string(steps.size()) + " fits so far");
        },
        state,
        [&](const RegistrationProgress& p, const std::vector<Pose>& poses) {
          if (p.ended && progress.shows(Verbosity::normal)) printRoundEnd(p, f.voxel);
          checkpointer(p, poses);
        });
  } catch (const mpi::Reported&) {
    return false;
  }
  const double fields = field.seconds(), fits = MPI_Wtime() - start - fields;
  char times[96];
  std::snprintf(times, sizeof times, "; fields %.2f s, fits %.2f s (%.2f ms a fit)", fields, fits,
                steps.empty() ? 0.0 : 1e3 * fits / static_cast<double>(steps.size()));
  progress.stage("register", std::string(toString(o.mode)) + ": " + std::to_string(steps.size()) +
                                 " fits" + times);
  warnStragglers(steps, scans, f.voxel, progress);
  reportOverlap(steps, progress);
  const bool simultaneous =
      o.mode == RegistrationMode::Simultaneous || o.mode == RegistrationMode::Both;
  if (simultaneous && !checkAgainstOthers(steps, scans, given, r, field, f.voxel, comm, progress))
    return false;
  return checkpointer.ok();
}

}  // namespace rangefuse
