#include "rangefuse/eval/Comparison.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/register/RigidFit.h"

namespace rangefuse {
namespace {

double fractionWithin(const std::vector<double>& d, double limit) {
  if (d.empty()) return 0;
  return double(std::count_if(d.begin(), d.end(), [&](double x) { return x <= limit; })) / d.size();
}

/// Distances from the reference's samples (those on the seen surface, with `seen`) to the mesh.
std::vector<double> completenessDistances(const TriangleMesh& reference, const TriangleMesh& mesh,
                                          const CompareSettings& s, const SeenCells* seen,
                                          double& seenFraction) {
  std::vector<Eigen::Vector3d> samples = sampleSurface(reference, s.samples, s.seed + 1);
  const size_t all = samples.size();
  if (seen)
    samples.erase(std::remove_if(samples.begin(), samples.end(),
                                 [&](const Eigen::Vector3d& p) { return !seen->near(p); }),
                  samples.end());
  seenFraction = all > 0 ? double(samples.size()) / double(all) : 0;
  const MeshDistance dist(mesh);
  std::vector<double> out;
  out.reserve(samples.size());
  for (const auto& p : samples) out.push_back(dist.distance(p));
  return out;
}

}  // namespace

MeshComparison compareMeshes(const TriangleMesh& mesh, const TriangleMesh& reference,
                             const CompareSettings& s, const SeenCells* seen) {
  MeshComparison c;
  const std::vector<double> acc = sampledDistances(mesh, reference, s.samples, s.seed);
  const std::vector<double> comp = completenessDistances(reference, mesh, s, seen, c.seenFraction);
  c.accuracy = summarize(acc);
  c.completeness = summarize(comp);
  c.chamfer = 0.5 * (c.accuracy.mean + c.completeness.mean);
  c.precision = fractionWithin(acc, s.tau);
  c.recall = fractionWithin(comp, s.tau);
  c.fscore = c.precision + c.recall > 0 ? 2 * c.precision * c.recall / (c.precision + c.recall) : 0;
  // Samples are area-weighted, so a fraction of samples is a fraction of area.
  c.spuriousAreaFraction = acc.empty() ? 0 : 1 - fractionWithin(acc, s.spuriousDistance);
  return c;
}

PoseError comparePose(const Pose& estimate, const Pose& reference,
                      const std::vector<Eigen::Vector3d>& points) {
  PoseError e;
  const Eigen::AngleAxisd delta(Eigen::Matrix3d(estimate.R * reference.R.transpose()));
  e.rotationDeg = std::abs(delta.angle()) * 180 / M_PI;
  // Translation where the scan is, not at its frame's origin (the sensor, often far away):
  // there a rotation error would count again, times the lever arm.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : points) centre += p / static_cast<double>(points.size());
  e.translation = (estimate.apply(centre) - reference.apply(centre)).norm();
  double sum = 0;
  for (const auto& p : points) {
    const double d = (estimate.apply(p) - reference.apply(p)).norm();
    sum += d;
    e.displacementMax = std::max(e.displacementMax, d);
  }
  e.points = points.size();
  e.displacementMean = points.empty() ? 0 : sum / points.size();
  return e;
}

Pose commonMotion(const std::vector<Pose>& estimates, const std::vector<Pose>& references,
                  const std::vector<std::vector<Eigen::Vector3d>>& points, size_t stride) {
  RigidSums sums;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // moments about the data, for precision
  size_t n = 0;
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t k = 0; k < points[i].size(); k += stride, ++n)
      centre += references[i].apply(points[i][k]);
  if (n == 0) return Pose{};
  centre /= static_cast<double>(n);
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t k = 0; k < points[i].size(); k += stride)
      sums.add(estimates[i].apply(points[i][k]) - centre,
               references[i].apply(points[i][k]) - centre, 1);
  Pose g = fitRigid(sums);
  g.t += centre - g.R * centre;
  return g;
}

}  // namespace rangefuse
