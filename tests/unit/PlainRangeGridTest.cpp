// The one-pass decoder of the usual binary grid layout against the general PLY reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>

#include "PlainRangeGrid.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/RangeGridPly.h"

using namespace rangefuse;

namespace {

struct Layout {
  bool bigEndian = false;
  bool doubles = false;     ///< x, y, z as double (else float)
  bool signedIndex = true;  ///< list items int (else uint)
  bool int16Z = false;      ///< z as int16: not the plain layout
};

/// A 12 x 9 grid with every third cell empty; the vertex records carry two more properties
/// around x, y and z, as scanners' files do.
std::string gridBytes(const Layout& l,
                      const std::function<void(int, Eigen::Vector3d&)>& edit = {}) {
  const int cols = 12, rows = 9, cells = cols * rows;
  int points = 0;
  for (int c = 0; c < cells; ++c) points += c % 3 != 0;
  const std::string coord = l.doubles ? "double" : "float";
  std::string out =
      std::string("ply\nformat ") + (l.bigEndian ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\nobj_info num_cols 12\nobj_info num_rows 9\nelement vertex " + std::to_string(points) +
      "\nproperty uchar flags\nproperty " + coord + " x\nproperty " + coord +
      " y\nproperty float confidence\nproperty " + (l.int16Z ? "int16" : coord) +
      " z\nelement range_grid 108\nproperty list uchar " + (l.signedIndex ? "int" : "uint") +
      " vertex_indices\nend_header\n";
  auto put = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (l.bigEndian) std::reverse(b, b + sizeof v);
    out.append(b, sizeof v);
  };
  auto coordinate = [&](double v) { l.doubles ? put(v) : put(static_cast<float>(v)); };
  for (int i = 0; i < points; ++i) {
    Eigen::Vector3d p(0.01 * i - 0.3, 0.1 / (i + 1), -0.5 - 0.001 * i);
    if (edit) edit(i, p);
    put(static_cast<uint8_t>(i));
    coordinate(p.x());
    coordinate(p.y());
    put(0.5f);
    l.int16Z ? put(static_cast<int16_t>(-i)) : coordinate(p.z());
  }
  for (int c = 0, i = 0; c < cells; ++c) {
    out += static_cast<char>(c % 3 != 0);
    if (c % 3 != 0)
      l.signedIndex ? put(static_cast<int32_t>(i++)) : put(static_cast<uint32_t>(i++));
  }
  return out;
}

/// decodePlainRangeGrid on `bytes`, with the grid's size set as the reader sets it.
bool decode(const std::string& bytes, RangeGrid& g) {
  const io::internal::PlyHeader h = io::internal::parsePlyHeader("t.ply", bytes);
  g.cols = 12, g.rows = 9;
  return io::internal::decodePlainRangeGrid(h, bytes, g);
}

std::string errorOf(const std::string& bytes) {
  try {
    io::parseRangeGridPly("t.ply", bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PlainRangeGrid, DecodesWhatTheGeneralReaderReads) {
  for (const bool doubles : {false, true})
    for (const bool signedIndex : {false, true}) {
      Layout little{false, doubles, signedIndex, false}, big = little;
      big.bigEndian = true;  // big-endian bodies take the general reader
      RangeGrid fast, ignored;
      ASSERT_TRUE(decode(gridBytes(little), fast));
      ASSERT_FALSE(decode(gridBytes(big), ignored));
      const RangeGrid general = io::parseRangeGridPly("t.ply", gridBytes(big));
      ASSERT_EQ(fast.points.size(), 72u);
      EXPECT_EQ(fast.points, general.points);
      EXPECT_EQ(fast.cell, general.cell);
      EXPECT_EQ(fast.cell[4], 2);
      EXPECT_EQ(fast.cell[6], -1);
      const RangeGrid read = io::parseRangeGridPly("t.ply", gridBytes(little));
      EXPECT_EQ(read.points, general.points);
      EXPECT_EQ(read.cell, general.cell);
    }
}

TEST(PlainRangeGrid, LeavesOtherLayoutsToTheGeneralReader) {
  RangeGrid g;
  EXPECT_FALSE(decode(gridBytes({false, false, true, true}), g));  // int16 z
  std::string withFaces = gridBytes({});
  withFaces.insert(withFaces.find("end_header"), "element face 0\nproperty list uchar int vi\n");
  EXPECT_FALSE(decode(withFaces, g));
  EXPECT_TRUE(g.points.empty() && g.cell.empty());
  EXPECT_EQ(io::parseRangeGridPly("t.ply", withFaces).points.size(), 72u);
}

// A body the general reader refuses is left to it, so that both readers refuse with its message.
TEST(PlainRangeGrid, LeavesBadBodiesToTheGeneralReader) {
  const std::string good = gridBytes({});
  const size_t cells = good.size() - (108 + 72 * 4);
  std::string twoIndices = good, outOfRange = good;
  twoIndices[cells + 1] = 2;         // cell #1 lists 2 indices
  outOfRange[cells + 2 + 3] = 0x7f;  // cell #1's index: huge
  const std::vector<std::pair<std::string, std::string>> cases = {
      {gridBytes({}, [](int i, Eigen::Vector3d& p) { p.y() = i == 5 ? NAN : p.y(); }), "NaN"},
      {twoIndices, "0 or 1"},
      {outOfRange, "out of range"},
      {good + "x", "bytes after the last element"},
      {good.substr(0, good.size() - 2), "truncated"}};
  for (const auto& [bytes, message] : cases) {
    RangeGrid g;
    EXPECT_FALSE(decode(bytes, g)) << message;
    EXPECT_TRUE(g.points.empty() && g.cell.empty()) << message;
    EXPECT_NE(errorOf(bytes).find(message), std::string::npos) << errorOf(bytes);
  }
}
