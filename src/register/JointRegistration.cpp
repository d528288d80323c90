#include "JointRegistration.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

/// Fixed point for the sums of a share: parts of one share made on different ranks then add
/// exactly, in any order. Weights are at most 1 a point, residuals at most `maxResidual`; 2^40
/// units each leave room for 2^22 points in one voxel.
constexpr double kShareScale = 0x1p40;

/// One scan's control points whose foot points fall into one voxel, summed in fixed point.
struct ExactShare {
  uint64_t voxel = 0;  ///< position in the layout's bricks times voxels a brick, plus offset
  uint32_t scan = 0, points = 0;
  int64_t weight = 0, offset[3] = {};  ///< Σ w, Σ w (p − the voxel's centre)
};

/// Where a share goes: the voxel nearest to the control point's foot point on the field's
/// surface. Grouping by the point's own voxel would compare only points that lie in the same
/// cell along the normal, which hides how far apart the scans are.
struct FootVoxel {
  uint64_t voxel = 0;
  int owner = -1;  ///< -1: the foot point lies outside the field's bricks
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

FootVoxel footVoxel(const BrickLayout& layout, const Eigen::Vector3d& q, size_t perBrick, int me) {
  const VoxelGrid& g = layout.grid;
  const VoxelIndex v = g.nearest(q);
  FootVoxel foot;
  if ((v.array() < 0).any() || v.maxCoeff() >= (1 << 20)) return foot;
  const BrickCoord bc = brickOf(v, g.brick);
  const uint64_t code = mortonEncode(bc);
  foot.owner = layout.mayOwn(code, me);
  if (foot.owner < 0) return foot;
  const VoxelIndex l = v - bc * g.brick;
  const size_t B = static_cast<size_t>(g.brick);
  // Codes follow the bricks' order and leave room for the voxel (the lattice is at most 2^20
  // voxels an axis, so code x voxels a brick < 2^60).
  foot.voxel =
      code * perBrick + (static_cast<size_t>(l.z()) * B + l.y()) * B + static_cast<size_t>(l.x());
  foot.centre = g.centre(v);
  return foot;
}

/// Where control point p's line of sight (unit u toward the sensor) meets the plane the field
/// gives at p: with range noise along the rays this is where the point would be without it, so
/// which voxel a point joins does not depend on its noise. (Stepping back along the gradient
/// instead leaves the noise's tangential part, which, where the scan samples the surface more
/// densely on one side, sorts points by their noise: 0.25 voxel of bias at 1 voxel of noise.)
/// Along the gradient for grazing rays.
Eigen::Vector3d footPoint(const Eigen::Vector3d& p, const Eigen::Vector3d& u,
                          const FieldSample& f) {
  const double cosine = u.dot(f.f);
  if (cosine > 0.3) return p - u * (f.distance / cosine);
  return p - f.f * f.distance;
}

/// Shares keyed by voxel and scan; parts of one share add up exactly (fixed point).
class ShareTable {
 public:
  /// The share of `voxel` and `scan`, made empty on first use.
  ExactShare& at(uint64_t voxel, uint32_t scan) {
    auto [it, added] = index_.try_emplace(Key{voxel, scan}, shares_.size());
    if (added) {
      shares_.emplace_back();
      shares_.back().voxel = voxel;
      shares_.back().scan = scan;
    }
    return shares_[it->second];
  }
  void add(const ExactShare& part) {
    ExactShare& to = at(part.voxel, part.scan);
    to.points += part.points;
    to.weight += part.weight;
    for (int k = 0; k < 3; ++k) to.offset[k] += part.offset[k];
  }
  const std::vector<ExactShare>& shares() const { return shares_; }
  /// The shares by voxel, then scan: an order that does not depend on where they were made.
  std::vector<ExactShare> sorted() && {
    std::sort(shares_.begin(), shares_.end(), [](const ExactShare& a, const ExactShare& b) {
      return a.voxel != b.voxel ? a.voxel < b.voxel : a.scan < b.scan;
    });
    return std::move(shares_);
  }

