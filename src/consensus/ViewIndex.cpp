#include "rangefuse/consensus/ViewIndex.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/core/KdTree.h"
#include "rangefuse/core/TriangleClosest.h"

namespace rangefuse {

struct ViewIndex::Tier {
  PointCloud centroids;
  std::vector<int32_t> triangle;  // tier-local index -> scan triangle
  double radius = 0;
  std::unique_ptr<KdTree> tree;

  void build() { tree = buildKdTree(centroids, 8); }
};

namespace {

double centroidRadius(const ScanSurface& s, int32_t t, Eigen::Vector3d& c) {
  const Triangle& f = s.triangles[t];
  c = (s.points[f[0]] + s.points[f[1]] + s.points[f[2]]) / 3.0;
  double r = 0;
  for (int k = 0; k < 3; ++k) r = std::max(r, (s.points[f[k]] - c).norm());
  return r;
}

}  // namespace

ViewIndex::ViewIndex(const ScanSurface& scan, const std::vector<int32_t>& triangles)
    : scan_(&scan) {
  std::vector<int32_t> ids = triangles;
  if (ids.empty() && triangles.empty())
    for (int32_t t = 0; t < static_cast<int32_t>(scan.triangles.size()); ++t) ids.push_back(t);
  std::vector<double> radii;
  std::vector<Eigen::Vector3d> centres(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) radii.push_back(centroidRadius(scan, ids[i], centres[i]));
  // Small tier: up to twice the median radius; the rest (long, grazing) in the large tier.
  std::vector<double> sorted = radii;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double split = sorted.empty() ? 0 : 2 * sorted[sorted.size() / 2];
  for (int k = 0; k < 2; ++k) tiers_.push_back(std::make_unique<Tier>());
  for (size_t i = 0; i < ids.size(); ++i) {
    Tier& tier = *tiers_[radii[i] <= split ? 0 : 1];
    tier.centroids.pts.push_back(centres[i]);
    tier.triangle.push_back(ids[i]);
    tier.radius = std::max(tier.radius, radii[i]);
  }
  for (auto& t : tiers_) t->build();
}

ViewIndex::~ViewIndex() = default;
ViewIndex::ViewIndex(ViewIndex&&) noexcept = default;

size_t ViewIndex::size() const {
  return tiers_[0]->triangle.size() + tiers_[1]->triangle.size();
}

bool ViewIndex::closest(const Eigen::Vector3d& x, double maxDistance,
                        SurfaceObservation& out) const {
  const ScanSurface& s = *scan_;
  double best = maxDistance;
  int32_t bestTri = -1;
  Eigen::Vector3d bestBary;
  auto consider = [&](int32_t t) {
    const Triangle& f = s.triangles[t];
    const Eigen::Vector3d b = closestBarycentric(x, s.points[f[0]], s.points[f[1]], s.points[f[2]]);
    const double d =
        (x - (b[0] * s.points[f[0]] + b[1] * s.points[f[1]] + b[2] * s.points[f[2]])).norm();
    if (d < best || (d == best && bestTri >= 0 && t < bestTri)) best = d, bestTri = t, bestBary = b;
  };
  constexpr size_t kFirst = 8;
  uint32_t ids[kFirst];
  double sq[kFirst];
  std::vector<std::pair<uint32_t, double>> hits;
  for (const auto& tier : tiers_) {
    if (tier->triangle.empty()) continue;
    const size_t k = tier->tree->knnSearch(x.data(), kFirst, ids, sq);
    if (std::sqrt(sq[0]) - tier->radius > best) continue;  // nothing in reach
    for (size_t i = 0; i < k; ++i) consider(tier->triangle[ids[i]]);
    // Every triangle not yet seen has its centroid beyond the k-th: it is at least that far
    // minus the tier radius. When that exceeds the best, the answer is already exact.
    if (k < kFirst || std::sqrt(sq[k - 1]) - tier->radius > best) continue;
    const double r = best + tier->radius;
    hits.clear();
    tier->tree->radiusSearch(x.data(), r * r, hits, nanoflann::SearchParams(32, 0, false));
    for (const auto& h : hits) consider(tier->triangle[h.first]);
  }
  if (bestTri < 0) return false;
  const Triangle& f = s.triangles[bestTri];
  out.point =
      bestBary[0] * s.points[f[0]] + bestBary[1] * s.points[f[1]] + bestBary[2] * s.points[f[2]];
  out.normal = (bestBary[0] * s.normals[f[0]] + bestBary[1] * s.normals[f[1]] +
                bestBary[2] * s.normals[f[2]])
                   .normalized();
  out.confidence = bestBary[0] * s.confidence[f[0]] + bestBary[1] * s.confidence[f[1]] +
                   bestBary[2] * s.confidence[f[2]];
  out.distance = best;
  return true;
}

}  // namespace rangefuse
