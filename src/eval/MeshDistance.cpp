#include "rangefuse/eval/MeshDistance.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "rangefuse/core/KdTree.h"

namespace rangefuse {

struct MeshDistance::Index {
  const TriangleMesh mesh;  // a copy: callers may pass temporaries
  PointCloud centroids;
  double radius = 0;  // largest centroid-to-vertex distance
  std::unique_ptr<KdTree> tree;

  explicit Index(const TriangleMesh& m) : mesh(m) {
    for (const Triangle& t : mesh.faces) {
      Eigen::Vector3d c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
      for (int k = 0; k < 3; ++k) radius = std::max(radius, (m.vertices[t[k]] - c).norm());
      centroids.pts.push_back(c);
    }
    tree = buildKdTree(centroids);
  }

  ClosestPoint onTriangle(size_t i, const Eigen::Vector3d& p) const {
    const Triangle& t = mesh.faces[i];
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Eigen::Vector3d w = closestBarycentric(p, a, b, c);
    return {i, w, (p - (w[0] * a + w[1] * b + w[2] * c)).norm()};
  }
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : index_(std::make_unique<Index>(mesh)) {}
MeshDistance::~MeshDistance() = default;

ClosestPoint MeshDistance::closest(const Eigen::Vector3d& p) const {
  if (index_->centroids.pts.empty()) return {};
  uint32_t nearest;
  double nearestSq;
  index_->tree->knnSearch(p.data(), 1, &nearest, &nearestSq);
  ClosestPoint best = index_->onTriangle(nearest, p);
  // Any triangle closer than `best` has its centroid within best + radius of p.
  const double r = best.distance + index_->radius;
  std::vector<std::pair<uint32_t, double>> hits;
  index_->tree->radiusSearch(p.data(), r * r, hits, nanoflann::SearchParams());
  // Ties go to the lowest face number, so the answer does not depend on the search's order.
  for (const auto& h : hits) {
    const ClosestPoint c = index_->onTriangle(h.first, p);
    if (c.distance < best.distance || (c.distance == best.distance && c.face < best.face)) best = c;
  }
  return best;
}

std::vector<Eigen::Vector3d> sampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  std::vector<double> cumulative;
  double total = 0;
  for (const Triangle& t : mesh.faces) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative.push_back(total);
  }
  std::vector<Eigen::Vector3d> out;
  if (total <= 0) return out;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0, 1);
  for (size_t i = 0; i < count; ++i) {
    size_t f = std::lower_bound(cumulative.begin(), cumulative.end(), uni(rng) * total) -
               cumulative.begin();
    f = std::min(f, mesh.faces.size() - 1);
    double r1 = std::sqrt(uni(rng)), r2 = uni(rng);
    const Triangle& t = mesh.faces[f];
    out.push_back((1 - r1) * mesh.vertices[t[0]] + r1 * (1 - r2) * mesh.vertices[t[1]] +
                  r1 * r2 * mesh.vertices[t[2]]);
  }
  return out;
}

DistanceStats summarize(std::vector<double> d) {
  DistanceStats s;
  if (d.empty()) return s;
  std::sort(d.begin(), d.end());
  double sum = 0;
  for (double x : d) sum += x;
  auto q = [&](double f) { return d[std::min(d.size() - 1, static_cast<size_t>(f * d.size()))]; };
  s.mean = sum / d.size();
  s.median = q(0.5);
  s.p90 = q(0.9);
  s.p99 = q(0.99);
  s.max = d.back();
  return s;
}

std::vector<double> sampledDistances(const TriangleMesh& from, const TriangleMesh& to, size_t count,
                                     uint64_t seed) {
  MeshDistance dist(to);
  std::vector<double> out;
  for (const auto& p : sampleSurface(from, count, seed)) out.push_back(dist.distance(p));
  return out;
}

}  // namespace rangefuse
