#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "SharedTemp.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {}  // namespace

TEST(FuseBunny, RealScansMatchTheStanfordReconstruction) {
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = 0.001;  // 1 mm
  o.outputs.out = sharedTempPath("bunny.ply");
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() != 0) return;
  TriangleMesh mesh = io::readMeshPly(o.outputs.out);
  TriangleMesh ref = io::readMeshPly(RANGEFUSE_TEST_DATA "/bunny/bun_zipper.ply");
  std::filesystem::remove(o.outputs.out);
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
  o.field.voxel = 0.001;
  o.outputs.out = sharedTempPath("never.ply");
  EXPECT_EQ(runFuse(o, MPI_COMM_WORLD), 1);
  EXPECT_FALSE(std::filesystem::exists(o.outputs.out));
  EXPECT_FALSE(std::filesystem::exists(o.outputs.out + ".tmp"));
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(conf);
}

TEST(FuseBunny, FarFromTheOriginGivesTheSameMesh) {
  // Survey-style coordinates: 1e5 m from the origin with 1 mm voxels.
  const Eigen::Vector3d offset(1e5, -1e5, 1e5);
  const io::ConfFile near = io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf");
  std::vector<io::ConfScan> far = near.scans;
  for (auto& s : far) {
    s.name = s.path;
    s.pose.t += offset;
  }
  // Paths first: sharedTempPath is collective, and only rank 0 checks the meshes.
  const std::string conf = sharedTempPath("far.conf"), nearOut = sharedTempPath("near.ply"),
                    farOut = sharedTempPath("far.ply");
  if (mpi::rank() == 0) io::writeConf(conf, far);
  MPI_Barrier(MPI_COMM_WORLD);
  FuseOptions o;
  o.field.voxel = 0.001;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.outputs.out = nearOut;
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  o.scans = conf;
  o.outputs.out = farOut;
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  if (mpi::rank() != 0) return;
  const TriangleMesh nearMesh = io::readMeshPly(nearOut);
  TriangleMesh farMesh = io::readMeshPly(farOut);
  for (auto& v : farMesh.vertices) v -= offset;
  const TriangleMesh ref = io::readMeshPly(RANGEFUSE_TEST_DATA "/bunny/bun_zipper.ply");
  const DistanceStats accuracy = summarize(sampledDistances(farMesh, ref, 100000, 1));
  const DistanceStats shift = summarize(sampledDistances(farMesh, nearMesh, 100000, 3));
  std::printf(
      "bunny 1 mm at 1e5 m: accuracy mean %.4f mm; from the near-origin mesh mean %.2e mm, "
      "max %.2e mm\n",
      accuracy.mean * 1e3, shift.mean * 1e3, shift.max * 1e3);
  EXPECT_LE(accuracy.mean, 0.10e-3);
  EXPECT_LE(shift.max, 0.01e-3);  // a hundredth of a voxel
  for (const std::string& f : {nearOut, farOut, conf}) std::filesystem::remove(f);
}
