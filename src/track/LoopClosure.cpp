#include "rangefuse/track/LoopClosure.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "KeyFrameFit.h"
#include "PoseGraph.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/prism/PrismField.h"
#include "rangefuse/register/Correspondences.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {
namespace internal {
namespace {

/// How far a motion moves points at `range` from its origin: its translation plus its turn.
double displacement(const Pose& motion, double range) {
  return motion.t.norm() + range * Eigen::AngleAxisd(motion.R).angle();
}

/// Every few of frame i's points with a positive confidence, at most `most`, and their
/// normals, in the frame's own coordinates; from its reader, on every rank.
KeyFramePoints keyFramePoints(const ScanSource& frames, size_t i, size_t most, MPI_Comm comm) {
  std::vector<double> packed;
  const int me = mpi::rank(comm);
  int reader = frames.holds(i) ? me : -1;
  MPI_Allreduce(MPI_IN_PLACE, &reader, 1, MPI_INT, MPI_MAX, comm);
  if (reader < 0) throw InputError("frame " + std::to_string(i) + " is held by no rank");
  if (me == reader) {
    const ScanSurface& s = frames.get(i)->surface;
    size_t valid = 0;
    for (const double c : s.confidence) valid += c > 0;
    const size_t stride = std::max<size_t>(1, (valid + most - 1) / most);
    for (size_t v = 0, k = 0; v < s.points.size(); ++v)
      if (s.confidence[v] > 0 && k++ % stride == 0) {
        packed.insert(packed.end(), s.points[v].data(), s.points[v].data() + 3);
        packed.insert(packed.end(), s.normals[v].data(), s.normals[v].data() + 3);
      }
  }
  unsigned long count = packed.size();
  MPI_Bcast(&count, 1, MPI_UNSIGNED_LONG, reader, comm);
  packed.resize(count);
  MPI_Bcast(packed.data(), static_cast<int>(count), MPI_DOUBLE, reader, comm);
  std::vector<Eigen::Vector3d> points, normals;
  for (size_t k = 0; k + 6 <= packed.size(); k += 6) {
    points.emplace_back(packed[k], packed[k + 1], packed[k + 2]);
    normals.emplace_back(packed[k + 3], packed[k + 4], packed[k + 5]);
  }
  return KeyFramePoints(std::move(points), std::move(normals));
}

/// The key frame's points (at `pose`) moved onto the field's surface, those without a
/// correspondence left out: the field averages the depth steps and noise of the frames fused
/// into it, which a loop's target should not carry. The rank owning each point's voxel moves it.
KeyFramePoints onField(const KeyFramePoints& raw, const Pose& pose, const BrickStore& field,
                       double eps, MPI_Comm comm) {
  const size_t n = raw.points().size();
  std::vector<double> moved(4 * n, 0.0);
  CorrespondenceSettings cs;
  cs.maxDistance = eps;
  BrickCache cache;
  for (size_t k = 0; k < n; ++k) {
    Correspondence c;
    if (!correspondence(field, pose.apply(raw.points()[k]), pose.R * raw.normals()[k], cs, c,
                        &cache))
      continue;
    const Eigen::Vector3d local = pose.inverse().apply(c.q);
    moved[4 * k] = local.x(), moved[4 * k + 1] = local.y(), moved[4 * k + 2] = local.z();
    moved[4 * k + 3] = 1;
  }
  // One rank owns each voxel: the sum is that rank's value, exactly, on any rank count.
  MPI_Allreduce(MPI_IN_PLACE, moved.data(), static_cast<int>(moved.size()), MPI_DOUBLE, MPI_SUM,
                comm);
  std::vector<Eigen::Vector3d> points, normals;
  for (size_t k = 0; k < n; ++k)
    if (moved[4 * k + 3] == 1) {
      points.emplace_back(moved[4 * k], moved[4 * k + 1], moved[4 * k + 2]);
      normals.push_back(raw.normals()[k]);
    }
  return KeyFramePoints(std::move(points), std::move(normals));
}

/// The information of a measured motion with a floor, so that a direction the two key frames
/// do not pin (a plane seen by both) leaves the graph solvable and takes what the others give.
Matrix6d floored(Matrix6d information) {
  const double floor = 1e-6 * std::max(1.0, information.diagonal().maxCoeff());
  information.diagonal().array() += floor;
  return information;
}

/// True when the fit pins every direction: its smallest eigenvalue, rotations counted as
/// motions at `range`, is at least 1e-4 of its largest (a bunny seen from 2.6 m gives 5e-4).
bool wellPosed(const Matrix6d& information, double range) {
  Matrix6d scaled = information;
  scaled.bottomRows<3>() /= range;
  scaled.rightCols<3>() /= range;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(scaled, Eigen::EigenvaluesOnly);
  const auto& v = eig.eigenvalues();
  return v(5) > 0 && v(0) >= 1e-4 * v(5);
}

}  // namespace

/// The key frames of a stream, the motions measured between them, and the loops.
class KeyFrames {
  /// A loop is fitted to the key frame it overlaps and this many on either side of it.
  static constexpr size_t kMapSide = 2;

