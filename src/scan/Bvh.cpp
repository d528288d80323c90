#include "rangefuse/scan/Bvh.h"

#include <algorithm>
#include <cmath>

namespace rangefuse {
namespace {

constexpr int kLeafSize = 4;

bool hitsBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& o, const Eigen::Vector3d& inv,
             double tMin, double tMax) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (box.min()[a] - o[a]) * inv[a], t1 = (box.max()[a] - o[a]) * inv[a];
    if (t0 > t1) std::swap(t0, t1);
    tMin = std::max(tMin, t0);
    tMax = std::min(tMax, t1);
    if (tMin > tMax) return false;
  }
  return true;
}

}  // namespace

bool intersectTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b, const Eigen::Vector3d& c, double tMin, double tMax,
                       double& t) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0) return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < 0 || u + v > 1) return false;
  t = e2.dot(q) * inv;
  return t > tMin && t < tMax;
}

Bvh::Bvh(const TriangleMesh& mesh) : mesh_(mesh) {
  for (int32_t i = 0; i < static_cast<int32_t>(mesh.faces.size()); ++i) {
    const Triangle& f = mesh.faces[i];
    centroids_.push_back((mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3.0);
    order_.push_back(i);
  }
  if (!order_.empty()) build(0, static_cast<int32_t>(order_.size()));
}

int32_t Bvh::build(int32_t begin, int32_t end) {
  const int32_t id = static_cast<int32_t>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centres;
  for (int32_t i = begin; i < end; ++i) {
    const Triangle& f = mesh_.faces[order_[i]];
    for (int k = 0; k < 3; ++k) box.extend(mesh_.vertices[f[k]]);
    centres.extend(centroids_[order_[i]]);
  }
  nodes_[id].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  Eigen::Vector3d::Index axis;
  centres.sizes().maxCoeff(&axis);
  const int32_t mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int32_t a, int32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
  const int32_t left = build(begin, mid), right = build(mid, end);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

bool Bvh::firstHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tMin, double tMax,
                   RayHit& hit) const {
  if (nodes_.empty()) return false;
  const Eigen::Vector3d inv = d.cwiseInverse();
  bool found = false;
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!hitsBox(n.box, o, inv, tMin, tMax)) continue;
    if (n.left >= 0) {
      stack[top++] = n.left;
      stack[top++] = n.right;
      continue;
    }
    for (int32_t i = n.begin; i < n.end; ++i) {
      const Triangle& f = mesh_.faces[order_[i]];
      double t;
      if (intersectTriangle(o, d, mesh_.vertices[f[0]], mesh_.vertices[f[1]], mesh_.vertices[f[2]],
                            tMin, tMax, t)) {
        tMax = t;  // only nearer hits from now on
        hit = RayHit{t, order_[i]};
        found = true;
      }
    }
  }
  return found;
}

bool Bvh::firstHitBruteForce(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tMin,
                             double tMax, RayHit& hit) const {
  bool found = false;
  for (int32_t i = 0; i < static_cast<int32_t>(mesh_.faces.size()); ++i) {
    const Triangle& f = mesh_.faces[i];
    double t;
    if (intersectTriangle(o, d, mesh_.vertices[f[0]], mesh_.vertices[f[1]], mesh_.vertices[f[2]],
                          tMin, tMax, t)) {
      tMax = t;
      hit = RayHit{t, i};
      found = true;
    }
  }
  return found;
}

}  // namespace rangefuse
