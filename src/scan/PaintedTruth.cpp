#include "rangefuse/scan/PaintedTruth.h"

#include <algorithm>
#include <map>
#include <utility>

#include "rangefuse/scan/SyntheticScanner.h"

namespace rangefuse {
namespace {

/// Adds midpoints shared between the triangles of one pass, so a split edge gets one vertex.
class Midpoints {
 public:
  Midpoints(TriangleMesh& mesh, double size) : mesh_(mesh), size_(size) {}

  int32_t of(int32_t a, int32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, added] = made_.try_emplace(key, static_cast<int32_t>(mesh_.vertices.size()));
    if (added) {
      const Eigen::Vector3d p = 0.5 * (mesh_.vertices[a] + mesh_.vertices[b]);
      mesh_.vertices.push_back(p);
      mesh_.colours.push_back(checkColour(p, size_));
    }
    return it->second;
  }

 private:
  TriangleMesh& mesh_;
  double size_;
  std::map<std::pair<int32_t, int32_t>, int32_t> made_;
};

/// Whether a triangle is still too coarse: longer than `coarsest` (a check could lie inside it
/// with its corners all one colour), or crossing a check edge and longer than `finest`.
bool needsSplit(const TriangleMesh& m, const Triangle& t, double coarsest, double finest) {
  double longest = 0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (m.vertices[t[k]] - m.vertices[t[(k + 1) % 3]]).norm());
  if (longest > coarsest) return true;
  const auto& c = m.colours;
  return !(c[t[0]] == c[t[1]] && c[t[1]] == c[t[2]]) && longest > finest;
}

/// One pass: every triangle still too coarse (needsSplit) becomes four. Returns whether any was
/// split.
bool splitPass(TriangleMesh& m, double size, double finest) {
  Midpoints mid(m, size);
  std::vector<Triangle> faces;
  faces.reserve(m.faces.size());
  bool split = false;
  for (const Triangle& t : m.faces) {
    if (!needsSplit(m, t, size / 4, finest)) {
      faces.push_back(t);
      continue;
    }
    split = true;
    const int32_t ab = mid.of(t[0], t[1]), bc = mid.of(t[1], t[2]), ca = mid.of(t[2], t[0]);
    faces.push_back({t[0], ab, ca});
    faces.push_back({ab, t[1], bc});
    faces.push_back({ca, bc, t[2]});
    faces.push_back({ab, bc, ca});
  }
  m.faces = std::move(faces);
  return split;
}

}  // namespace

TriangleMesh paintedTruth(const TriangleMesh& mesh, double size, double finest) {
  TriangleMesh m = mesh;
  m.normals.clear();
  m.colours.clear();
  for (const Eigen::Vector3d& v : m.vertices) m.colours.push_back(checkColour(v, size));
  // Each pass halves the split triangles' edges; 24 passes bound it whatever the input.
  for (int pass = 0; pass < 24 && splitPass(m, size, finest); ++pass) {
  }
  return m;
}

}  // namespace rangefuse