 public:
  KeyFrames(const LoopSettings& s, const ScanSource& frames, MPI_Comm comm)
      : s_(s), frames_(frames), comm_(comm) {}

  bool fused(size_t i, std::vector<Pose>& poses, const BrickStore& field) {
    if (!s_.enabled || !isKey(i, poses)) return false;
    const double start = MPI_Wtime();
    add(i, poses);
    surface_.push_back(onField(points_.back(), poses[i], field, s_.eps, comm_));
    const bool moved = closeLoop(poses);
    seconds_ += MPI_Wtime() - start;
    return moved;
  }

  bool finish(std::vector<Pose>& poses) {
    if (!s_.enabled || keyFrames_.size() < 2 || !pending_) return false;
    const double start = MPI_Wtime();
    const bool moved = solve(poses, poses.size() - 1);
    seconds_ += MPI_Wtime() - start;
    return moved;
  }

  nlohmann::json state() const {
    nlohmann::json edges = nlohmann::json::array();
    for (const PoseEdge& e : edges_) {
      const Eigen::Quaterniond q(e.measured.R);
      std::vector<double> info(e.information.data(), e.information.data() + 36);
      edges.push_back(
          {{"from", e.from},
           {"to", e.to},
           {"motion",
            {e.measured.t.x(), e.measured.t.y(), e.measured.t.z(), q.x(), q.y(), q.z(), q.w()}},
           {"information", info}});
    }
    return {
        {"key_frames", keyFrames_}, {"edges", edges}, {"loops", loops_}, {"closures", closures_}};
  }

  void restore(const nlohmann::json& j, const std::string& where) {
    try {
      keyFrames_ = j.at("key_frames").get<std::vector<size_t>>();
      loops_ = j.at("loops").get<size_t>();
      closures_ = j.at("closures").get<size_t>();
      edges_.clear();
      for (const nlohmann::json& e : j.at("edges")) {
        PoseEdge edge;
        edge.from = e.at("from").get<size_t>();
        edge.to = e.at("to").get<size_t>();
        const auto m = e.at("motion").get<std::vector<double>>();
        const auto info = e.at("information").get<std::vector<double>>();
        if (m.size() != 7 || info.size() != 36 || edge.from >= keyFrames_.size() ||
            edge.to >= keyFrames_.size())
          throw InputError(where + ": a measured motion between key frames is malformed");
        edge.measured.R =
            Eigen::Quaterniond(m[6], m[3], m[4], m[5]).normalized().toRotationMatrix();
        edge.measured.t = Eigen::Vector3d(m[0], m[1], m[2]);
        edge.information = Eigen::Map<const Matrix6d>(info.data());
        edges_.push_back(edge);
      }
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where + ": key frames unreadable (" + e.what() + ")");
    }
    for (const size_t f : keyFrames_)
      if (f >= frames_.size()) throw InputError(where + ": a key frame is not in the stream");
    points_.clear(), surface_.clear();
    for (const size_t f : keyFrames_) {
      points_.push_back(keyFramePoints(frames_, f, s_.keyPoints, comm_));
      // The field each was fused into is gone: a resumed stream's loops fit raw points.
      surface_.push_back(KeyFramePoints(points_.back().points(), points_.back().normals()));
    }
  }

