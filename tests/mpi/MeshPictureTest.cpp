#include <gtest/gtest.h>

#include <cmath>

#include "rangefuse/render/MeshPicture.h"

using namespace rangefuse;

namespace {

const Eigen::Vector3d kSphereCentre(0.3, -0.2, 0.1);
const double kSphereRadius = 2.0;

/// A latitude-longitude sphere, faces wound outward; without the faces whose centre lies above
/// `capZ` (relative to the centre), so that a hole opens toward +z.
MeshPart spherePart(double capZ = INFINITY) {
  MeshPart part;
  TriangleMesh& m = part.mesh;
  const int rings = 40, sectors = 80;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      m.vertices.push_back(kSphereCentre +
                           kSphereRadius * Eigen::Vector3d(std::sin(th) * std::cos(ph),
                                                           std::sin(th) * std::sin(ph),
                                                           std::cos(th)));
    }
  auto id = [&](int i, int j) { return i * sectors + (j % sectors); };
  auto add = [&](Triangle f) {
    const Eigen::Vector3d &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    if ((b - a).cross(c - a).norm() == 0) return;
    if ((((a + b + c) / 3 - kSphereCentre).z()) > capZ) return;
    if ((b - a).cross(c - a).dot(a + b + c - 3 * kSphereCentre) < 0) std::swap(f[1], f[2]);
    m.faces.push_back(f);
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      add({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      add({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return part;
}

/// Distance along the ray o + t d to triangle f, or infinity (Moller-Trumbore).
double hit(const TriangleMesh& m, const Triangle& f, const Eigen::Vector3d& o,
           const Eigen::Vector3d& d) {
  const Eigen::Vector3d &a = m.vertices[f[0]], e1 = m.vertices[f[1]] - a, e2 = m.vertices[f[2]] - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return INFINITY;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (u < 0 || v < 0 || u + v > 1) return INFINITY;
  return e2.dot(q) / det;
}

bool isBackground(const Image& img, size_t pixel) {
  return std::equal(kBackground.begin(), kBackground.end(), img.rgb.begin() + 3 * pixel);
}

}  // namespace

TEST(MeshPicture, CoversThePixelsABruteForceRayCastHits) {
  const MeshPart part = spherePart();
  ViewSettings view;
  view.width = 120, view.height = 90;
  const Image img = pictureOfMesh(part, view, 0, MPI_COMM_SELF);
  Eigen::AlignedBox3d extent;
  const Eigen::Matrix3d axes = viewAxes(view);
  for (const Eigen::Vector3d& v : part.mesh.vertices) extent.extend(axes * v);
  const ViewFrame frame(view, extent);
  size_t covered = 0, differ = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const Eigen::Vector3d o = frame.rayOrigin(x + 0.5, y + 0.5, 1);
      double nearest = INFINITY;
      for (const Triangle& f : part.mesh.faces)
        nearest = std::min(nearest, hit(part.mesh, f, o, -axes.row(2).transpose()));
      const bool drawn = !isBackground(img, size_t(y) * view.width + x);
      covered += drawn;
      differ += drawn != std::isfinite(nearest);
    }
  // Only pixels whose centre lies within rounding of the silhouette may differ.
  EXPECT_LE(differ, 2u) << covered << " pixels covered";
  // Framed to fill the shorter side: the disc's area over the picture's height squared.
  EXPECT_NEAR(covered / (M_PI / 4 * view.height * view.height), 1 / (1.06 * 1.06), 0.03);
}

TEST(MeshPicture, FrontFacesWarmAndAHoleShowsTheCoolInside) {
  ViewSettings view;
  view.width = view.height = 101;
  view.elevationDeg = 0;  // looking along -z, into the hole
  const Image closed = pictureOfMesh(spherePart(), view, 0, MPI_COMM_SELF);
  const Image open = pictureOfMesh(spherePart(0.8 * kSphereRadius), view, 0, MPI_COMM_SELF);
  const uint8_t* front = &closed.rgb[(50 * 101 + 50) * 3];
  const uint8_t* inside = &open.rgb[(50 * 101 + 50) * 3];
  EXPECT_GT(front[0], 200);
  EXPECT_GT(front[0], front[2]);
  EXPECT_LT(inside[0], inside[2]);
  EXPECT_LT(inside[0], 150);
  // The rim at the picture's edge stays warm.
  const uint8_t* rim = &open.rgb[(50 * 101 + 8) * 3];
  EXPECT_GT(rim[0], rim[2]);
}

TEST(MeshPicture, ACameraInsideSeesTheInsideAllRound) {
  ViewSettings view;
  view.width = 64, view.height = 48;
  view.camera = Pose{Eigen::Matrix3d::Identity(), kSphereCentre};
  view.focal = 32, view.farthest = 4 * kSphereRadius;
  const Image img = pictureOfMesh(spherePart(), view, 0, MPI_COMM_SELF);
  for (size_t i = 0; i < size_t(view.width) * view.height; ++i) {
    ASSERT_FALSE(isBackground(img, i)) << "pixel " << i;
    ASSERT_LT(img.rgb[3 * i], img.rgb[3 * i + 2]) << "pixel " << i;  // back faces: cool
  }
}
