#include "rangefuse/register/ControlRouting.h"

#include <algorithm>
#include <unordered_map>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

/// A control point on its way to a rank that may evaluate it.
struct RoutedPoint {
  uint64_t scan;
  uint64_t vertex;  ///< in the scan, for coarser levels chosen alike on any rank count
  Eigen::Vector3d p, n;
  double w;
};

/// The ranks that may own brick c or one of its 26 neighbours (BrickLayout::mayOwn), each once.
std::vector<int> ownersAround(const BrickLayout& layout, const BrickCoord& c, int me) {
  std::vector<int> ranks;
  for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x) {
        const BrickCoord n = c + BrickCoord(x, y, z);
        if ((n.array() < 0).any()) continue;
        const int owner = layout.mayOwn(mortonEncode(n), me);
        if (owner < 0) continue;
        if (std::find(ranks.begin(), ranks.end(), owner) == ranks.end()) ranks.push_back(owner);
      }
  return ranks;
}

/// Centre and radius of a ball around the scan's control points (its box's), zero if none;
/// `count` gets their number.
Eigen::Vector4d sphereOf(const PrismScan& scan, int stride, double& count) {
  const ScanSurface& s = scan.surface;
  Eigen::AlignedBox3d box;
  for (size_t v = 0; v < s.points.size(); v += stride)
    if (s.confidence[v] > 0) box.extend(s.points[v]), ++count;
  if (box.isEmpty()) return Eigen::Vector4d::Zero();
  const Eigen::Vector3d c = box.center();
  Eigen::Vector4d sphere;
  sphere << c, (box.max() - c).norm();
  return sphere;
}

/// A sensor as 7 numbers (a flag, point, direction), for sharing by summation.
void packSensor(const Sensor& s, double* out) {
  out[0] = s.isPoint ? 1 : 0;
  for (int k = 0; k < 3; ++k) out[1 + k] = s.point[k], out[4 + k] = s.direction[k];
}

Sensor unpackSensor(const double* in) {
  return Sensor{in[0] > 0.5, Eigen::Vector3d(in[1], in[2], in[3]),
                Eigen::Vector3d(in[4], in[5], in[6])};
}

}  // namespace

