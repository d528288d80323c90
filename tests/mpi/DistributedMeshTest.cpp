#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "SharedTemp.h"
#include "SphereField.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/MeshPartPly.h"

using namespace rangefuse;
using namespace rangefuse::test;

namespace {

/// The whole mesh as one rank extracts it, with normals as the single-rank code gives them.
TriangleMesh serialSphereMesh() {
  BrickLayout layout = sphereLayout(1);
  BrickStore serial(layout, 0);
  fillSphere(serial);
  TriangleMesh one = extractDistributedMesh(serial, 0, MPI_COMM_SELF).mesh;
  one.normals = vertexNormals(one);
  return one;
}

/// sphereLayout with its bricks given to ranks as `split` says: "work" (equal work), "first"
/// (all on rank 0, the others hold nothing) or "last".
BrickLayout splitLayout(const std::string& split) {
  BrickLayout l = sphereLayout(mpi::size());
  const size_t n = l.codes.size();
  std::vector<size_t> start = l.rankStart;
  if (split == "first") std::fill(start.begin() + 1, start.end(), n);
  if (split == "last") std::fill(start.begin(), start.end() - 1, 0);
  l.setRuns(start);
  return l;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(DistributedMesh, SameMeshOnAllRanksAsOnOneRank) {
  BrickLayout layout = sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fillSphere(store);
  MeshStats stats;
  MeshPart part = extractDistributedMesh(store, 0, MPI_COMM_WORLD, &stats);
  addPartNormals(part, MPI_COMM_WORLD);
  if (mpi::size() > 1) {
    uint64_t halo = stats.haloBricksReceived, total = 0;
    MPI_Allreduce(&halo, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_GT(total, 0u);  // the split really crossed rank boundaries
  }
  const TriangleMesh distributed = gatherMesh(part, 0, MPI_COMM_WORLD);
  if (mpi::rank() != 0) return;
  const TriangleMesh one = serialSphereMesh();
  ASSERT_GT(one.faces.size(), 1000u);
  EXPECT_EQ(part.totalVertices, one.vertices.size());
  EXPECT_EQ(part.totalFaces, one.faces.size());
  EXPECT_EQ(distributed.vertices, one.vertices);
  EXPECT_EQ(distributed.faces, one.faces);
  EXPECT_EQ(distributed.normals, one.normals);  // bit for bit: summed in the same order
  double volume = 0;
  for (const auto& t : one.faces)
    volume += one.vertices[t[0]].dot(one.vertices[t[1]].cross(one.vertices[t[2]])) / 6.0;
  EXPECT_NEAR(volume / (4.0 / 3.0 * M_PI * std::pow(kRadius, 3)), 1.0, 0.01);
}

TEST(DistributedMesh, EveryVertexHasOneOwnerAndNoRankHoldsAnUnusedVertex) {
  BrickLayout layout = sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fillSphere(store);
  const MeshPart part = extractDistributedMesh(store, 0, MPI_COMM_WORLD);
  uint64_t owned = part.ownedVertices, allOwned = 0;
  MPI_Allreduce(&owned, &allOwned, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(allOwned, part.totalVertices);
  std::vector<int> used(part.mesh.vertices.size());
  for (const auto& t : part.mesh.faces)
    for (int k = 0; k < 3; ++k) used[t[k]] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
  for (size_t i = 0; i < part.global.size(); ++i) {
    EXPECT_LE(part.owner[i], mpi::rank());  // the lowest user owns a vertex
    EXPECT_GE(part.global[i], 0);
    EXPECT_LT(part.global[i], static_cast<int64_t>(part.totalVertices));
  }
}

TEST(MeshPartPly, SameBytesAsTheSingleRankWriterWhateverTheSplit) {
  const std::string dir = test::sharedTempPath("part-ply");
  if (mpi::rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  std::string expected;
  if (mpi::rank() == 0) {
    io::writeMeshPly(dir + "/one.ply", serialSphereMesh());
    expected = fileBytes(dir + "/one.ply");
  }
  for (const std::string split : {"work", "first", "last"}) {
    BrickLayout layout = splitLayout(split);
    BrickStore store(layout, mpi::rank());
    fillSphere(store);
    MeshPart part = extractDistributedMesh(store, 0, MPI_COMM_WORLD);
    addPartNormals(part, MPI_COMM_WORLD);
    const std::string path = dir + "/" + split + ".ply";
    ASSERT_TRUE(io::writeMeshPartPly(path, part, MPI_COMM_WORLD));
    if (mpi::rank() == 0) {
      EXPECT_EQ(fileBytes(path), expected) << split;
      EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove_all(dir);
}

TEST(MeshPartPly, AnEmptyMeshIsAValidFile) {
  const std::string dir = test::sharedTempPath("empty-ply");
  if (mpi::rank() == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  MeshPart part;
  part.rank = mpi::rank();
  ASSERT_TRUE(io::writeMeshPartPly(dir + "/empty.ply", part, MPI_COMM_WORLD));
  if (mpi::rank() == 0) {
    const TriangleMesh back = io::readMeshPly(dir + "/empty.ply");
    EXPECT_TRUE(back.vertices.empty() && back.faces.empty());
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove_all(dir);
}

TEST(MeshPartPly, AnUnwritableFolderFailsOnEveryRankWithoutAFile) {
  const std::string dir = test::sharedTempPath("missing-folder");
  MeshPart part;
  part.rank = mpi::rank();
  EXPECT_FALSE(io::writeMeshPartPly(dir + "/no/such/mesh.ply", part, MPI_COMM_WORLD));
  EXPECT_FALSE(std::filesystem::exists(dir + "/no/such/mesh.ply.tmp"));
}

TEST(Agree, OneFailingRankFailsEveryRank) {
  const bool ok = mpi::rank() != mpi::size() - 1;
  EXPECT_EQ(mpi::agree(ok, "injected failure (expected in this test)", MPI_COMM_WORLD), false);
  EXPECT_TRUE(mpi::agree(true, "", MPI_COMM_WORLD));
}
