#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"

using namespace rangefuse;

namespace {

RangeGrid smallGrid() {
  RangeGrid g;
  g.cols = 3;
  g.rows = 2;
  g.cell = {0, -1, 1, 2, 3, -1};
  g.points = {{0, 0, -1}, {1.5, 0.25, -1.125}, {0, 1, -2}, {0.5, 1, -0.75}};
  g.pinhole = Pinhole{269.8, 270.5, 159.5, 119.5};
  return g;
}

const char* kAsciiHeader =
    "ply\r\nformat ascii 1.0  \r\ncomment anything\r\nobj_info is_cyberware_data 1\r\n"
    "obj_info num_cols 2\r\nobj_info num_rows 2\r\nobj_info echo_frames 512\r\n"
    "element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
    "element range_grid 4\r\nproperty list uchar int vertex_indices\r\nend_header\r\n";

std::string asciiBody() {
  return "0 0 1 \r\n1 0 1 \r\n0 1 1 \r\n1 0\r\n1 1\r\n0\r\n1 2\r\n";
}

void expectError(const std::string& path, const std::string& fragment) {
  try {
    io::readRangeGridPly(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
  }
}

}  // namespace

class PlyRoundTrip : public ::testing::TestWithParam<io::PlyEncoding> {};

TEST_P(PlyRoundTrip, WriteThenReadGivesSameGrid) {
  test::TempDir dir;
  const RangeGrid g = smallGrid();
  io::writeRangeGridPly(dir.file("g.ply"), g, GetParam());
  const RangeGrid r = io::readRangeGridPly(dir.file("g.ply"));
  EXPECT_EQ(r.cols, 3);
  EXPECT_EQ(r.rows, 2);
  EXPECT_EQ(r.cell, g.cell);
  ASSERT_EQ(r.points.size(), g.points.size());
  for (size_t i = 0; i < g.points.size(); ++i) EXPECT_EQ(r.points[i], g.points[i]);
  ASSERT_TRUE(r.pinhole.has_value());
  EXPECT_DOUBLE_EQ(r.pinhole->fy, 270.5);
  EXPECT_DOUBLE_EQ(r.pinhole->cy, 119.5);
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, PlyRoundTrip,
                         ::testing::Values(io::PlyEncoding::Ascii,
                                           io::PlyEncoding::BinaryLittleEndian,
                                           io::PlyEncoding::BinaryBigEndian));

TEST(PlyReader, AcceptsCrlfTrailingSpacesUnknownObjInfo) {
  test::TempDir dir;
  const RangeGrid g = io::readRangeGridPly(dir.write("a.ply", kAsciiHeader + asciiBody()));
  EXPECT_EQ(g.cols, 2);
  EXPECT_EQ(g.cell, (std::vector<int32_t>{0, 1, -1, 2}));
  EXPECT_EQ(g.points[1], Eigen::Vector3d(1, 0, 1));
  EXPECT_FALSE(g.pinhole.has_value());
}

TEST(PlyReader, ReadsRealBunnyScan) {
  const RangeGrid g = io::readRangeGridPly(RANGEFUSE_TEST_DATA "/bunny/bun000.ply");
  EXPECT_EQ(g.cols, 512);
  EXPECT_EQ(g.rows, 400);
  EXPECT_EQ(g.points.size(), 40256u);
  size_t used = 0;
  for (int32_t c : g.cell) used += c >= 0;
  EXPECT_EQ(used, 40256u);
}

TEST(PlyReader, TruncatedAsciiBody) {
  test::TempDir dir;
  std::string body = asciiBody();
  expectError(dir.write("t.ply", kAsciiHeader + body.substr(0, body.size() - 10)), "truncated");
}

TEST(PlyReader, ExtraDataMeansCountsDoNotMatch) {
  test::TempDir dir;
  expectError(dir.write("x.ply", kAsciiHeader + asciiBody() + "1 2\n"), "do not match");
}

TEST(PlyReader, UnknownFormat) {
  test::TempDir dir;
  std::string h = kAsciiHeader;
  h.replace(h.find("ascii"), 5, "binary_middle_endian");
  expectError(dir.write("f.ply", h + asciiBody()), "unknown format");
}

TEST(PlyReader, NanCoordinate) {
  test::TempDir dir;
  std::string body = asciiBody();
  body.replace(0, 1, "nan");
  expectError(dir.write("n.ply", kAsciiHeader + body), "NaN");
}

TEST(PlyReader, InfCoordinateInBinary) {
  test::TempDir dir;
  RangeGrid g = smallGrid();
  g.points[2].y() = INFINITY;
  io::writeRangeGridPly(dir.file("i.ply"), g, io::PlyEncoding::BinaryBigEndian);
  expectError(dir.file("i.ply"), "vertex #2");
}

TEST(PlyReader, IndexOutOfRange) {
  test::TempDir dir;
  std::string body = asciiBody();
  body.replace(body.find("1 2\r\n"), 5, "1 7\r\n");
  expectError(dir.write("o.ply", kAsciiHeader + body), "out of range");
}

TEST(PlyReader, CellWithTwoIndices) {
  test::TempDir dir;
  std::string body = asciiBody();
  body.replace(body.find("0\r\n1 2"), 3, "2 0 1\r\n");
  expectError(dir.write("l.ply", kAsciiHeader + body), "0 or 1");
}

TEST(PlyReader, GridSizeDisagreesWithCells) {
  test::TempDir dir;
  std::string h = kAsciiHeader;
  h.replace(h.find("num_cols 2"), 10, "num_cols 3");
  expectError(dir.write("s.ply", h + asciiBody()), "num_cols");
}

namespace {

/// A binary grid of mixed property types, written byte by byte in either byte order.
std::string mixedBinaryGrid(bool bigEndian, int cols, int rows) {
  std::string out =
      std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\nobj_info num_cols " + std::to_string(cols) + "\nobj_info num_rows " +
      std::to_string(rows) + "\nelement vertex " + std::to_string(cols * rows / 2) +
      "\nproperty double x\nproperty float y\nproperty int16 z\n"
      "property uchar intensity\nelement range_grid " +
      std::to_string(cols * rows) + "\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (bigEndian) std::reverse(b, b + sizeof v);
    out.append(b, sizeof v);
  };
  for (int i = 0; i < cols * rows / 2; ++i) {
    put(0.125 * i - 3.0);
    put(static_cast<float>(i) / 7.0f);
    put(static_cast<int16_t>(-i));
    put(static_cast<uint8_t>(i % 251));
  }
  for (int c = 0; c < cols * rows; ++c) {
    out += static_cast<char>(c % 2 == 0 ? 1 : 0);
    if (c % 2 == 0) put(static_cast<uint32_t>(c / 2));
  }
  return out;
}

}  // namespace

