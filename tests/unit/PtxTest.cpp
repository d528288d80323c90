// Leica PTX: round trips, a hand-written file against hand-computed world points, bad input.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <random>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Ptx.h"

using namespace rangefuse;
using test::TempDir;

namespace {

RangeGrid randomGrid(int cols, int rows, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  RangeGrid g;
  g.cols = cols, g.rows = rows, g.spherical = true;
  g.cell.assign(static_cast<size_t>(cols) * rows, -1);
  for (size_t k = 0; k < g.cell.size(); ++k) {
    if (rng() % 5 == 0) continue;  // no return
    g.cell[k] = static_cast<int32_t>(g.points.size());
    g.points.emplace_back(u(rng), u(rng), u(rng));
  }
  return g;
}

std::string message(const std::string& path) {
  try {
    for (const io::PtxScan& s : io::indexPtx(path)) io::readPtxScan(path, s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string wholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Header of a 2 x 2 scan at the identity.
const char* kHeader = "2\n2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";

}  // namespace

TEST(Ptx, GridsAndPosesRoundTripExactly) {
  TempDir dir;
  const std::vector<RangeGrid> grids = {randomGrid(7, 5, 1), randomGrid(3, 11, 2)};
  std::vector<Pose> poses(2);
  poses[0].R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  poses[0].t = Eigen::Vector3d(1e5 + 0.125, -3, 7);  // survey coordinates stay exact
  poses[1].t = Eigen::Vector3d(0.5, 0.25, -1);
  const std::string path = dir.file("two.ptx");
  io::writePtx(path, grids, poses);
  const std::vector<io::PtxScan> scans = io::indexPtx(path);
  ASSERT_EQ(scans.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(scans[i].cols, grids[i].cols);
    EXPECT_EQ(scans[i].rows, grids[i].rows);
    EXPECT_EQ(scans[i].pose.R, poses[i].R);
    EXPECT_EQ(scans[i].pose.t, poses[i].t);
    const RangeGrid g = io::readPtxScan(path, scans[i]);
    EXPECT_TRUE(g.spherical);
    ASSERT_EQ(g.cell.size(), grids[i].cell.size());
    ASSERT_EQ(g.points.size(), grids[i].points.size());
    for (size_t k = 0; k < g.cell.size(); ++k) {  // points are numbered in file order
      ASSERT_EQ(g.cell[k] < 0, grids[i].cell[k] < 0) << "cell " << k;
      if (g.cell[k] >= 0) {
        EXPECT_EQ(g.points[g.cell[k]], grids[i].points[grids[i].cell[k]]);
      }
    }
  }
}

TEST(Ptx, ColumnsReadFromTheirOwnBytesAreTheSameColumnsOfTheWholeScan) {
  TempDir dir;
  const std::vector<RangeGrid> grids = {randomGrid(9, 4, 3), randomGrid(6, 7, 4)};
  const std::string path = dir.file("cols.ptx");
  io::writePtx(path, grids, {Pose{}, Pose{}});
  for (const io::PtxScan& scan : io::indexPtx(path)) {
    ASSERT_EQ(scan.columns.size(), static_cast<size_t>(scan.cols));
    EXPECT_EQ(scan.columns.front(), scan.offset);
    const RangeGrid whole = io::readPtxScan(path, scan);
    for (int first = 0; first <= scan.cols; ++first)
      for (int count = 0; first + count <= scan.cols; ++count) {
        const RangeGrid part = io::readPtxColumns(path, scan, first, count);
        ASSERT_EQ(part.cols, count);
        ASSERT_EQ(part.rows, scan.rows);
        for (int r = 0; r < scan.rows; ++r)
          for (int c = 0; c < count; ++c) {
            const int32_t a = part.at(r, c), b = whole.at(r, first + c);
            ASSERT_EQ(a < 0, b < 0) << "row " << r << ", column " << first + c;
            if (a >= 0) {
              EXPECT_EQ(part.points[a], whole.points[b]);
            }
          }
      }
    EXPECT_THROW(io::readPtxColumns(path, scan, scan.cols - 1, 2), std::logic_error);
  }
  // A line gone bad after indexing is named by its own line number, read from its column.
  std::string text = wholeFile(path);
  const io::PtxScan second = io::indexPtx(path)[1];
  text.replace(second.columns[2], 1, "x");
  const std::string bad = dir.write("bad.ptx", text);
  try {
    io::readPtxColumns(bad, io::indexPtx(bad)[1], 2, 1);
    ADD_FAILURE() << "a bad line was read";
  } catch (const InputError& e) {
    const uint64_t line = second.line + 2 * second.rows;
    EXPECT_NE(std::string(e.what()).find("bad.ptx:" + std::to_string(line) + ": expected"),
              std::string::npos)
        << e.what();
  }
}

TEST(Ptx, TwoScansGiveTheHandComputedWorldPointsInColumnMajorOrder) {
  TempDir dir;
  // Scan 1: a quarter turn about z, then (10, 20, 30): [x y z 1] M. Scan 2: the identity.
  const std::string text =
      "2\n2\n10 20 30\n0 1 0\n-1 0 0\n0 0 1\n"
      "0 1 0 0\n-1 0 0 0\n0 0 1 0\n10 20 30 1\n"
      "1 0 0 0.5\n0 0 0 0\n2 0 0 0.5 10 20 30\n0 3 0 0.5\n" +
      std::string(kHeader) + "1 2 3 0.1\r\n4 5 6 0.1\r\n7 8 9 0.1\r\n0 0 0 0\r\n";
  const std::string path = dir.write("hand.ptx", text);
  const std::vector<io::PtxScan> scans = io::indexPtx(path);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0].line, 11u);
  const RangeGrid a = io::readPtxScan(path, scans[0]);
  // File order: (c0 r0), (c0 r1), (c1 r0), (c1 r1); (c0 r1) saw nothing.
  EXPECT_EQ(a.at(1, 0), -1);
  ASSERT_GE(a.at(0, 0), 0);
  auto world = [&](const RangeGrid& g, const io::PtxScan& s, int r, int c) {
    return s.pose.apply(g.points[static_cast<size_t>(g.at(r, c))]);
  };
  EXPECT_LT((world(a, scans[0], 0, 0) - Eigen::Vector3d(10, 21, 30)).norm(), 1e-15);
  EXPECT_LT((world(a, scans[0], 0, 1) - Eigen::Vector3d(10, 22, 30)).norm(), 1e-15);
  EXPECT_LT((world(a, scans[0], 1, 1) - Eigen::Vector3d(7, 20, 30)).norm(), 1e-15);
  const RangeGrid b = io::readPtxScan(path, scans[1]);
  EXPECT_EQ(b.points.size(), 3u);
  EXPECT_EQ(world(b, scans[1], 1, 0), Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(b.at(1, 1), -1);
  EXPECT_EQ(b.sensor().toward(Eigen::Vector3d(0, 0, 2)), Eigen::Vector3d(0, 0, -1));
}

TEST(Ptx, BadInputNamesTheFileAndLine) {
  TempDir dir;
  const std::string points = "1 0 0 1\n2 0 0 1\n3 0 0 1\n";
  EXPECT_NE(message(dir.write("short.ptx", kHeader + points))
                .find("short.ptx:11: scan 1 has "
                      "fewer than 4 point lines"),
            std::string::npos);
  EXPECT_NE(message(dir.write("two.ptx", kHeader + points + "1 2\n")).find("two.ptx:14: expected"),
            std::string::npos);
  EXPECT_NE(message(dir.write("nan.ptx", kHeader + points + "nan 0 0 1\n"))
                .find("nan.ptx:14: non-finite"),
            std::string::npos);
  EXPECT_NE(message(dir.write("cols.ptx", "2.5\n" + std::string(kHeader + 2)))
                .find("cols.ptx:1: expected the number of columns"),
            std::string::npos);
  EXPECT_NE(message(dir.write("axis.ptx", "2\n2\n0 0 0\n1 0\n"))
                .find("axis.ptx:4: expected the scanner X axis"),
            std::string::npos);
  EXPECT_NE(message(dir.write("empty.ptx", "\n\n")).find("empty.ptx: no scan"), std::string::npos);
  EXPECT_NE(message(dir.file("missing.ptx")).find("missing.ptx: cannot open"), std::string::npos);
  InputLimits small;
  small.maxGridCells = 3;
  EXPECT_THROW(io::indexPtx(dir.write("big.ptx", kHeader + points + "4 0 0 1\n"), small),
               InputError);
}

TEST(Ptx, AStationWhoseTransformIsNotRigidIsRefusedByName) {
  TempDir dir;
  const std::string points = "1 0 0 1\n2 0 0 1\n3 0 0 1\n4 0 0 1\n";
  // PDAL's PTX tests: a header transform that scales z by 2, on the second station.
  const std::string scaled =
      "2\n2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 2 0\n0 0 0 1\n";
  const std::string text = kHeader + points + scaled + points;
  const std::string m = message(dir.write("scaled.ptx", text));
  EXPECT_NE(m.find("scaled.ptx:"), std::string::npos) << m;
  EXPECT_NE(m.find("station 1: the header's transform is not rigid"), std::string::npos) << m;
  EXPECT_NE(m.find("scales lengths by 1 to 2"), std::string::npos) << m;
  // The same transform printed to 8 digits is a rotation still.
  const std::string rounded =
      "2\n2\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.70710678 0.70710678 0 0\n-0.70710678 0.70710678 0 0\n"
      "0 0 1 0\n0 0 0 1\n";
  EXPECT_EQ(io::indexPtx(dir.write("rounded.ptx", rounded + points)).size(), 1u);
}
