// Clean-up after a failed parallel write: the temporary and the lock files Open MPI leaves
// beside it go; every other file in the folder stays.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "TempDir.h"
#include "parallelio/FailedTemporary.h"

namespace rangefuse::io {
namespace {

std::vector<std::string> filesIn(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(FailedTemporary, RemovesTheTemporaryAndItsOpenMpiLocksOnly) {
  test::TempDir dir;
  const std::vector<std::string> gone = {"mesh.ply.tmp", "mesh.ply.tmp-1057095681-18041.lock",
                                         "mesh.ply.tmp-2-3.lock"};
  const std::vector<std::string> kept = {"mesh.ply",
                                         "mesh.ply.tmp-1057095681-18041.lock.bak",
                                         "mesh.ply.tmp.lock",
                                         "mesh.ply.tmp-12.lock",
                                         "mesh.ply.tmp--3.lock",
                                         "mesh.ply.tmp-1-.lock",
                                         "mesh.ply.tmp-a-3.lock",
                                         "other.ply.tmp-1-2.lock",
                                         "xmesh.ply.tmp-1-2.lock"};
  for (const auto& name : gone) dir.write(name, "x");
  for (const auto& name : kept) dir.write(name, "x");

  internal::removeFailedTemporary(dir.file("mesh.ply.tmp"));

  std::vector<std::string> expected = kept;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(filesIn(dir.file("")), expected);
}

TEST(FailedTemporary, AMissingTemporaryOrFolderIsNotAnError) {
  test::TempDir dir;
  dir.write("mesh.ply.tmp-5-6.lock", "x");
  internal::removeFailedTemporary(dir.file("mesh.ply.tmp"));
  EXPECT_TRUE(filesIn(dir.file("")).empty());
  internal::removeFailedTemporary(dir.file("no-such-folder/mesh.ply.tmp"));
}

}  // namespace
}  // namespace rangefuse::io
