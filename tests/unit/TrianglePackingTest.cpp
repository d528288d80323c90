// Routing packs a part's triangles as 16-bit steps below the next new vertex (decision 54):
// against the triangles given, in first-use numbering (6 bytes a triangle) and in any other,
// whose corners far from the next new vertex take 32 bits more.
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

/// Corners whose step below the next new vertex does not fit 16 bits, counted one by one.
size_t escapes(const std::vector<Triangle>& t) {
  size_t n = 0;
  int64_t next = 0;
  for (const Triangle& tri : t)
    for (const int32_t v : tri) {
      n += !(next - v >= 0 && next - v < 0xffff);
      next = std::max(next, int64_t(v) + 1);
    }
  return n;
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

TEST(TrianglePacking, FirstUseNumberingTakesSixBytesATriangle) {
  // A depth camera's rows: the row above is 640 vertices back.
  const std::vector<Triangle> t = gridTriangles(40, 640);
  std::mt19937 random(3);
  std::vector<uint32_t> pick;
  for (uint32_t k = 0; k < t.size(); ++k)
    if (random() % 4 != 0) pick.push_back(k);  // a part: some of the triangles
  ScanSurface s;
  s.triangles = t;
  s.points.resize(40 * 640);
  std::vector<int32_t> remap(s.points.size(), -1);
  usedVertices(s, pick, remap);
  const std::vector<Triangle> expected = renumbered(t, pick, remap);
  ASSERT_EQ(escapes(expected), 0u);
  EXPECT_EQ(packedBytes(t, pick, remap, expected), kHead + 6 * pick.size());
}

TEST(TrianglePacking, AnyNumberingComesBackExactly) {
  const std::vector<Triangle> t = gridTriangles(30, 30);
  std::vector<uint32_t> all(t.size());
  std::iota(all.begin(), all.end(), 0u);
  std::mt19937 random(4);
  std::uniform_int_distribution<int32_t> anyCorner(0, INT32_MAX);
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<int32_t> remap(900);
    // Shuffled numbers, then some far beyond: steps forward, back and past 16 bits.
    std::iota(remap.begin(), remap.end(), 0);
    std::shuffle(remap.begin(), remap.end(), random);
    for (int k = 0; k < 40 * trial; ++k) remap[random() % 900] = anyCorner(random);
    remap[5] = INT32_MAX;
    remap[7] = 0;
    const std::vector<Triangle> expected = renumbered(t, all, remap);
    const size_t far = escapes(expected);
    EXPECT_GT(far, 0u);
    EXPECT_EQ(packedBytes(t, all, remap, expected), kHead + 6 * all.size() + 4 * far);
  }
}

TEST(TrianglePacking, NoTrianglesPackAsTheHeadAlone) {
  EXPECT_EQ(packedBytes(gridTriangles(3, 3), {}, std::vector<int32_t>(9, -1), {}), kHead);
}
