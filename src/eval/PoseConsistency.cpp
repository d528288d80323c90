#include "rangefuse/eval/PoseConsistency.h"

#include <cmath>
#include <memory>

#include "rangefuse/core/KdTree.h"

namespace rangefuse {
namespace {

/// Adds the squared residuals of scan a's vertices against scan b to `sum` and `pairs`.
void residualsAgainst(const ScanSurface& a, const ScanSurface& b, const KdTree& tree,
                      const ConsistencySettings& s, double& sum, size_t& pairs) {
  for (size_t v = 0; v < a.points.size(); v += s.stride) {
    const Eigen::Vector3d& p = a.points[v];
    uint32_t nearest;
    double squared;
    tree.knnSearch(p.data(), 1, &nearest, &squared);
    const Eigen::Vector3d& n = b.normals[nearest];
    if (n.dot(a.normals[v]) < s.minCosine) continue;
    const Eigen::Vector3d d = p - b.points[nearest];
    const double along = n.dot(d);
    if (std::abs(along) > s.maxDistance || (d - along * n).norm() > s.maxTangential) continue;
    sum += along * along;
    ++pairs;
  }
}

}  // namespace

std::vector<ScanConsistency> poseConsistency(const std::vector<ScanSurface>& world,
                                             const ConsistencySettings& s) {
  return poseConsistency(world, world, s);
}

std::vector<ScanConsistency> poseConsistency(const std::vector<ScanSurface>& probes,
                                             const std::vector<ScanSurface>& world,
                                             const ConsistencySettings& s) {
  std::vector<PointCloud> clouds(world.size());
  std::vector<std::unique_ptr<KdTree>> trees;
  for (size_t j = 0; j < world.size(); ++j) {
    clouds[j].pts = world[j].points;
    trees.push_back(buildKdTree(clouds[j]));
  }
  auto rms = [](double sum, size_t pairs) {
    return pairs > 0 ? std::sqrt(sum / static_cast<double>(pairs)) : 0.0;
  };
  std::vector<ScanConsistency> out(world.size());
  for (size_t i = 0; i < world.size(); ++i) {
    ScanConsistency& c = out[i];
    c.sampled = (probes[i].points.size() + s.stride - 1) / s.stride;
    c.pairsWith.assign(world.size(), 0);
    c.rmsWith.assign(world.size(), 0.0);
    double sum = 0;
    for (size_t j = 0; j < world.size(); ++j) {
      if (j == i || world[j].points.empty()) continue;
      double sumWith = 0;
      residualsAgainst(probes[i], world[j], *trees[j], s, sumWith, c.pairsWith[j]);
      c.rmsWith[j] = rms(sumWith, c.pairsWith[j]);
      sum += sumWith;
      c.pairs += c.pairsWith[j];
    }
    c.rms = rms(sum, c.pairs);
  }
  return out;
}

}  // namespace rangefuse
