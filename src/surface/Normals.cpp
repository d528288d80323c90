#include <algorithm>

#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {
namespace {

/// Vertex-to-neighbour adjacency (vertices sharing a triangle, ascending), compressed rows.
/// Filled in place from each vertex's triangle corners: no list a vertex.
void buildNeighbours(const TriangleMesh& m, std::vector<size_t>& start, std::vector<int32_t>& nbr) {
  const size_t n = m.vertices.size();
  std::vector<size_t> end(n + 1, 0);
  for (const auto& t : m.faces)
    for (int32_t v : t) end[v + 1] += 2;
  for (size_t v = 0; v < n; ++v) end[v + 1] += end[v];
  nbr.resize(end[n]);
  std::vector<size_t> at(end.begin(), end.end() - 1);
  for (const auto& t : m.faces)
    for (int k = 0; k < 3; ++k) {
      nbr[at[t[k]]++] = t[(k + 1) % 3];
      nbr[at[t[k]]++] = t[(k + 2) % 3];
    }
  // Each row sorted and made unique, moved down over what earlier rows dropped.
  start.assign(n + 1, 0);
  for (size_t v = 0; v < n; ++v) {
    const auto first = nbr.begin() + end[v], last = nbr.begin() + end[v + 1];
    std::sort(first, last);
    const auto unique = std::unique(first, last);
    start[v + 1] = std::copy(first, unique, nbr.begin() + start[v]) - nbr.begin();
  }
  nbr.resize(start[n]);
}

/// Eigen's normalize() leaves a zero vector as it is: one root a vector.
void normalizeAll(std::vector<Eigen::Vector3d>& v) {
  for (auto& n : v) n.normalize();
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
  std::vector<size_t> start;
  std::vector<int32_t> nbr;
  buildNeighbours(mesh, start, nbr);
  std::vector<Eigen::Vector3d> next(n.size());
  for (int pass = 0; pass < passes; ++pass) {
    for (size_t v = 0; v < n.size(); ++v) {
      Eigen::Vector3d sum = n[v];
      for (size_t k = start[v]; k < start[v + 1]; ++k) sum += n[nbr[k]];
      sum.normalize();
      next[v] = sum;
    }
    n.swap(next);
  }
  return n;
}

}  // namespace rangefuse
