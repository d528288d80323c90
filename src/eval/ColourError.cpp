#include "rangefuse/eval/ColourError.h"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "rangefuse/core/KdTree.h"

namespace rangefuse {
namespace {

/// The reference's colour at the point closest to each mesh vertex; NaN beyond `maxDistance`.
std::vector<Eigen::Vector3f> referenceColours(const TriangleMesh& mesh,
                                              const TriangleMesh& reference, double maxDistance) {
  const MeshDistance dist(reference);
  std::vector<Eigen::Vector3f> out;
  out.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) {
    const ClosestPoint c = dist.closest(v);
    if (!(c.distance <= maxDistance)) {
      out.push_back(Eigen::Vector3f::Constant(NAN));
      continue;
    }
    const Triangle& t = reference.faces[c.face];
    Eigen::Vector3f colour = Eigen::Vector3f::Zero();
    for (int k = 0; k < 3; ++k) colour += float(c.weights[k]) * reference.colours[t[k]];
    out.push_back(colour);
  }
  return out;
}

/// Least-squares slope of the mesh's colour steps on the reference's, over the mesh edges whose
/// reference step is at least kTextureEdgeStep. Projecting on the reference step keeps noise in
/// the mesh colours from passing for contrast.
void edgeContrast(const TriangleMesh& mesh, const std::vector<Eigen::Vector3f>& ref,
                  ColourComparison& c) {
  std::set<std::pair<int64_t, int64_t>> edges;
  for (const Triangle& t : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = t[k], b = t[(k + 1) % 3];
      if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  double along = 0, squared = 0;
  for (const auto& [a, b] : edges) {
    const Eigen::Vector3d dr = (ref[a] - ref[b]).cast<double>();
    if (!dr.allFinite() || dr.norm() < kTextureEdgeStep) continue;
    along += (mesh.colours[a] - mesh.colours[b]).cast<double>().dot(dr);
    squared += dr.squaredNorm();
    ++c.edges;
  }
  c.edgeContrast = squared > 0 ? along / squared : 0;
}

/// Where the reference's texture edges run: the middle of each of its edges whose two ends
/// differ by kTextureEdgeStep or more (the synthetic truth splits such edges finely).
PointCloud textureEdges(const TriangleMesh& reference) {
  std::set<std::pair<int64_t, int64_t>> seen;
  PointCloud out;
  for (const Triangle& t : reference.faces)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
      const Eigen::Vector3f step = reference.colours[a] - reference.colours[b];
      if (step.norm() < kTextureEdgeStep || !seen.insert({a, b}).second) continue;
      out.pts.push_back(0.5 * (reference.vertices[a] + reference.vertices[b]));
    }
  return out;
}

/// For each mesh vertex, whether a texture edge of the reference lies within `nearEdge`.
std::vector<bool> nearTextureEdges(const TriangleMesh& mesh, const TriangleMesh& reference,
                                   double nearEdge) {
  const PointCloud edges = textureEdges(reference);
  std::vector<bool> near(mesh.vertices.size(), false);
  if (edges.pts.empty()) return near;
  const auto tree = buildKdTree(edges);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    uint32_t index;
    double squared;
    tree->knnSearch(mesh.vertices[i].data(), 1, &index, &squared);
    near[i] = squared <= nearEdge * nearEdge;
  }
  return near;
}

}  // namespace

ColourComparison compareColours(const TriangleMesh& mesh, const TriangleMesh& reference,
                                double maxDistance, double nearEdge) {
  ColourComparison c;
  const std::vector<Eigen::Vector3f> ref = referenceColours(mesh, reference, maxDistance);
  const std::vector<bool> near = nearTextureEdges(mesh, reference, nearEdge);
  std::vector<double> errors, nearErrors, farErrors;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!ref[i].allFinite()) continue;
    const double e = 255.0 * (mesh.colours[i] - ref[i]).cwiseAbs().cast<double>().mean();
    errors.push_back(e);
    (near[i] ? nearErrors : farErrors).push_back(e);
  }
  c.vertices = errors.size();
  c.nearEdgeVertices = nearErrors.size(), c.farEdgeVertices = farErrors.size();
  c.error = summarize(std::move(errors));
  c.nearEdgeError = summarize(std::move(nearErrors));
  c.farEdgeError = summarize(std::move(farErrors));
  edgeContrast(mesh, ref, c);
  return c;
}

}  // namespace rangefuse