  size_t keyFrames() const { return keyFrames_.size(); }
  size_t loops() const { return loops_; }
  size_t closures() const { return closures_; }
  double seconds() const { return seconds_; }

 private:
  /// Whether fused frame i becomes a key frame: the first, or the camera moved or turned far
  /// enough from the last one.
  bool isKey(size_t i, const std::vector<Pose>& poses) const {
    if (keyFrames_.empty()) return true;
    const Pose m = relative(poses[keyFrames_.back()], poses[i]);
    return m.t.norm() > s_.keyStepShare * points_.back().medianRange() ||
           rotationDegrees(m.R) > s_.keyTurnDeg;
  }

  /// Keeps frame i as a key frame, with the tracked motion from the last one as an edge.
  void add(size_t i, const std::vector<Pose>& poses) {
    points_.push_back(keyFramePoints(frames_, i, s_.keyPoints, comm_));
    keyFrames_.push_back(i);
    const size_t k = keyFrames_.size() - 1;
    if (k == 0) return;
    PoseEdge e;
    e.from = k - 1, e.to = k;
    e.measured = relative(poses[keyFrames_[k - 1]], poses[i]);
    e.information = floored(
        measurePair(points_[k - 1], points_[k], e.measured, s_.endVoxels * s_.voxel, s_.voxel)
            .information);
    edges_.push_back(e);
  }

  /// The earlier key frame the newest one overlaps most, at least minInliers of its points
  /// within the start radius, from a time at least minLoopFrames before; -1 when none.
  long loopCandidate(const std::vector<Pose>& poses) const {
    const size_t k = keyFrames_.size() - 1;
    const Pose& here = poses[keyFrames_[k]];
    long best = -1;
    double bestShare = s_.minInliers;
    for (size_t j = 0; j + 1 < k; ++j) {
      if (keyFrames_[j] + s_.minLoopFrames > keyFrames_[k]) break;
      const Pose& there = poses[keyFrames_[j]];
      const double range = points_[j].medianRange();
      if ((here.t - there.t).norm() > range) continue;
      if ((here.R * points_[k].view()).dot(there.R * points_[j].view()) < std::cos(M_PI / 4))
        continue;
      const double share =
          overlapShare(points_[j], points_[k], relative(there, here), s_.startVoxels * s_.voxel);
      if (share > bestShare) bestShare = share, best = static_cast<long>(j);
    }
    return best;
  }

  /// The points of key frame j and its neighbours (those at least minLoopFrames before frame
  /// `before`) in j's frame, at their poses: a loop fitted to one key frame alone leaves the
  /// directions its view pins weakly to noise.
  KeyFramePoints localMap(size_t j, size_t before, const std::vector<Pose>& poses) const {
    std::vector<Eigen::Vector3d> points, normals;
    const size_t first = j >= kMapSide ? j - kMapSide : 0;
    for (size_t m = first; m <= j + kMapSide && m < keyFrames_.size(); ++m) {
      if (keyFrames_[m] + s_.minLoopFrames > before) break;
      const Pose into = relative(poses[keyFrames_[j]], poses[keyFrames_[m]]);
      for (size_t p = 0; p < surface_[m].points().size(); ++p) {
        points.push_back(into.apply(surface_[m].points()[p]));
        normals.push_back(into.R * surface_[m].normals()[p]);
      }
    }
    return KeyFramePoints(std::move(points), std::move(normals));
  }

