// A damaged checkpoint is refused, never resumed into a different mesh: a real bunny checkpoint
// with one byte flipped or 64 bytes overwritten at many offsets either resumes to the identical
// mesh (the damage hit unused bytes) or is refused with a message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "SharedTemp.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/run/FuseJob.h"

using namespace rangefuse;
using test::sharedTempPath;

namespace {

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// Rank 0 writes `bytes` over `length` bytes at `offset` of a copy of `good`; all ranks wait.
void damagedCopy(const std::string& good, const std::string& bad, size_t offset, size_t length) {
  if (mpi::rank() == 0) {
    std::string bytes = readBytes(good);
    for (size_t i = offset; i < std::min(bytes.size(), offset + length); ++i)
      bytes[i] = static_cast<char>(length == 1 ? bytes[i] ^ 0x10 : 0xA5 ^ (i * 31));
    std::ofstream(bad, std::ios::binary) << bytes;
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST(CheckpointDamage, IsRefusedOrResumesToTheSameMesh) {
  const std::string good = sharedTempPath("good.h5"), bad = sharedTempPath("bad.h5"),
                    meshGood = sharedTempPath("good.ply"), meshBad = sharedTempPath("bad.ply");
  FuseOptions o;
  o.scans = RANGEFUSE_TEST_DATA "/bunny/bun.conf";
  o.field.voxel = 0.003;
  o.outputs.out = meshGood;
  o.outputs.checkpoint = good;
  ASSERT_EQ(runFuse(o, MPI_COMM_WORLD), 0);
  const std::string expected = mpi::rank() == 0 ? readBytes(meshGood) : "";
  const size_t size = std::filesystem::file_size(good);
  int refused = 0, same = 0;
  for (size_t length : {size_t{1}, size_t{64}})
    for (int k = 0; k < 40; ++k) {
      // Spread over the file, with the file's start (superblock, headers) sampled densely.
      const size_t offset = k < 10 ? k * 97 : (size - 64) * (k - 10) / 30;
      damagedCopy(good, bad, offset, length);
      FuseOptions r;
      r.scans = o.scans;
      r.outputs.resume = bad;
      r.outputs.out = meshBad;
      const int rc = runFuse(r, MPI_COMM_WORLD);
      if (rc != 0) {
        ++refused;
        EXPECT_FALSE(std::filesystem::exists(meshBad));
        continue;
      }
      ++same;
      if (mpi::rank() == 0) {
        EXPECT_EQ(readBytes(meshBad), expected)
            << length << " bytes damaged at " << offset << " resumed into a different mesh";
      }
      MPI_Barrier(MPI_COMM_WORLD);
      if (mpi::rank() == 0) std::filesystem::remove(meshBad);
    }
  if (mpi::rank() == 0) {
    std::printf("checkpoint of %zu bytes damaged at 80 places: %d refused, %d identical\n", size,
                refused, same);
    for (const auto& f : {good, bad, meshGood}) std::filesystem::remove(f);
  }
  EXPECT_GT(refused, 40) << "most damage hits data the checksums cover";
}

}  // namespace
