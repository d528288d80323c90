#include "rangefuse/scan/Shapes.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

TriangleMesh makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool bottom,
                     double cell) {
  TriangleMesh m;
  const Eigen::Vector3d size = hi - lo;
  // Each face as a corner and two edges whose cross product points outward.
  struct Face {
    Eigen::Vector3d corner, u, v;
  };
  const Eigen::Vector3d X(size.x(), 0, 0), Y(0, size.y(), 0), Z(0, 0, size.z());
  const std::vector<Face> faces = {{lo, Z, Y},     {lo + X, Y, Z}, {lo, X, Z},
                                   {lo + Y, Z, X}, {lo + Z, X, Y}, {lo, Y, X}};
  for (size_t f = 0; f < (bottom ? 6u : 5u); ++f) {
    const Face& face = faces[f];
    const int nu = std::max(1, static_cast<int>(std::ceil(face.u.norm() / cell)));
    const int nv = std::max(1, static_cast<int>(std::ceil(face.v.norm() / cell)));
    const int32_t base = static_cast<int32_t>(m.vertices.size());
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i)
        m.vertices.push_back(face.corner + face.u * i / nu + face.v * j / nv);
    auto at = [&](int i, int j) { return base + j * (nu + 1) + i; };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        m.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  return m;
}

TriangleMesh makeRoom() {
  // Faces in cells of at most 0.25 m, so that closest-point searches stay local.
  TriangleMesh m = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(8, 6, 3), true, 0.25);
  appendMesh(m,
             makeBox(Eigen::Vector3d(2.0, 1.4, 0), Eigen::Vector3d(3.6, 2.3, 0.75), false, 0.25));
  appendMesh(m, makeBox(Eigen::Vector3d(7.3, 0.4, 0), Eigen::Vector3d(7.9, 1.9, 2.0), false, 0.25));
  appendMesh(m, makeBox(Eigen::Vector3d(5.0, 4.0, 0), Eigen::Vector3d(5.6, 4.6, 0.6), false, 0.25));
  appendMesh(m, makeSphere(Eigen::Vector3d(1.5, 4.6, 1.2), 0.4, 32, 64));
  return m;
}

TriangleMesh makeDesk() {
  // Cells of 5 cm: fine enough that the boxes' faces stay flat under the scanner's rays.
  const double cell = 0.05, top = 0.75;
  TriangleMesh m =
      makeBox(Eigen::Vector3d(-0.6, -0.4, top - 0.03), Eigen::Vector3d(0.6, 0.4, top), true, cell);
  for (const double x : {-0.55, 0.5})
    for (const double y : {-0.35, 0.3})
      appendMesh(m, makeBox(Eigen::Vector3d(x, y, 0),
                            Eigen::Vector3d(x + 0.05, y + 0.05, top - 0.03), false, cell));
  auto onTop = [&](double x0, double y0, double x1, double y1, double z0, double z1) {
    appendMesh(m, makeBox(Eigen::Vector3d(x0, y0, top + z0), Eigen::Vector3d(x1, y1, top + z1),
                          z0 > 0, cell));
  };
  onTop(-0.05, 0.26, 0.03, 0.34, 0, 0.1);     // monitor stand
  onTop(-0.3, 0.28, 0.25, 0.32, 0.1, 0.43);   // monitor
  onTop(-0.28, -0.2, 0.17, -0.05, 0, 0.025);  // keyboard
  onTop(0.25, -0.3, 0.5, -0.12, 0, 0.05);     // book
  appendMesh(m, makeSphere(Eigen::Vector3d(-0.42, -0.15, top + 0.07), 0.07, 24, 48));  // ball
  appendMesh(m, makeTorus(Eigen::Vector3d(0.38, 0.15, top + 0.025), 0.08, 0.025, 64, 24));
  return m;
}

TriangleMesh makeShape(const std::string& name) {
  if (name == "room") return makeRoom();
  if (name == "desk") return makeDesk();
  if (name == "sphere") return makeSphere(Eigen::Vector3d::Zero(), 50, 96, 192);
  if (name == "torus") return makeTorus(Eigen::Vector3d::Zero(), 35, 15, 192, 80);
  if (name == "composite") return makeComposite();
  throw InputError("--shape must be sphere, torus, composite, room or desk, not '" + name + "'");
}

}  // namespace rangefuse
