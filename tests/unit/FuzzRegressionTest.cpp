// Replays every input a fuzzer ever crashed on (tests/fuzz/regressions/ENTRY/) through the
// same entry, plus hand-made hostile inputs: each must be read or refused with InputError.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../fuzz/FuzzEntries.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"

namespace rangefuse {
namespace {

std::string readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class FuzzRegression : public ::testing::TestWithParam<const char*> {};

TEST_P(FuzzRegression, EveryFoundCrashIsNowReadOrRefused) {
  const std::string entryName = GetParam();
  const fuzz::Entry entry = fuzz::entryNamed(entryName);
  ASSERT_NE(entry, nullptr);
  const std::filesystem::path dir =
      std::filesystem::path(RANGEFUSE_FUZZ_DIR) / "regressions" / entryName;
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    if (f.path().filename().string()[0] == '.') continue;  // .gitkeep keeps the folder in git
    EXPECT_NO_THROW(entry(readBytes(f.path()))) << f.path();
  }
}

// The checkpoint entry needs MPI: it is replayed by the MPI tests.
INSTANTIATE_TEST_SUITE_P(Readers, FuzzRegression,
                         ::testing::Values("range_grid_ply", "mesh_ply", "conf", "fuse_ini", "ptx",
                                           "e57", "depth_png", "depth_sequence", "colour_image"));

TEST(FuzzRegression, ListItemTooLargeForAnIndexIsRefused) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 6.6e86\n";
  try {
    io::parseMeshPly("big.ply", ply);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "element 'face' #0: list item 6.6e+86 of 'vertex_indices' is out of range"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rangefuse
