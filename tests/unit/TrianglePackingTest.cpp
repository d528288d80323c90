// Routing packs a part's triangles as steps below the next new vertex in one or two bytes
// (decisions 54, 58): against the triangles given, in first-use numbering and in any other,
// whose corners far from the next new vertex take 32 bits and a byte; sizes against a count
// corner by corner.
#include <gtest/gtest.h>

#include <numeric>
#include <random>

#include "../common/PackedRoundTrip.h"
#include "route/PartPacking.h"
#include "route/TrianglePacking.h"

using namespace rangefuse;
using namespace rangefuse::internal;

namespace {

constexpr size_t kHead = 2 * sizeof(uint64_t);

/// Two triangles a cell of a rows x cols grid of vertices.
std::vector<Triangle> gridTriangles(int rows, int cols) {
  std::vector<Triangle> t;
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const int32_t a = r * cols + c, b = a + 1, d = a + cols, e = d + 1;
      t.push_back({a, d, b});
      t.push_back({b, d, e});
    }
  return t;
}

/// The picked triangles renumbered by remap, as unpacking must give them.
std::vector<Triangle> renumbered(const std::vector<Triangle>& t, const std::vector<uint32_t>& pick,
                                 const std::vector<int32_t>& remap) {
  std::vector<Triangle> out;
  for (uint32_t k : pick) out.push_back({remap[t[k][0]], remap[t[k][1]], remap[t[k][2]]});
  return out;
}

/// The bytes the steps of `t` take, counted corner by corner: 1 below 240, 2 below 4080, 5
/// otherwise; `far` counts the last.
size_t stepBytes(const std::vector<Triangle>& t, size_t* far = nullptr) {
  size_t bytes = 0, escaped = 0;
  int64_t next = 0;
  for (const Triangle& tri : t)
    for (const int32_t v : tri) {
      const int64_t step = next - v;
      const size_t b = step >= 0 && step < 240 ? 1 : step >= 0 && step < 4080 ? 2 : 5;
      bytes += b, escaped += b == 5;
      next = std::max(next, int64_t(v) + 1);
    }
  if (far) *far = escaped;
  return bytes;
}

/// Packs after a marker; unpacking gives `expected`, and skipping lands where unpacking did.
size_t packedBytes(const std::vector<Triangle>& t, const std::vector<uint32_t>& pick,
                   const std::vector<int32_t>& remap, const std::vector<Triangle>& expected) {
  std::vector<char> buf(3, 'x');
  packTriangles(buf, t, pick, remap);
  EXPECT_EQ(test::unpackedFrom<Triangle>(buf, 3, unpackTriangles, skipTriangles), expected);
  return buf.size() - 3;
}

}  // namespace

TEST(TrianglePacking, FirstUseNumberingTakesThreeToFiveBytesATriangle) {
  // A depth camera's rows, 640 vertices (two bytes back to the row above) and 213 (merged 3 x 3:
  // one byte).
  for (const auto& [cols, most] : {std::pair{640, 5.0}, std::pair{213, 3.5}}) {
    const std::vector<Triangle> t = gridTriangles(40, cols);
    std::mt19937 random(3);
    std::vector<uint32_t> pick;
    for (uint32_t k = 0; k < t.size(); ++k)
      if (random() % 4 != 0) pick.push_back(k);  // a part: some of the triangles
    ScanSurface s;
    s.triangles = t;
    s.points.resize(40 * size_t(cols));
    std::vector<int32_t> remap(s.points.size(), -1);
    usedVertices(s, pick, remap);
    const std::vector<Triangle> expected = renumbered(t, pick, remap);
    size_t far = 0;
    const size_t steps = stepBytes(expected, &far);
    ASSERT_EQ(far, 0u);
    EXPECT_EQ(packedBytes(t, pick, remap, expected), kHead + steps) << cols;
    EXPECT_LE(double(steps) / double(pick.size()), most) << cols;
  }
}

TEST(TrianglePacking, AnyNumberingComesBackExactly) {
  const std::vector<Triangle> t = gridTriangles(30, 30);
  std::vector<uint32_t> all(t.size());
  std::iota(all.begin(), all.end(), 0u);
  std::mt19937 random(4);
  std::uniform_int_distribution<int32_t> anyCorner(0, INT32_MAX);
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<int32_t> remap(900);
    // Shuffled numbers, then some far beyond: steps forward, back and past two bytes.
    std::iota(remap.begin(), remap.end(), 0);
    std::shuffle(remap.begin(), remap.end(), random);
    for (int k = 0; k < 40 * trial; ++k) remap[random() % 900] = anyCorner(random);
    remap[5] = INT32_MAX;
    remap[7] = 0;
    const std::vector<Triangle> expected = renumbered(t, all, remap);
    size_t far = 0;
    const size_t steps = stepBytes(expected, &far);
    EXPECT_GT(far, 0u);
    EXPECT_EQ(packedBytes(t, all, remap, expected), kHead + steps);
  }
}

TEST(TrianglePacking, NoTrianglesPackAsTheHeadAlone) {
  EXPECT_EQ(packedBytes(gridTriangles(3, 3), {}, std::vector<int32_t>(9, -1), {}), kHead);
}
