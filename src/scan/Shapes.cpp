#include "rangefuse/scan/Shapes.h"

#include <cmath>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

/// Faces of a (rows+1) x cols vertex grid wrapped in the column direction; `wrapRows` also
/// closes the row direction (torus).
void gridFaces(TriangleMesh& m, int32_t base, int rows, int cols, bool wrapRows) {
  const int rowCount = wrapRows ? rows : rows - 1;
  auto at = [&](int r, int c) { return base + ((r % rows) * cols + (c % cols)); };
  for (int r = 0; r < rowCount; ++r)
    for (int c = 0; c < cols; ++c) {
      m.faces.push_back({at(r, c), at(r + 1, c), at(r + 1, c + 1)});
      m.faces.push_back({at(r, c), at(r + 1, c + 1), at(r, c + 1)});
    }
}

}  // namespace

void appendMesh(TriangleMesh& a, const TriangleMesh& b) {
  const int32_t base = static_cast<int32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Triangle& f : b.faces) a.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

TriangleMesh makeSphere(const Eigen::Vector3d& centre, double radius, int rings, int segments) {
  TriangleMesh m;
  m.vertices.push_back(centre + Eigen::Vector3d(0, 0, radius));
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      m.vertices.push_back(centre + radius * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                                             std::sin(theta) * std::sin(phi),
                                                             std::cos(theta)));
    }
  }
  const int32_t south = static_cast<int32_t>(m.vertices.size());
  m.vertices.push_back(centre - Eigen::Vector3d(0, 0, radius));
  for (int s = 0; s < segments; ++s) {
    const int32_t a = 1 + s, b = 1 + (s + 1) % segments;
    m.faces.push_back({0, a, b});
    const int32_t c = 1 + (rings - 2) * segments + s,
                  d = 1 + (rings - 2) * segments + (s + 1) % segments;
    m.faces.push_back({south, d, c});
  }
  gridFaces(m, 1, rings - 1, segments, false);
  return m;
}

TriangleMesh makeTorus(const Eigen::Vector3d& centre, double R, double r, int ringSegments,
                       int tubeSegments) {
  TriangleMesh m;
  for (int i = 0; i < ringSegments; ++i) {
    const double u = 2 * M_PI * i / ringSegments;
    for (int j = 0; j < tubeSegments; ++j) {
      const double v = 2 * M_PI * j / tubeSegments;
      m.vertices.push_back(centre + Eigen::Vector3d((R + r * std::cos(v)) * std::cos(u),
                                                    (R + r * std::cos(v)) * std::sin(u),
                                                    r * std::sin(v)));
    }
  }
  gridFaces(m, 0, ringSegments, tubeSegments, true);
  return m;
}

TriangleMesh makeComposite() {
  TriangleMesh m = makeTorus(Eigen::Vector3d::Zero(), 30, 12, 160, 64);
  appendMesh(m, makeSphere(Eigen::Vector3d(0, 0, 30), 14, 64, 128));
  appendMesh(m, makeSphere(Eigen::Vector3d(50, 0, -4), 8, 48, 96));
  return m;
}

TriangleMesh makeShape(const std::string& name) {
  if (name == "sphere") return makeSphere(Eigen::Vector3d::Zero(), 50, 96, 192);
  if (name == "torus") return makeTorus(Eigen::Vector3d::Zero(), 35, 15, 192, 80);
  if (name == "composite") return makeComposite();
  throw InputError("--shape must be sphere, torus or composite, not '" + name + "'");
}

}  // namespace rangefuse
