#include <algorithm>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

/// Vertex-to-neighbour adjacency (vertices sharing a triangle), compressed rows.
void buildNeighbours(const TriangleMesh& m, std::vector<int32_t>& start,
                     std::vector<int32_t>& nbr) {
  std::vector<std::vector<int32_t>> lists(m.vertices.size());
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) {
      lists[t[k]].push_back(t[(k + 1) % 3]);
      lists[t[k]].push_back(t[(k + 2) % 3]);
    }
  start.assign(1, 0);
  for (auto& l : lists) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    nbr.insert(nbr.end(), l.begin(), l.end());
    start.push_back(static_cast<int32_t>(nbr.size()));
  }
}

void normalizeAll(std::vector<Eigen::Vector3d>& v) {
  for (auto& n : v)
    if (n.norm() > 0) n.normalize();
}

}  // namespace

std::vector<Eigen::Vector3d> filteredVertexNormals(const TriangleMesh& mesh, int passes) {
  std::vector<Eigen::Vector3d> n(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& t : mesh.faces) {
    const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    Eigen::Vector3d fn = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 3; ++k) n[t[k]] += fn;
  }
  normalizeAll(n);
  std::vector<int32_t> start, nbr;
  buildNeighbours(mesh, start, nbr);
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<Eigen::Vector3d> next(n.size());
    for (size_t v = 0; v < n.size(); ++v) {
      next[v] = n[v];
      for (int32_t k = start[v]; k < start[v + 1]; ++k) next[v] += n[nbr[k]];
    }
    normalizeAll(next);
    n.swap(next);
  }
  return n;
}

}  // namespace rangefuse
