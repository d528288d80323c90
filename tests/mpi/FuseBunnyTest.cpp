#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "SharedTemp.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/parallel/Mpi.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {}  // namespace

TEST(FuseBunny, RealScansMatchTheStanfordReconstruction) {
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.voxel = 0.001;  // 1 mm
  o.out = sharedTempPath("bunny.ply");
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() != 0) return;
  TriangleMesh mesh = io::readMeshPly(o.out);
  TriangleMesh ref = io::readMeshPly(RANGEFUSE_TEST_DATA "/bunny/bun_zipper.ply");
  std::filesystem::remove(o.out);
  DistanceStats accuracy = summarize(sampledDistances(mesh, ref, 100000, 1));
  DistanceStats completeness = summarize(sampledDistances(ref, mesh, 100000, 2));
  std::printf("bunny 1 mm: accuracy mean %.4f mm, completeness mean %.4f mm\n", accuracy.mean * 1e3,
              completeness.mean * 1e3);
  EXPECT_LE(accuracy.mean, 0.10e-3);
  EXPECT_LE(completeness.mean, 0.15e-3);
  EXPECT_LE(accuracy.p99, 1e-3);
}

TEST(FuseBunny, MissingScanFailsOnEveryRankWithoutOutput) {
  std::string conf = sharedTempPath("missing.conf");
  if (mpi::rank() == 0) std::ofstream(conf) << "bmesh no_such_scan.ply 0 0 0 0 0 0 1\n";
  MPI_Barrier(MPI_COMM_WORLD);
  FuseOptions o;
  o.scans = conf;
  o.voxel = 0.001;
  o.out = sharedTempPath("never.ply");
  EXPECT_EQ(runFuse(o, MPI_COMM_WORLD), 1);
  EXPECT_FALSE(std::filesystem::exists(o.out));
  EXPECT_FALSE(std::filesystem::exists(o.out + ".tmp"));
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(conf);
}
