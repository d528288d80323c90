#include <gtest/gtest.h>

#include <filesystem>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/KdTree.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/RangeGridPly.h"

using namespace rangefuse;

namespace {

std::vector<Eigen::Vector3d> worldPoints(const io::ConfScan& s, bool transpose) {
  RangeGrid g = io::readRangeGridPly(s.path);
  std::vector<Eigen::Vector3d> out;
  const Eigen::Matrix3d R = transpose ? s.pose.R : Eigen::Matrix3d(s.pose.R.transpose());
  for (const auto& p : g.points) out.push_back(R * p + s.pose.t);
  return out;
}

/// Fraction of bun045's points within 1 mm of some bun000 point.
double overlapFraction(bool conventionAsMeasured) {
  io::ConfFile conf = io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf");
  PointCloud ref{worldPoints(conf.scans[0], conventionAsMeasured)};
  const auto tree = buildKdTree(ref);
  auto pts = worldPoints(conf.scans[1], conventionAsMeasured);
  size_t close = 0;
  for (const auto& p : pts) {
    uint32_t i;
    double d2;
    tree->knnSearch(p.data(), 1, &i, &d2);
    close += d2 < 1e-6;
  }
  return double(close) / pts.size();
}

}  // namespace

TEST(Conf, BunnyScansOverlapWithMeasuredConvention) {
  // NOTES.md: 91.3% with p_world = R(q)^T p + t, 0.3% with R(q) as written.
  EXPECT_GT(overlapFraction(true), 0.85);
  EXPECT_LT(overlapFraction(false), 0.05);
}

TEST(Conf, ReadsBunnyConf) {
  io::ConfFile conf = io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf");
  ASSERT_EQ(conf.scans.size(), 10u);
  EXPECT_EQ(conf.scans[1].name, "bun045.ply");
  EXPECT_EQ(conf.scans[1].path, RANGEFUSE_TEST_DATA "/bunny/bun045.ply");
  EXPECT_TRUE(conf.scans[0].pose.R.isIdentity());
  EXPECT_TRUE(conf.warnings.empty());
}

TEST(Conf, WriteThenReadGivesSameTransforms) {
  test::TempDir dir;
  io::ConfFile conf = io::readConf(RANGEFUSE_TEST_DATA "/bunny/bun.conf");
  io::writeConf(dir.file("out.conf"), conf.scans);
  io::ConfFile back = io::readConf(dir.file("out.conf"));
  ASSERT_EQ(back.scans.size(), conf.scans.size());
  for (size_t i = 0; i < conf.scans.size(); ++i) {
    // Written elsewhere, the names lead back to the same files.
    EXPECT_EQ(std::filesystem::weakly_canonical(back.scans[i].path),
              std::filesystem::weakly_canonical(conf.scans[i].path));
    EXPECT_LT((back.scans[i].pose.R - conf.scans[i].pose.R).norm(), 1e-14);
    EXPECT_EQ(back.scans[i].pose.t, conf.scans[i].pose.t);
  }
}

TEST(Conf, NamesAreRelativeToTheFolderOfTheConfThatHoldsThem) {
  EXPECT_EQ(io::nameFor("bun000.ply", "/data/bunny/bun000.ply", "/data/bunny/out.conf"),
            "bun000.ply");
  EXPECT_EQ(io::nameFor("bun000.ply", "/data/bunny/bun000.ply", "/data/runs/p.conf"),
            "../bunny/bun000.ply");
  EXPECT_EQ(io::nameFor("../x/s.ptx#3", "/data/x/s.ptx", "/data/y/z/p.conf"), "../../x/s.ptx#3");
  EXPECT_EQ(io::nameFor("depth/1.5.png", "/seq/depth/1.5.png", "/seq/poses.conf"), "depth/1.5.png");
  EXPECT_EQ(io::nameFor("/abs/a.ply", "/abs/a.ply", "/elsewhere/p.conf"), "/abs/a.ply");
}

TEST(Conf, ABareNameIsInTheWorkingFolder) {
  test::TempDir dir;
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir.file(""));
  EXPECT_EQ(io::nameFor("s.ply", dir.file("scans/s.ply"), "out.conf"), "scans/s.ply");
  EXPECT_EQ(io::nameFor("s.ply", dir.file("s.ply"), "out.conf"), "s.ply");
  std::filesystem::current_path(before);
}

TEST(Conf, MeshLinesWarnCameraIgnored) {
  test::TempDir dir;
  io::ConfFile c = io::readConf(dir.write(
      "a.conf",
      "camera 1 2 3  0 0 0 1\r\nmesh other.ply 0 0 0 0 0 0 1\nbmesh s.ply 1 2 3 0 0 0 1\n"));
  ASSERT_EQ(c.scans.size(), 1u);
  EXPECT_EQ(c.scans[0].pose.t, Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("line 2"), std::string::npos);
}

TEST(Conf, BadLinesNameFileAndLine) {
  test::TempDir dir;
  const std::string path =
      dir.write("b.conf", "bmesh a.ply 0 0 0 0 0 0 1\nbmesh b.ply 0 0 0 0 0\n");
  try {
    io::readConf(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::readConf(dir.write("c.conf", "bmesh a.ply 0 0 nan 0 0 0 1\n")), InputError);
  EXPECT_THROW(io::readConf(dir.write("d.conf", "frobnicate\n")), InputError);
  EXPECT_THROW(io::readConf(dir.write("e.conf", "camera 0 0 0 0 0 0 1\n")), InputError);
  EXPECT_THROW(io::readConf(dir.file("missing.conf")), InputError);
}
