#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "../fuzz/FuzzEntries.h"
#include "DirectoryExpectations.h"
#include "SharedTemp.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/Checkpoint.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {

/// A layout of scattered bricks with recognisable voxel values.
BrickLayout testLayout(int ranks) {
  BrickLayout l;
  l.grid.voxel = 0.25;
  l.grid.brick = 4;
  l.grid.origin = Eigen::Vector3d(-1.5, 2.25, 0.125);
  for (int i = 0; i < 37; ++i) l.codes.push_back(mortonEncode({i % 5, (i * 7) % 11, i / 3}));
  std::sort(l.codes.begin(), l.codes.end());
  l.codes.erase(std::unique(l.codes.begin(), l.codes.end()), l.codes.end());
  for (size_t i = 0; i < l.codes.size(); ++i) l.work.push_back(1 + (i * 13) % 7);
  l.setRuns(partitionWork(l.work, ranks));
  return l;
}

float valueOf(uint64_t code, size_t voxel, int field) {
  return static_cast<float>(std::sin(0.001 * code + 0.37 * voxel + field)) * 1e3f;
}

void fill(BrickStore& s) {
  for (size_t b = 0; b < s.brickCount(); ++b)
    for (size_t v = 0; v < s.voxelsPerBrick(); ++v) {
      VoxelSums& x = s.sums()[b * s.voxelsPerBrick() + v];
      float* f = reinterpret_cast<float*>(&x);
      for (int k = 0; k < 6; ++k) f[k] = valueOf(s.code(b), v, k);
    }
}

}  // namespace

TEST(Checkpoint, EveryVoxelAndPoseRoundTripsBitForBit) {
  const std::string path = sharedTempPath("ck") + ".h5";
  const BrickLayout layout = testLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fill(store);
  io::CheckpointMeta meta;
  meta.parameters = {{"voxel", 0.25}, {"method", "prism"}};
  meta.scanNames = {"a.ply", "b.ply"};
  meta.scanHashes = {"0123456789abcdef", "fedcba9876543210"};
  Pose p;
  p.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  p.t = Eigen::Vector3d(0.1, -2.0 / 3.0, 1e-17);
  meta.poses = {Pose{}, p};
  meta.progress = {{"stage", "field"}};
  meta.hasField = true;
  meta.grid = layout.grid;
  io::writeCheckpoint(path, meta, &store, MPI_COMM_WORLD);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  const io::CheckpointMeta back = io::readCheckpointMeta(path, MPI_COMM_WORLD);
  EXPECT_EQ(back.scanNames, meta.scanNames);
  EXPECT_EQ(back.scanHashes, meta.scanHashes);
  EXPECT_EQ(back.poses[1].R, p.R);  // JSON keeps doubles exactly (shortest round-trip form)
  EXPECT_EQ(back.poses[1].t, p.t);
  EXPECT_EQ(back.grid.origin, layout.grid.origin);
  EXPECT_EQ(back.progress, meta.progress);
  BrickLayout readLayout;
  const auto read = io::readCheckpointField(path, back, readLayout, MPI_COMM_WORLD);
  // Each rank reads back its own part: its bricks, those bordering them, every rank's range.
  test::expectDirectory(readLayout, layout, mpi::rank());
  for (size_t b = 0; b < read->brickCount(); ++b)
    for (size_t v = 0; v < read->voxelsPerBrick(); ++v) {
      const float* f =
          reinterpret_cast<const float*>(&read->sums()[b * read->voxelsPerBrick() + v]);
      for (int k = 0; k < 6; ++k) ASSERT_EQ(f[k], valueOf(read->code(b), v, k));
    }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(path);
}

namespace {

/// An HDF5 file with a `format` attribute (or none) and a `version`, and nothing else.
std::string foreignFile(const std::string& name, const char* format, int version) {
  const std::string path = sharedTempPath(name) + ".h5";
  if (mpi::rank() == 0) {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t scalar = H5Screate(H5S_SCALAR);
    if (format) {
      const hid_t type = H5Tcopy(H5T_C_S1);
      H5Tset_size(type, std::strlen(format));
      const hid_t a = H5Acreate2(file, "format", type, scalar, H5P_DEFAULT, H5P_DEFAULT);
      H5Awrite(a, type, format);
      H5Aclose(a);
      H5Tclose(type);
    }
    const hid_t v = H5Acreate2(file, "version", H5T_NATIVE_INT, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(v, H5T_NATIVE_INT, &version);
    H5Aclose(v);
    H5Sclose(scalar);
    H5Fclose(file);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

void expectRefused(const std::string& path, const std::string& fragment) {
  try {
    io::readCheckpointMeta(path, MPI_COMM_WORLD);
    ADD_FAILURE() << "accepted " << path;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(path);
}

}  // namespace

TEST(Checkpoint, ForeignAndNewerFilesAreRefused) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  expectRefused(foreignFile("foreign", nullptr, 1), "not a rangefuse checkpoint");
  expectRefused(foreignFile("other", "someone-else", 1), "not a rangefuse checkpoint");
  expectRefused(foreignFile("newer", "rangefuse-checkpoint", 99), "newer rangefuse");
  expectRefused(foreignFile("older", "rangefuse-checkpoint", 1), "has no checksums");
  expectRefused(foreignFile("nometa", "rangefuse-checkpoint", io::kCheckpointVersion),
                "no dataset meta");
}

TEST(Checkpoint, EveryFuzzFoundInputIsReadOrRefused) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const auto dir = std::filesystem::path(RANGEFUSE_FUZZ_DIR) / "regressions" / "checkpoint";
  ASSERT_TRUE(std::filesystem::is_directory(dir));
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    if (f.path().filename().string()[0] == '.') continue;  // .gitkeep
    std::ifstream in(f.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NO_THROW(fuzz::checkpoint(bytes)) << f.path();  // each rank its own file
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST(Checkpoint, FieldLargerThanTheVoxelLimitIsRefused) {
  const std::string path = sharedTempPath("limit.h5");
  BrickLayout layout = testLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  io::CheckpointMeta meta;
  meta.hasField = true;
  meta.grid = layout.grid;
  io::writeCheckpoint(path, meta, &store, MPI_COMM_WORLD);
  InputLimits limits;
  limits.maxVoxels = 100;
  try {
    io::readCheckpointMeta(path, MPI_COMM_WORLD, limits);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field voxels"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--max-voxels"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(io::readCheckpointMeta(path, MPI_COMM_WORLD));
  MPI_Barrier(MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::filesystem::remove(path);
}