ControlRouting::ControlRouting(const ScanSource& scans, int stride, MPI_Comm comm, bool lazy,
                               double noiseFloor)
    : scans_(scans),
      stride_(stride),
      noiseFloor_(noiseFloor),
      comm_(comm),
      spheres_(scans.size(), Eigen::Vector4d::Zero()),
      sensors_(scans.size()),
      counts_(scans.size(), 0.0),
      known_(scans.size(), 0),
      held_(scans.size()) {
  if (lazy) return;
  std::vector<size_t> all(scans.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  learn(all);
}

void ControlRouting::follow() {
  const size_t n = scans_.size();
  spheres_.resize(n, Eigen::Vector4d::Zero());
  sensors_.resize(n);
  counts_.resize(n, 0.0);
  known_.resize(n, 0);
  held_.resize(n);
}

void ControlRouting::learn(const std::vector<size_t>& which) {
  std::vector<size_t> unknown;
  for (size_t i : which)
    if (!known_[i]) unknown.push_back(i);
  if (unknown.empty()) return;
  // Each scan is held by one rank, which alone fills its numbers: a sum shares them.
  std::vector<double> numbers(12 * unknown.size(), 0.0);
  // A scan read again may fail on one rank: every rank then throws here.
  mpi::collectivelyOrThrow(comm_, [&] {
    for (size_t k = 0; k < unknown.size(); ++k) {
      if (!scans_.holds(unknown[k])) continue;
      const std::shared_ptr<const PrismScan> scan = scans_.get(unknown[k]);
      double* out = &numbers[12 * k];
      const Eigen::Vector4d sphere = sphereOf(*scan, stride_, out[11]);
      std::copy(sphere.data(), sphere.data() + 4, out);
      packSensor(scan->surface.sensor, out + 4);
    }
  });
  MPI_Allreduce(MPI_IN_PLACE, numbers.data(), static_cast<int>(numbers.size()), MPI_DOUBLE, MPI_SUM,
                comm_);
  for (size_t k = 0; k < unknown.size(); ++k) {
    const size_t i = unknown[k];
    const double* in = &numbers[12 * k];
    spheres_[i] = Eigen::Vector4d(in[0], in[1], in[2], in[3]);
    sensors_[i] = unpackSensor(in + 4);
    counts_[i] = in[11];
    known_[i] = 1;
  }
}

Eigen::Vector4d ControlRouting::ball(const std::vector<Pose>& poses) const {
  Eigen::AlignedBox3d box;
  for (size_t i = 0; i < spheres_.size(); ++i)
    if (spheres_[i][3] > 0) box.extend(poses[i].apply(spheres_[i].head<3>()));
  if (box.isEmpty()) return Eigen::Vector4d::Zero();
  const Eigen::Vector3d c = box.center();
  double r = 0;
  for (size_t i = 0; i < spheres_.size(); ++i)
    if (spheres_[i][3] > 0)
      r = std::max(r, (poses[i].apply(spheres_[i].head<3>()) - c).norm() + spheres_[i][3]);
  Eigen::Vector4d out;
  out << c, r;
  return out;
}

double ControlRouting::motionBound(size_t i, const Pose& from, const Pose& to) const {
  // R x + t - (R0 x + t0) = (R - R0)(x - c) + (R - R0) c + t - t0, and |x - c| <= r.
  const Eigen::Vector3d c = spheres_[i].head<3>();
  const Eigen::Matrix3d dR = to.R - from.R;
  return dR.norm() * spheres_[i][3] + (dR * c + to.t - from.t).norm();
}

void ControlRouting::route(const std::vector<size_t>& which, const std::vector<Pose>& poses,
                           const BrickStore& store) {
  learn(which);
  const BrickLayout& layout = store.layout();
  std::unordered_map<uint64_t, std::vector<int>> owners;
  const int me = mpi::rank(comm_), ranks = mpi::size(comm_);
  for (size_t i : which) held_[i] = Held{poses[i], nullptr, {}, {}, {}, {}, {}};
  // In windows of as many scans as ranks: only a window's points are in flight at once.
  for (size_t first = 0; first < which.size(); first += ranks) {
    const size_t end = std::min(which.size(), first + ranks);
    std::vector<std::vector<char>> out(ranks);
    // A scan read again may fail on one rank: every rank then throws before the exchange.
    mpi::collectivelyOrThrow(comm_, [&] {
      for (size_t k = first; k < end; ++k)
        if (scans_.holds(which[k]))
          packControlPoints(which[k], poses[which[k]], layout, me, owners, out);
    });
    receive(mpi::exchangeBytes(std::move(out), comm_), store);
  }
}

void ControlRouting::receive(const std::vector<std::vector<char>>& in, const BrickStore& store) {
  const VoxelGrid& g = store.grid();
  std::unordered_map<uint64_t, bool> near;  // per brick: an own brick is it or a neighbour
  auto nearOwn = [&](uint64_t code) {
    auto it = near.find(code);
    if (it != near.end()) return it->second;
    bool found = store.localBrick(code) >= 0;
    for (uint64_t n : neighbourCodes(code)) found = found || store.localBrick(n) >= 0;
    return near.emplace(code, found).first->second;
  };
  // Each scan comes from the one rank holding it, in its order.
  for (const auto& buf : in) {
    for (size_t at = 0; at < buf.size();) {
      RoutedPoint p;
      mpi::unpack(buf, at, &p, 1);
      const Pose& pose = held_[p.scan].routedAt;
      if (!nearOwn(mortonEncode(brickOf(g.nearest(pose.apply(p.p)), g.brick)))) continue;
      Held& h = held_[p.scan];
      h.pointVertices.push_back(static_cast<uint32_t>(p.vertex));
      h.points.push_back(p.p);
      h.normals.push_back(p.n);
      h.weights.push_back(p.w);
    }
  }
}

void ControlRouting::packControlPoints(size_t i, const Pose& pose, const BrickLayout& layout,
                                       int me,
                                       std::unordered_map<uint64_t, std::vector<int>>& owners,
                                       std::vector<std::vector<char>>& out) {
  const VoxelGrid& g = layout.grid;
  // A kept scan is referred to; one read again is copied from, then released.
  const std::shared_ptr<const PrismScan> scan = scans_.get(i);
  if (scans_.kept(i)) held_[i].scan = scan;
  const ScanSurface& s = scan->surface;
  const double noise = scan->noise.quadratic();
  // A point that moves less than the reach (a brick edge less one voxel) keeps its nearest
  // voxel within a brick edge of the one it has now: in this brick or a neighbour. Points in
  // grid order mostly share their brick with the point before.
  uint64_t lastCode = ~uint64_t{0};
  const std::vector<int>* ranks = nullptr;
  for (size_t v = 0; v < s.points.size(); v += stride_) {
    if (!(s.confidence[v] > 0)) continue;
    const BrickCoord c = brickOf(g.nearest(pose.apply(s.points[v])), g.brick);
    const uint64_t code = mortonEncode(c);
    if (code != lastCode) {
      auto it = owners.find(code);
      if (it == owners.end()) it = owners.emplace(code, ownersAround(layout, c, me)).first;
      lastCode = code, ranks = &it->second;
    }
    bool packed = false;
    RoutedPoint p;
    for (int r : *ranks) {
      if (r == me && held_[i].scan) {
        held_[i].vertices.push_back(static_cast<uint32_t>(v));
        continue;
      }
      if (!packed) p = RoutedPoint{i, v, s.points[v], s.normals[v], weightOf(*scan, v, noise)};
      packed = true;
      mpi::pack(out[r], &p, 1);
    }
  }
}

double ControlRouting::weightOf(const PrismScan& scan, size_t v, double quadratic) const {
  const double confidence = scan.surface.confidence[v];
  if (!(noiseFloor_ > 0 && quadratic > 0)) return confidence;
  // A residual spreads by the field's error (the floor) plus the point's own depth noise: a far
  // point of a depth camera, its depth quantised in steps growing with depth^2, weighs less.
  // The spread, not the variance: weights of 1 / variance (depth^-4) made the synthetic bunny
  // streams drift at their loop's end (ATE 2.1 -> 40 mm), 1 / spread costs them 0.8 mm and
  // takes the real kitchen from 3.1 to 2.6 cm (docs/tracking.md).
  // The scan frame's point is the vertex as prepared (the surface is built at the identity).
  const double depth = scan.noise.depthOfPoint(scan.surface.points[v]);
  const double sigma = quadratic * depth * depth;
  return confidence * noiseFloor_ / (noiseFloor_ + sigma);
}

void ControlRouting::release(size_t i) {
  held_[i] = Held{};
}

ControlPoints ControlRouting::at(size_t i, const Pose& pose, const BrickStore& store, int every) {
  const VoxelGrid& g = store.grid();
  if (motionBound(i, held_[i].routedAt, pose) > (g.brick - 1) * g.voxel) {
    std::vector<Pose> poses(scans_.size());
    poses[i] = pose;
    route({i}, poses, store);
    ++reroutes_;
  }
  const Held& h = held_[i];
  ControlPoints c;
  c.sensor = sensors_[i].placed(pose);
  auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n, double w) {
    c.points.push_back(pose.apply(p));
    c.normals.push_back(pose.rotate(n));
    c.weights.push_back(w);
  };
  const size_t n = h.vertices.size() + h.points.size();
  c.points.reserve(n);
  c.normals.reserve(n);
  c.weights.reserve(n);
  // A coarser level takes every `every`-th control point by its vertex number: the same points
  // whichever ranks hold them.
  const uint32_t step = static_cast<uint32_t>(stride_) * static_cast<uint32_t>(every);
  const double noise = h.scan ? h.scan->noise.quadratic() : 0;
  for (uint32_t v : h.vertices) {
    if (v % step != 0) continue;
    const ScanSurface& s = h.scan->surface;
    add(s.points[v], s.normals[v], weightOf(*h.scan, v, noise));
  }
  for (size_t k = 0; k < h.points.size(); ++k)
    if (h.pointVertices[k] % step == 0) add(h.points[k], h.normals[k], h.weights[k]);
  return c;
}

}  // namespace rangefuse
