// Registration of every scan against the fused field: Tubic et al. Algorithm 1 (incremental)
// and Algorithm 2 (simultaneous), with correspondence sums reduced across ranks.
#pragma once

#include <mpi.h>

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/register/Correspondences.h"
#include "rangefuse/register/LooseMotion.h"
#include "rangefuse/register/RegistrationMode.h"
#include "rangefuse/register/ScanSource.h"

namespace rangefuse {

/// How registration fits run and when they stop: the algorithm's own parameters (the user's
/// are RegistrationSettings, converted by the registration stage).
struct FitControl {
  RegistrationMode mode = RegistrationMode::None;
  size_t anchor = 0;        ///< the scan that fixes the frame
  int controlStride = 1;    ///< every k-th vertex is a control point
  int maxIterations = 100;  ///< fits per scan (Algorithm 1) or per round (Algorithm 2)
  int maxRounds = 8;        ///< Algorithm 2: field rebuilds
  RegistrationSolve solve = RegistrationSolve::Joint;  ///< Algorithm 2's fits
  double rotationTolDeg = 1e-3;       ///< converged when a fit turns less than this ...
  double translationTol = 0;          ///< ... and moves less than this (world units)
  double jointRotationTolDeg = 0.01;  ///< a joint step converged below this ...
  double jointTranslationTol = 0;     ///< ... and this (world units)
  size_t minCorrespondences = 50;     ///< fewer: the scan is reported and left where it is
  bool accelerate = true;             ///< extrapolate steadily converging fits
  double maxExtrapolation = 1e300;    ///< ... to at most this motion (world units at the radius)
  double roundTolerance = 0;          ///< Algorithm 2 stops when a round moves no scan this far
  CorrespondenceSettings correspondences;
};

/// Which fit made a step: Algorithm 1's, Algorithm 2's joint solve, Algorithm 2's per-scan
/// fits, or the check of a scan against the other scans alone (fitAgainstOthers: it does not
/// move the scan).
enum class FitAlgorithm { Incremental, Joint, Simultaneous, Others };

/// Where a registration stands: not begun, in Algorithm 1, in Algorithm 2, or finished.
enum class RegistrationPhase { Start, Incremental, Simultaneous, Done };

/// The names the progress lines, reports and checkpoints use.
const char* toString(FitAlgorithm algorithm);
const char* toString(RegistrationPhase phase);

/// The phase named `text`; throws std::runtime_error for another name.
RegistrationPhase parseRegistrationPhase(const std::string& text);

/// One fit of one scan, for the report and the progress lines.
struct RegistrationStep {
  FitAlgorithm algorithm = FitAlgorithm::Incremental;
  int round = 0, iteration = 0;
  size_t scan = 0;
  uint64_t correspondences = 0;
  double rms = 0;           ///< weighted RMS distance to the correspondences, before the fit
  double rotationDeg = 0;   ///< the fit's rotation
  double translation = 0;   ///< the fit's translation, world units
  bool applied = false;     ///< false when too few correspondences (and for Others)
  double othersMotion = 0;  ///< Others: the mean vertex motion the fit makes, world units
  LooseMotion loose;        ///< the joint solve's loosest motion of the scan (other fits: none)
  /// The joint solve's overlap of this scan with each later scan t it shares voxels with: the
  /// control points of both there (other fits: none).
  std::vector<std::pair<uint32_t, uint64_t>> overlap;
};

/// A fit's motion as a twist about the control points' centroid: rotation vector and shift of
/// the centroid; `radius` (the points' RMS radius) scales rotation into a length.
struct Twist {
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  double radius = 1;
};

/// The previous fit of a scan, for acceleration.
struct FitHistory {
  bool have = false;
  Twist last;
};

/// The end of a round of Algorithm 2, for the progress lines.
struct RoundEnd {
  int round = 0;
  double motion = 0;  ///< the largest mean vertex motion of a scan in the round, world units
};

/// Where registration stands, enough to continue it exactly (checkpoints).
struct RegistrationProgress {
  RegistrationPhase phase = RegistrationPhase::Start;
  size_t nextScan = 0;                ///< incremental: the next scan to register
  int round = 1;                      ///< simultaneous: the round in progress
  int iteration = 0;                  ///< simultaneous: iterations done in this round
  bool roundMoved = false;            ///< simultaneous: this round's first iteration moved a scan
  bool lastMoved = true;              ///< simultaneous: the last iteration moved a scan
  std::vector<Pose> roundPoses;       ///< simultaneous: the poses this round's field is built from
  std::vector<FitHistory> history;    ///< simultaneous: per scan
  std::vector<double> latticeOrigin;  ///< the fields' lattice (empty: not chosen yet)
  std::optional<RoundEnd> ended;      ///< set for the boundary that ends a round (not saved)

