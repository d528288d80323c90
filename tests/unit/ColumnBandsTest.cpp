// A station read in bands of columns gives the triangles and normals of the station read whole,
// and the rules every band shares, taken from a sample of columns, are the whole grid's.
#include <gtest/gtest.h>

#include <map>

#include "rangefuse/scan/Shapes.h"
#include "rangefuse/scan/SyntheticScanner.h"
#include "rangefuse/surface/ColumnBands.h"
#include "rangefuse/surface/GridMerging.h"

using namespace rangefuse;

namespace {

/// A station in the synthetic room, in its own frame: a full turn of 480 x 200 cells.
RangeGrid station() {
  ScanSettings s;
  s.views = 1, s.width = 480, s.height = 200, s.voxel = 0.05, s.noise = 0.3;
  s.path = ViewPath::Stations;
  return scanMesh(makeRoom(), s).scans.front().grid;
}

/// Columns [first, first + count) of g.
RangeGrid columnsOf(const RangeGrid& g, int first, int count) {
  RangeGrid out = g;
  out.cols = count;
  out.points.clear();
  out.cell.assign(static_cast<size_t>(count) * g.rows, -1);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < count; ++c)
      if (const int32_t k = g.at(r, first + c); k >= 0) {
        out.cell[static_cast<size_t>(r) * count + c] = static_cast<int32_t>(out.points.size());
        out.points.push_back(g.points[k]);
      }
  return out;
}

ColumnReader readerOf(const RangeGrid& g) {
  return [&g](int first, int count) { return columnsOf(g, first, count); };
}

using Corner = std::array<double, 3>;
using Face = std::array<Corner, 3>;

Corner corner(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

/// Each triangle by its corners (first corner the least, winding kept), with a count.
std::map<Face, int> facesOf(const std::vector<ScanSurface>& parts) {
  std::map<Face, int> faces;
  for (const ScanSurface& s : parts)
    for (const Triangle& t : s.triangles) {
      Face f = {corner(s.points[t[0]]), corner(s.points[t[1]]), corner(s.points[t[2]])};
      while (!(f[0] <= f[1] && f[0] <= f[2])) f = {f[1], f[2], f[0]};
      ++faces[f];
    }
  return faces;
}

std::map<Corner, Eigen::Vector3d> normalsOf(const std::vector<ScanSurface>& parts) {
  std::map<Corner, Eigen::Vector3d> normals;
  for (const ScanSurface& s : parts)
    for (size_t v = 0; v < s.points.size(); ++v) normals[corner(s.points[v])] = s.normals[v];
  return normals;
}

/// The grid's surface read whole (one band) against read in `bands` bands.
void expectBandsMakeTheWhole(const RangeGrid& g, const SurfaceOptions& o, int bands) {
  const ColumnReader read = readerOf(g);
  const BandRules rules = bandRules(read, g.cols, g.rows, o);
  const std::vector<ScanSurface> whole = {buildBandSurface(read, rules, 0, 1, o)};
  std::vector<ScanSurface> parts;
  for (int b = 0; b < bands; ++b) parts.push_back(buildBandSurface(read, rules, b, bands, o));
  const std::map<Face, int> a = facesOf(whole), b = facesOf(parts);
  EXPECT_GT(a.size(), 10000u);
  EXPECT_TRUE(a == b) << a.size() << " triangles whole, " << b.size() << " in bands";
  const auto na = normalsOf(whole), nb = normalsOf(parts);
  ASSERT_EQ(na.size(), nb.size());
  double worst = 0;
  for (const auto& [p, n] : na) worst = std::max(worst, (n - nb.at(p)).norm());
  EXPECT_LT(worst, 1e-12);  // the same neighbours, summed in another order
  for (const ScanSurface& s : parts)
    for (size_t v = 0; v < s.points.size(); ++v)
      EXPECT_NEAR(s.confidence[v], std::max(0.0, s.normals[v].dot(-s.points[v].normalized())),
                  1e-12);
}

}  // namespace

TEST(ColumnBands, ScansAreSplitOnlyPastTheCellLimitAndNeverIntoNarrowBands) {
  EXPECT_EQ(bandCount(4000, 2000, 0), 1);
  EXPECT_EQ(bandCount(4000, 2000, 8000000), 1);
  EXPECT_EQ(bandCount(4000, 2000, 7999999), 2);
  EXPECT_EQ(bandCount(4000, 2000, 1000000), 8);
  EXPECT_EQ(bandCount(4000, 2000, 1000), 4000 / kMinBandColumns);
  EXPECT_EQ(bandCount(200, 100000, 1000), 1);  // too few columns to split
}

TEST(ColumnBands, TheSampledRulesAreTheWholeGridsOwn) {
  const RangeGrid g = station();
  for (const double perCell : {0.0, 2.5}) {
    SurfaceOptions o;
    const double lateral = lateralSpacing(g);
    o.mergeTarget = perCell * lateral;
    const BandRules rules = bandRules(readerOf(g), g.cols, g.rows, o);
    const int k = o.mergeTarget > 0 ? mergeFactor(lateral, o.mergeTarget, g.rows) : 1;
    EXPECT_EQ(rules.k, k);
    const RangeGrid merged = mergeCells(g, k, gridSpacing(g), o.maxEdgeFactor);
    GridTriangulation whole = gridTriangulation(merged, o);  // buildScanSurface's rules
    whole.maxEdge = mergedEdgeLimit(gridSpacing(merged), gridSpacing(g), k, o.maxEdgeFactor);
    EXPECT_TRUE(rules.triangulation.wraps);
    EXPECT_EQ(rules.triangulation.wraps, whole.wraps);
    EXPECT_EQ(rules.triangulation.forward, whole.forward);
    EXPECT_NEAR(rules.step, gridSpacing(g), 0.05 * gridSpacing(g));
    EXPECT_NEAR(rules.triangulation.maxEdge, whole.maxEdge, 0.05 * whole.maxEdge);
    EXPECT_NEAR(rules.angular, k * angularSpacing(g), 0.05 * k * angularSpacing(g));
  }
  // Part of a turn does not close.
  const RangeGrid part = columnsOf(g, 0, 300);
  EXPECT_FALSE(bandRules(readerOf(part), part.cols, part.rows, {}).triangulation.wraps);
}

TEST(ColumnBands, BandsTogetherAreTheWholeStationAtFullResolution) {
  expectBandsMakeTheWhole(station(), {}, 3);
}

TEST(ColumnBands, BandsTogetherAreTheWholeStationMergedInBlocks) {
  const RangeGrid g = station();
  SurfaceOptions o;
  o.mergeTarget = 2.5 * lateralSpacing(g);  // blocks of 2 x 2, and 480 / 2 columns in 4 bands
  expectBandsMakeTheWhole(g, o, 4);
}

TEST(ColumnBands, BandsOfPartOfATurnLeaveTheEndsOpen) {
  const RangeGrid g = columnsOf(station(), 40, 401);  // an odd count: a narrow last block
  SurfaceOptions o;
  o.mergeTarget = 3.5 * lateralSpacing(g);
  expectBandsMakeTheWhole(g, o, 3);
}