  /// Fits the newest key frame to the earlier one it overlaps most; when the fit holds and the
  /// poses disagree with it by more than closeVoxels, solves the graph and moves every frame
  /// with its key frame. True when poses moved.
  bool closeLoop(std::vector<Pose>& poses) {
    const long candidate = loopCandidate(poses);
    if (candidate < 0) return false;
    const size_t j = static_cast<size_t>(candidate), k = keyFrames_.size() - 1;
    const Pose tracked = relative(poses[keyFrames_[j]], poses[keyFrames_[k]]);
    PairFitSettings fs;
    fs.startRadius = s_.startVoxels * s_.voxel;
    fs.endRadius = s_.endVoxels * s_.voxel;
    fs.huber = s_.voxel;
    const KeyFramePoints map = localMap(j, keyFrames_[k], poses);
    const PairFit fit = fitPair(map, points_[k], tracked, fs);
    const double range = points_[j].medianRange();
    if (fit.inliers < s_.minInliers || fit.rms > fs.endRadius / 2 ||
        displacement(relative(tracked, fit.motion), range) > fs.startRadius ||
        !wellPosed(fit.information, range))
      return false;
    ++loops_;
    PoseEdge loop;
    loop.from = j, loop.to = k;
    loop.measured = fit.motion;
    loop.information = floored(fit.information);
    edges_.push_back(loop);
    const double off = displacement(relative(tracked, fit.motion), range);
    if (off < s_.closeVoxels * s_.voxel) return false;
    pending_ = true;
    // Tracking goes on well against a field a few voxels off; building it again costs about
    // what fusing the frames did, so it waits for a large disagreement or the stream's end.
    if (off < s_.trackVoxels * s_.voxel || keyFrames_[k] < lastClosed_ + s_.closeEvery)
      return false;
    return solve(poses, keyFrames_[k]);
  }

  /// Solves the graph and moves frames 0..last with their key frames (the last key frame at or
  /// before each). True when a key frame moved by closeVoxels or more.
  bool solve(std::vector<Pose>& poses, size_t last) {
    pending_ = false;
    std::vector<Pose> before, after;
    for (const size_t f : keyFrames_) before.push_back(poses[f]);
    after = before;
    optimisePoseGraph(after, edges_);
    double largest = 0;
    for (size_t k = 0; k < after.size(); ++k)
      largest =
          std::max(largest, displacement(relative(before[k], after[k]), points_[k].medianRange()));
    if (!(largest >= s_.closeVoxels * s_.voxel)) return false;
    // Frame f follows the last key frame at or before it.
    size_t k = 0;
    for (size_t f = 0; f <= last; ++f) {
      while (k + 1 < keyFrames_.size() && keyFrames_[k + 1] <= f) ++k;
      poses[f] = after[k] * before[k].inverse() * poses[f];
    }
    ++closures_;
    lastClosed_ = keyFrames_.back();
    return true;
  }

  const LoopSettings s_;
  const ScanSource& frames_;
  MPI_Comm comm_;
  std::vector<size_t> keyFrames_;        ///< frame numbers, in order
  std::vector<KeyFramePoints> points_;   ///< as the frame measured them
  std::vector<KeyFramePoints> surface_;  ///< moved onto the field they were fused into
  std::vector<PoseEdge> edges_;
  size_t loops_ = 0, closures_ = 0;
  bool pending_ = false;   ///< a loop measured since the last closure disagrees with the poses
  size_t lastClosed_ = 0;  ///< the frame whose key frame closed the last loop
  double seconds_ = 0;
};

}  // namespace internal

LoopClosure::LoopClosure(const LoopSettings& s, const ScanSource& frames, MPI_Comm comm)
    : keys_(std::make_unique<internal::KeyFrames>(s, frames, comm)) {}
LoopClosure::~LoopClosure() = default;
bool LoopClosure::fused(size_t i, std::vector<Pose>& poses, const BrickStore& field) {
  return keys_->fused(i, poses, field);
}
bool LoopClosure::finish(std::vector<Pose>& poses) {
  return keys_->finish(poses);
}
nlohmann::json LoopClosure::state() const {
  return keys_->state();
}
void LoopClosure::restore(const nlohmann::json& j, const std::string& where) {
  keys_->restore(j, where);
}
size_t LoopClosure::keyFrames() const {
  return keys_->keyFrames();
}
size_t LoopClosure::loops() const {
  return keys_->loops();
}
size_t LoopClosure::closures() const {
  return keys_->closures();
}
double LoopClosure::seconds() const {
  return keys_->seconds();
}

}  // namespace rangefuse