  nlohmann::json toJson() const;
  static RegistrationProgress fromJson(const nlohmann::json& j);
};

/// The field registration fits against. Every call is collective and returns the field.
class RegistrationField {
 public:
  virtual ~RegistrationField() = default;
  /// Fixes the lattice of every field to come: `origin` when given (a resumed run), else one
  /// chosen around the scans at `poses`. Returns the origin, for checkpoints.
  virtual std::vector<double> fixLattice(const std::vector<double>& origin,
                                         const std::vector<Pose>& poses) = 0;
  /// The field of the listed scans at their poses.
  virtual const BrickStore& build(const std::vector<size_t>& scans,
                                  const std::vector<Pose>& poses) = 0;
  /// The last field with scan `i` added at poses[i]: voxel by voxel what build() of the longer
  /// list gives. May move the lattice when the scan leaves it (see latticeOrigin()).
  virtual const BrickStore& add(size_t i, const std::vector<Pose>& poses) = 0;
  /// The lattice origin now in use.
  virtual std::vector<double> latticeOrigin() const = 0;
};

/// Called at every boundary (after each scan of Algorithm 1, each iteration of Algorithm 2).
using BoundaryCallback = std::function<void(const RegistrationProgress&, const std::vector<Pose>&)>;

/// Collective: refines `poses` (the anchor never moves), continuing from `progress`. `scans`
/// are in their own frames; a rank holds only the scans it read (the others are empty), and
/// the field's calls route them. `onStep` sees every fit (rank 0 prints it); `onBoundary` every
/// point a checkpoint may be taken. Every rank ends with the same poses.
void registerScans(const ScanSource& scans, std::vector<Pose>& poses, const FitControl& options,
                   RegistrationField& field, MPI_Comm comm,
                   const std::function<void(const RegistrationStep&)>& onStep,
                   RegistrationProgress& progress, const BoundaryCallback& onBoundary);

/// Collective: where the other scans put each of the scans `which` (not the anchor): its fit
/// against the field of all the others at `poses` (Algorithm 1's fits and settings), from its
/// registered pose. A scan in the field it fits against pulls that field toward itself, so
/// Algorithm 2 can leave a scan that started far off short of where its overlaps put it, with
/// a residual like everyone's; this fit cannot. Returns an Others step per scan (its first
/// fit's residual and correspondences, and othersMotion); `poses` do not change. A field is
/// built for each scan. Every rank returns the same, in the order of `which`.
std::vector<RegistrationStep> fitAgainstOthers(const ScanSource& scans,
                                               const std::vector<Pose>& poses,
                                               const FitControl& options, RegistrationField& field,
                                               const std::vector<size_t>& which, MPI_Comm comm);

/// Collective: each scan's mean vertex displacement between two sets of poses (every 16th
/// vertex). Every rank returns the same.
std::vector<double> scanMotions(const ScanSource& scans, const std::vector<Pose>& from,
                                const std::vector<Pose>& to, MPI_Comm comm);

/// The change a fit makes: rotation angle (degrees) and translation length.
double rotationDegrees(const Eigen::Matrix3d& R);

}  // namespace rangefuse
