#include <gtest/gtest.h>

#include <algorithm>

#include "SphereField.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/render/MeshPicture.h"
#include "rangefuse/render/Render.h"

using namespace rangefuse;
using namespace rangefuse::test;

namespace {

/// The picture one rank draws from the whole field.
Image serialPicture(const ViewSettings& view) {
  const BrickLayout layout = sphereLayout(1);
  BrickStore store(layout, 0);
  fillSphere(store);
  return renderField(SparseField::gather(store, 0, 0, MPI_COMM_SELF), view);
}

bool isBackground(const Image& img, size_t pixel) {
  return std::equal(kBackground.begin(), kBackground.end(), img.rgb.begin() + 3 * pixel);
}

/// The rows and columns holding surface: first and last of each.
Eigen::Array4i silhouetteBounds(const Image& img) {
  Eigen::Array4i b(img.width, -1, img.height, -1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (!isBackground(img, size_t(y) * img.width + x))
        b = Eigen::Array4i(std::min(b[0], x), std::max(b[1], x), std::min(b[2], y),
                           std::max(b[3], y));
  return b;
}

}  // namespace

TEST(DistributedRender, SamePixelsAsTheGatheredFieldFromEveryView) {
  const BrickLayout layout = sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fillSphere(store);
  for (const auto& [az, el] : {std::pair{0.0, 20.0}, {135.0, -40.0}, {250.0, 85.0}}) {
    ViewSettings view;
    view.azimuthDeg = az;
    view.elevationDeg = el;
    view.width = 96;
    view.height = 80;
    const Image composite = renderDistributed(store, 0, view, 0, MPI_COMM_WORLD);
    if (mpi::rank() != 0) continue;
    const Image one = serialPicture(view);
    EXPECT_EQ(composite.rgb, one.rgb) << "view " << az << "," << el;
    // The view frames the surface: the sphere's silhouette spans most of the picture's height
    // (the shorter side), centred, and is round.
    const Eigen::Array4i b = silhouetteBounds(one);
    const double across = b[3] - b[2] + 1;
    EXPECT_GT(across, 0.8 * view.height) << "view " << az << "," << el;
    EXPECT_LT(across, 0.97 * view.height);
    EXPECT_NEAR(b[1] - b[0] + 1, across, 2);
    EXPECT_NEAR(0.5 * (b[0] + b[1] + 1), 0.5 * view.width, 1.5);
  }
}

TEST(DistributedRender, AMeshInPartsGivesThePictureOfTheWholeMesh) {
  // A mesh sphere with a hole, its faces dealt out to the ranks in turn.
  TriangleMesh whole;
  const int rings = 24, sectors = 48;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      whole.vertices.push_back(
          Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  for (int i = 3; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const int a = i * sectors + j, b = (i + 1) * sectors + j,
                c = (i + 1) * sectors + (j + 1) % sectors, d = i * sectors + (j + 1) % sectors;
      whole.faces.push_back({a, b, c});
      whole.faces.push_back({a, c, d});
    }
  MeshPart mine, all;
  mine.mesh.vertices = all.mesh.vertices = whole.vertices;
  all.mesh.faces = whole.faces;
  for (size_t f = mpi::rank(); f < whole.faces.size(); f += mpi::size())
    mine.mesh.faces.push_back(whole.faces[f]);
  for (const auto& [az, el] : {std::pair{0.0, 20.0}, {135.0, 70.0}, {250.0, -85.0}}) {
    ViewSettings view;
    view.azimuthDeg = az, view.elevationDeg = el;
    view.width = 90, view.height = 70;
    const Image composite = pictureOfMesh(mine, view, 0, MPI_COMM_WORLD);
    if (mpi::rank() != 0) continue;
    EXPECT_EQ(composite.rgb, pictureOfMesh(all, view, 0, MPI_COMM_SELF).rgb)
        << "view " << az << "," << el;
  }
}
