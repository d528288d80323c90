#include <gtest/gtest.h>

#include <cmath>

#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/parallel/Mpi.h"

using namespace rangefuse;

namespace {

const Eigen::Vector3d kCentre(20.3, 19.6, 20.2);
const double kRadius = 12.2;

double sphere(const Eigen::Vector3d& p) {
  return (p - kCentre).norm() - kRadius;
}

/// Bricks of 4^3 unit voxels within reach of the sphere, split over `ranks`.
BrickLayout sphereLayout(int ranks) {
  BrickLayout l;
  l.grid.brick = 4;
  for (int z = 0; z < 12; ++z)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        Eigen::Vector3d centre = 4.0 * Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(1.5);
        if (std::abs(sphere(centre)) < 6) l.codes.push_back(mortonEncode({x, y, z}));
      }
  std::sort(l.codes.begin(), l.codes.end());
  l.work.assign(l.codes.size(), 1);
  l.rankStart = partitionWork(l.work, ranks);
  return l;
}

/// A distance field observed within 3 voxels of the surface.
void fillSphere(BrickStore& store) {
  const int B = store.grid().brick;
  for (size_t b = 0; b < store.brickCount(); ++b) {
    BrickCoord base = mortonDecode(store.code(b)) * B;
    for (int z = 0; z < B; ++z)
      for (int y = 0; y < B; ++y)
        for (int x = 0; x < B; ++x) {
          VoxelIndex v = base + VoxelIndex(x, y, z);
          double d = sphere(store.grid().centre(v));
          VoxelSums& s = store.sums()[store.offset(b, v)];
          if (std::abs(d) <= 3) s.wd = static_cast<float>(d), s.w = 1;
        }
  }
}

}  // namespace

TEST(DistributedMesh, SameMeshOnAllRanksAsOnOneRank) {
  BrickLayout layout = sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fillSphere(store);
  MeshStats stats;
  TriangleMesh distributed = extractDistributedMesh(store, 0, MPI_COMM_WORLD, &stats);
  if (mpi::size() > 1) {
    uint64_t halo = stats.haloBricksReceived, total = 0;
    MPI_Allreduce(&halo, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_GT(total, 0u);  // the split really crossed rank boundaries
  }
  if (mpi::rank() != 0) return;
  BrickLayout serialLayout = sphereLayout(1);
  BrickStore serial(serialLayout, 0);
  fillSphere(serial);
  TriangleMesh one = extractDistributedMesh(serial, 0, MPI_COMM_SELF);
  ASSERT_GT(one.faces.size(), 1000u);
  EXPECT_EQ(distributed.vertices, one.vertices);
  EXPECT_EQ(distributed.faces, one.faces);
  double volume = 0;
  for (const auto& t : one.faces)
    volume += one.vertices[t[0]].dot(one.vertices[t[1]].cross(one.vertices[t[2]])) / 6.0;
  EXPECT_NEAR(volume / (4.0 / 3.0 * M_PI * std::pow(kRadius, 3)), 1.0, 0.01);
}

TEST(Agree, OneFailingRankFailsEveryRank) {
  const bool ok = mpi::rank() != mpi::size() - 1;
  EXPECT_EQ(mpi::agree(ok, "injected failure (expected in this test)", MPI_COMM_WORLD), false);
  EXPECT_TRUE(mpi::agree(true, "", MPI_COMM_WORLD));
}
