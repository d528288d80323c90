#include "rangefuse/eval/SeenSurface.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace rangefuse {
namespace {

// 21 bits an axis around the origin: ±10⁶ cells, room for a building at millimetre cells.
constexpr int64_t kBias = int64_t(1) << 20;
constexpr int64_t kMask = (int64_t(1) << 21) - 1;

}  // namespace

uint64_t SeenCells::key(const Eigen::Vector3d& p, int dx, int dy, int dz) const {
  auto axis = [&](double v, int d) {
    return static_cast<uint64_t>((static_cast<int64_t>(std::floor(v / cell_)) + d + kBias) & kMask);
  };
  return axis(p.x(), dx) << 42 | axis(p.y(), dy) << 21 | axis(p.z(), dz);
}

void SeenCells::merge(std::vector<uint64_t>& fresh) {
  std::sort(fresh.begin(), fresh.end());
  fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
  std::vector<uint64_t> merged;
  merged.reserve(keys_.size() + fresh.size());
  std::set_union(keys_.begin(), keys_.end(), fresh.begin(), fresh.end(),
                 std::back_inserter(merged));
  keys_.swap(merged);
  fresh.clear();
}

void SeenCells::addSurface(const TriangleMesh& mesh, const Pose& pose) {
  constexpr size_t kBatch = size_t(1) << 24;  // keys sorted a batch at a time: bounded memory
  std::vector<uint64_t> fresh;
  for (const Triangle& t : mesh.faces) {
    const Eigen::Vector3d a = pose.apply(mesh.vertices[t[0]]),
                          ab = pose.R * (mesh.vertices[t[1]] - mesh.vertices[t[0]]),
                          ac = pose.R * (mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const double edge = std::max({ab.norm(), ac.norm(), (ac - ab).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(edge / cell_)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) fresh.push_back(key(a + (ab * i + ac * j) / n, 0, 0, 0));
    if (fresh.size() >= kBatch) merge(fresh);
  }
  merge(fresh);
}

bool SeenCells::near(const Eigen::Vector3d& p) const {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (std::binary_search(keys_.begin(), keys_.end(), key(p, dx, dy, dz))) return true;
  return false;
}

}  // namespace rangefuse