 private:
  struct Key {
    uint64_t voxel;
    uint32_t scan;
    bool operator==(const Key& o) const { return voxel == o.voxel && scan == o.scan; }
  };
  struct Hash {
    size_t operator()(const Key& k) const { return k.voxel * 0x9E3779B97F4A7C15ull ^ k.scan; }
  };
  std::unordered_map<Key, size_t, Hash> index_;
  std::vector<ExactShare> shares_;
};

/// A value in fixed point (truncated: any rounding will do that is the same everywhere).
int64_t fixed(double v) {
  return static_cast<int64_t>(v * kShareScale);
}

/// Adds control point p of scan `scan` to its foot voxel's share.
void addPoint(ShareTable& shares, const FootVoxel& foot, uint32_t scan, const Eigen::Vector3d& p,
              double w, double maxResidual) {
  ExactShare& e = shares.at(foot.voxel, scan);
  e.points += 1;
  e.weight += fixed(w);
  for (int k = 0; k < 3; ++k) e.offset[k] += fixed(w * (p[k] - foot.centre[k]) / maxResidual);
}

/// This rank's and the received parts of the shares of the voxels this rank owns, sorted.
std::vector<ExactShare> exactShares(const std::vector<Pose>& poses, const BrickStore& store,
                                    ControlRouting& control, const CorrespondenceSettings& settings,
                                    double maxResidual, MPI_Comm comm) {
  const int me = mpi::rank(comm);
  std::vector<ShareTable> parts(static_cast<size_t>(mpi::size(comm)));
  for (size_t i = 0; i < poses.size(); ++i) {
    const ControlPoints c = control.at(i, poses[i], store);
    BrickCache cache;
    for (size_t k = 0; k < c.points.size(); ++k) {
      FieldSample f;
      if (!(c.weights[k] > 0) ||
          !sampleField(store, c.points[k], c.normals[k], settings, f, &cache))
        continue;
      const Eigen::Vector3d q = footPoint(c.points[k], c.sensor.toward(c.points[k]), f);
      const FootVoxel foot = footVoxel(store.layout(), q, store.voxelsPerBrick(), me);
      if (foot.owner < 0) continue;
      addPoint(parts[foot.owner], foot, static_cast<uint32_t>(i), c.points[k],
               std::min(1.0, c.weights[k]), maxResidual);
    }
  }
  std::vector<std::vector<char>> out(parts.size());
  for (size_t r = 0; r < parts.size(); ++r)
    if (static_cast<int>(r) != me)
      mpi::pack(out[r], parts[r].shares().data(), parts[r].shares().size());
  ShareTable mine = std::move(parts[me]);
  for (const auto& buf : mpi::exchangeBytes(std::move(out), comm))
    for (size_t at = 0; at < buf.size();) {
      ExactShare e;
      mpi::unpack(buf, at, &e, 1);
      mine.add(e);
    }
  return std::move(mine).sorted();
}

/// The field at voxel `voxel` (brick code x voxels a brick + voxel in the brick): its centre, unit
/// gradient and distance; false when the field is too light there.
bool voxelPlane(const BrickStore& store, uint64_t voxel, float minWeight, Eigen::Vector3d& centre,
                Eigen::Vector3d& f, double& d) {
  const size_t perBrick = store.voxelsPerBrick(), inBrick = voxel % perBrick;
  const int64_t found = store.localBrick(voxel / perBrick);
  if (found < 0) return false;  // a brick in this rank's range that does not exist
  const size_t local = static_cast<size_t>(found);
  const VoxelSums& sums = store.sums()[local * perBrick + inBrick];
  f = Eigen::Vector3d(sums.wf[0], sums.wf[1], sums.wf[2]);
  if (!(sums.w > minWeight) || !(f.norm() > 0)) return false;
  f.normalize();
  d = sums.wd / sums.w;
  const VoxelGrid& g = store.grid();
  const int B = g.brick;
  const VoxelIndex l(static_cast<int>(inBrick % B), static_cast<int>(inBrick / B % B),
                     static_cast<int>(inBrick / B / B));
  centre = g.centre(mortonDecode(store.code(local)) * B + l);
  return true;
}

/// The shares per voxel in scan order (the map's order), as doubles. A share's residual is the
/// distance of its points' centroid along the voxel's own gradient, from the voxel's own plane,
/// and every share of a voxel moves with the Jacobian of the voxel's surface point: the control
/// points' noise along their rays would otherwise correlate with the residuals and bias the
/// poses (errors in variables), and voxels far from the surface hold a less linear field.
std::vector<std::vector<VoxelShare>> voxelShares(const std::vector<ExactShare>& exact,
                                                 const BrickStore& store, const MotionFrame& frame,
                                                 float minWeight, double maxResidual) {
  std::vector<std::vector<VoxelShare>> voxels;
  uint64_t last = ~uint64_t{0};
  Vector6d a = Vector6d::Zero();
  Eigen::Vector3d centre, f;
  double d = 0;
  bool usable = false;
  for (const ExactShare& e : exact) {
    if (e.voxel != last) {
      last = e.voxel;
      usable = voxelPlane(store, e.voxel, minWeight, centre, f, d);
      if (usable) a << (centre - f * d - frame.centre).cross(f) / frame.length, f;
      if (usable) voxels.emplace_back();
    }
    if (!usable || e.weight <= 0) continue;
    VoxelShare s;
    s.scan = e.scan;
    s.points = e.points;
    s.weight = static_cast<double>(e.weight) / kShareScale;
    s.jacobian = s.weight * a;
    Eigen::Vector3d offset;
    for (int k = 0; k < 3; ++k)
      offset[k] = static_cast<double>(e.offset[k]) / kShareScale * maxResidual;
    s.residual = s.weight * d + f.dot(offset);  // Σ w (d + f.(p − centre))
    voxels.back().push_back(s);
  }
  return voxels;
}

/// How far a motion moves points at most `frame.length` from the centre (to first order).
double reach(const Vector6d& delta) {
  return delta.head<3>().norm() + delta.tail<3>().norm();
}

}  // namespace

