// Outputs checked against inputs by where the file system puts them: the same file through a
// symbolic link, a hard link, "./" or ".." is one file; a file not yet written is its folder
// and name; against a brute-force reference (canonical paths and inode numbers) on random
// aliases.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/OutputOverlap.h"

using namespace rangefuse;
using test::TempDir;
namespace fs = std::filesystem;

namespace {

/// The message of the InputError refuseOverlaps throws, or "" when it throws none.
std::string refusal(const io::FileRoles& files) {
  try {
    io::refuseOverlaps(files);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A folder holding a.ply, a hard link to it, a symbolic link to it, and sub/.
struct Aliases {
  TempDir dir;
  Aliases() {
    dir.write("a.ply", "ply\n");
    fs::create_directories(dir.file("sub"));
    fs::create_hard_link(dir.file("a.ply"), dir.file("hard.ply"));
    fs::create_symlink(dir.file("a.ply"), dir.file("soft.ply"));
    fs::create_directory_symlink(dir.file("sub"), dir.file("subLink"));
  }
};

}  // namespace

TEST(OutputOverlap, OneFileByEveryName) {
  Aliases a;
  const std::string file = a.dir.file("a.ply");
  for (const std::string& alias :
       {a.dir.file("hard.ply"), a.dir.file("soft.ply"), a.dir.file("sub/../a.ply"),
        a.dir.file("./a.ply"), a.dir.file("subLink/../a.ply")})
    EXPECT_TRUE(io::sameFile(file, alias)) << alias;
  EXPECT_FALSE(io::sameFile(file, a.dir.file("sub/a.ply")));
  // Files not written yet: the same folder and name, whichever way the folder is named.
  EXPECT_TRUE(io::sameFile(a.dir.file("sub/new.ply"), a.dir.file("subLink/new.ply")));
  EXPECT_TRUE(io::sameFile(a.dir.file("new.ply"), a.dir.file("sub/../new.ply")));
  EXPECT_FALSE(io::sameFile(a.dir.file("new.ply"), a.dir.file("sub/new.ply")));
  // A dangling link is written through: it names the file it points at.
  fs::create_symlink(a.dir.file("target.ply"), a.dir.file("dangling.ply"));
  EXPECT_TRUE(io::sameFile(a.dir.file("dangling.ply"), a.dir.file("target.ply")));
  EXPECT_FALSE(io::placeOf(a.dir.file("missing/x.ply")));
}

TEST(OutputOverlap, RefusalNamesBothFilesAndRoles) {
  Aliases a;
  io::FileRoles files;
  files.inputs = {{"scan list", a.dir.file("a.ply")}};
  files.outputs = {{"mesh", a.dir.file("soft.ply")}};
  const std::string why = refusal(files);
  EXPECT_NE(why.find(a.dir.file("soft.ply") + ": the mesh would overwrite '" + a.dir.file("a.ply") +
                     "' (the scan list)"),
            std::string::npos)
      << why;
  files.outputs = {{"mesh", a.dir.file("m.ply")}, {"report", a.dir.file("sub/../m.ply")}};
  EXPECT_NE(
      refusal(files).find("given as both '" + a.dir.file("m.ply") + "' (the mesh) and the report"),
      std::string::npos)
      << refusal(files);
  files.outputs = {{"mesh", a.dir.file("m.ply")}, {"report", a.dir.file("r.json")}};
  EXPECT_EQ(refusal(files), "");
  files.watched = {{"followed folder", a.dir.file("subLink")}};
  files.outputs = {{"preview", a.dir.file("sub/../sub/p.png")}};
  EXPECT_NE(refusal(files).find("inside"), std::string::npos) << refusal(files);
  files.outputs = {{"preview", a.dir.file("p.png")}};
  EXPECT_EQ(refusal(files), "");
}

TEST(OutputOverlap, MatchesCanonicalPathsOnRandomAliases) {
  // Brute force: two names are one file when their canonical paths are equal (existing files:
  // or their inodes, for hard links); random names built from links, "./" and "..".
  Aliases a;
  const std::vector<std::string> folders = {"",     "./",       "sub/../", "subLink/../",
                                            "sub/", "subLink/", "sub/./"};
  const std::vector<std::string> names = {"a.ply", "hard.ply", "soft.ply", "new.ply", "b.ply"};
  std::mt19937 rng(7);
  a.dir.write("sub/b.ply", "x");
  const auto reference = [&](const std::string& p, const std::string& q) {
    std::error_code ec;
    struct stat sp, sq;
    if (::stat(p.c_str(), &sp) == 0 && ::stat(q.c_str(), &sq) == 0)
      return sp.st_dev == sq.st_dev && sp.st_ino == sq.st_ino;
    return fs::weakly_canonical(p, ec) == fs::weakly_canonical(q, ec);
  };
  for (int trial = 0; trial < 400; ++trial) {
    const auto draw = [&] {
      return a.dir.file(folders[rng() % folders.size()] + names[rng() % names.size()]);
    };
    const std::string p = draw(), q = draw();
    EXPECT_EQ(io::sameFile(p, q), reference(p, q)) << p << " vs " << q;
  }
}