TEST(PlyReader, BulkAndValueByValueReadersAgree) {
  // Little-endian bodies are decoded in bulk, big-endian ones value by value.
  test::TempDir dir;
  const RangeGrid little =
      io::readRangeGridPly(dir.write("le.ply", mixedBinaryGrid(false, 40, 30)));
  const RangeGrid big = io::readRangeGridPly(dir.write("be.ply", mixedBinaryGrid(true, 40, 30)));
  ASSERT_EQ(little.points.size(), 600u);
  EXPECT_EQ(little.points, big.points);
  EXPECT_EQ(little.cell, big.cell);
  EXPECT_EQ(little.points[5], Eigen::Vector3d(0.125 * 5 - 3.0, 5.0f / 7.0f, -5));
  EXPECT_EQ(little.cell[10], 5);
  EXPECT_EQ(little.cell[11], -1);
}

TEST(PlyReader, EveryTruncationOfABinaryGridIsAnError) {
  test::TempDir dir;
  const std::string whole = mixedBinaryGrid(false, 6, 4);
  const size_t header = whole.find("end_header\n") + 11;
  for (size_t n = header; n < whole.size(); ++n)
    expectError(dir.write("cut.ply", whole.substr(0, n)), "");
}

TEST(PlyReader, TruncatedBinary) {
  test::TempDir dir;
  io::writeRangeGridPly(dir.file("b.ply"), smallGrid(), io::PlyEncoding::BinaryLittleEndian);
  std::string bytes;
  {
    std::ifstream in(dir.file("b.ply"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  expectError(dir.write("b2.ply", bytes.substr(0, bytes.size() - 3)), "truncated");
}

TEST(PlyReader, HugeCountRefusedBeforeAllocating) {
  test::TempDir dir;
  std::string h = kAsciiHeader;
  h.replace(h.find("vertex 3"), 8, "vertex 4000000000");
  const std::string path = dir.write("h.ply", h + asciiBody());
  expectError(path,
              "element 'vertex' count 4e+09 exceeds the limit 200000000 (raise it with "
              "--max-elements)");
  // Past the limit, the body itself still refuses a count it cannot hold.
  InputLimits raised;
  raised.maxElements = 10'000'000'000;
  try {
    io::readRangeGridPly(path, raised);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("claims 4000000000"), std::string::npos) << e.what();
  }
}

TEST(PlyReader, GridLargerThanTheLimitIsRefused) {
  test::TempDir dir;
  std::string h = kAsciiHeader;
  const std::string path = dir.write("g.ply", h + asciiBody());
  InputLimits small;
  small.maxGridCells = 3;
  try {
    io::readRangeGridPly(path, small);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("num_cols x num_rows = 4 exceeds the limit 3 (raise it "
                                         "with --max-grid-cells)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(io::readRangeGridPly(path));
}

TEST(PlyReader, MissingFile) {
  expectError("/nonexistent/scan.ply", "cannot open");
}

TEST(PlyReader, AFolderIsNotAScan) {
  test::TempDir dir;
  std::filesystem::create_directory(dir.file("scan.ply"));
  expectError(dir.file("scan.ply"), "is not a regular file");
}

TEST(MeshPly, ReadsBunnyReference) {
  TriangleMesh m = io::readMeshPly(RANGEFUSE_TEST_DATA "/bunny/bun_zipper.ply");
  EXPECT_EQ(m.vertices.size(), 35947u);
  EXPECT_EQ(m.faces.size(), 69451u);
}

TEST(MeshPly, WriteThenReadRoundTrip) {
  test::TempDir dir;
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {{0, 2, 1}, {0, 1, 3}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  io::writeMeshPly(dir.file("m.ply"), m);
  TriangleMesh r = io::readMeshPly(dir.file("m.ply"));
  EXPECT_EQ(r.vertices, m.vertices);
  EXPECT_EQ(r.faces, m.faces);
  EXPECT_FALSE(std::filesystem::exists(dir.file("m.ply.tmp")));
}

TEST(MeshPly, FaceIndexOutOfRange) {
  test::TempDir dir;
  std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  const std::string path = dir.write("f.ply", text);
  try {
    io::readMeshPly(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("face #0"), std::string::npos) << e.what();
  }
}