std::vector<RegistrationStep> jointStep(std::vector<Pose>& poses, const BrickStore& store,
                                        ControlRouting& control, const JointStepSettings& s,
                                        MPI_Comm comm) {
  // About the control points' ball at these poses: a frame that depends on the scans alone,
  // so a run resumed with a field of other bricks takes the same steps.
  const Eigen::Vector4d ball = control.ball(poses);
  const MotionFrame frame{ball.head<3>(), ball[3] + s.field.maxDistance + store.grid().voxel};
  const double maxResidual = s.field.maxDistance + store.grid().voxel;
  const auto voxels = voxelShares(exactShares(poses, store, control, s.field, maxResidual, comm),
                                  store, frame, s.field.minWeight, maxResidual);
  const JointEquations eq = reduceJointEquations(voxels, poses.size(), maxResidual, comm);
  std::vector<char> free(poses.size());
  for (size_t i = 0; i < poses.size(); ++i)
    free[i] = i != s.anchor && eq.points[i] >= s.minCorrespondences;
  std::vector<Vector6d> delta = solveJoint(eq, free);
  // Far from the optimum the linear step may overshoot the envelope the planes hold in.
  double largest = 0;
  for (const Vector6d& d : delta) largest = std::max(largest, reach(d));
  const double shrink = largest > s.maxStep ? s.maxStep / largest : 1.0;
  std::vector<RegistrationStep> steps(poses.size());
  for (const auto& [pair, points] : eq.pairPoints)
    steps[pair.first].overlap.emplace_back(pair.second, points);
  for (size_t i = 0; i < poses.size(); ++i) {
    RegistrationStep& step = steps[i];
    step.scan = i;
    step.correspondences = eq.points[i];
    step.rms = eq.rms(i);
    step.applied = free[i] || i == s.anchor;  // the anchor is where it belongs
    if (!free[i]) continue;
    step.loose =
        loosestMotion(eq.blocks.at({static_cast<uint32_t>(i), static_cast<uint32_t>(i)}), frame);
    const Pose m = motionPose(shrink * delta[i], frame);
    poses[i] = m * poses[i];
    step.rotationDeg = rotationDegrees(m.R);
    step.translation = shrink * delta[i].tail<3>().norm();
  }
  return steps;
}

}  // namespace rangefuse
