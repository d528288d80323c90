// Colour fused beside the distance: the running mean against the weighted mean computed at
// once, a uniform patch that keeps its colour exactly, a two-colour edge that stays sharp, and
// the same bits on any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/surface/ScanSurface.h"

using namespace rangefuse;

namespace {

constexpr float kStep = 1.0f / 65535;  // one unit of the 16-bit mean

/// checkedPlane's colour of cell (col, row).
Colour planeColour(int col, int row) {
  return Colour(col < 101 ? 0.9f : 0.1f, float(col % 7) / 7, float(row % 5) / 5);
}

/// A flat patch at height z, 0.5 apart, coloured by `colourAt(x)`.
template <class ColourAt>
PrismScan patch(double z, ColourAt colourAt) {
  RangeGrid g;
  g.cols = 40, g.rows = 30;
  g.colourKind = ColourKind::rgb;
  for (int y = 0; y < g.rows; ++y)
    for (int x = 0; x < g.cols; ++x) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(x * 0.5, y * 0.5, z);
      g.colours.push_back(colourAt(x * 0.5));
    }
  PrismScan s;
  s.surface = buildScanSurface(g, Pose{}, SurfaceOptions{});
  s.limits = computePrismLimits(s.surface, 1.5);
  return s;
}

/// The store of one rank holding every brick the scans reach, with colour, the scans added.
BrickStore fused(const std::vector<PrismScan>& scans, int threads) {
  BrickStore store(planBricks(scans, fitGrid(scans, 0.5, 4, 1.5), 1), 0);
  store.enableColour(ColourKind::rgb);
  PrismIntegrator integrator(store, threads);
  for (const PrismScan& s : scans) integrator.addScan(s);
  return store;
}

}  // namespace

TEST(VoxelColour, RunningMeanIsTheWeightedMean) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0, 1), weight(0.1f, 2);
  VoxelColour c;
  float w = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int n = 0; n < 200; ++n) {
    const Colour sample(unit(rng), unit(rng), unit(rng));
    const float wi = weight(rng);
    c.add(sample, wi, w);
    w += wi;
    sum += wi * sample.cast<double>();
    // Each update rounds to the nearest unit: the error stays within a few units.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.value()[k], sum[k] / w, 8 * kStep) << n;
  }
}

TEST(ColourField, UniformPatchKeepsItsColour) {
  const Colour green(0.2f, 0.6f, 0.4f);
  const std::vector<PrismScan> scans{patch(10, [&](double) { return green; }),
                                     patch(10.2, [&](double) { return green; })};
  const BrickStore store = fused(scans, 1);
  size_t seen = 0;
  for (size_t i = 0; i < store.sums().size(); ++i) {
    if (!(store.sums()[i].w > 0)) continue;
    ++seen;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(store.colours()[i].value()[k], green[k], kStep);
  }
  EXPECT_GT(seen, 1000u);
}

TEST(ColourField, TwoColourEdgeStaysWithinAVoxel) {
  // Red for x < 10, blue beyond; voxels 0.5 wide, samples 0.5 apart. A voxel takes the colour
  // at the foot of its nearest prism, interpolated across that triangle: only voxels within a
  // grid step of x = 10 may mix the two.
  const Colour red(1, 0, 0), blue(0, 0, 1);
  auto edge = [&](double x) { return x < 10 ? red : blue; };
  const std::vector<PrismScan> scans{patch(10, edge)};
  const BrickStore store = fused(scans, 1);
  const VoxelGrid& grid = store.grid();
  size_t pure = 0;
  for (size_t b = 0; b < store.brickCount(); ++b) {
    const BrickCoord brick = mortonDecode(store.code(b));
    const int B = grid.brick;
    for (int z = 0; z < B; ++z)
      for (int y = 0; y < B; ++y)
        for (int x = 0; x < B; ++x) {
          const VoxelIndex v = brick * B + VoxelIndex(x, y, z);
          const size_t at = store.offset(b, brick, v);
          if (!(store.sums()[at].w > 0)) continue;
          const Colour c = store.colours()[at].value();
          const double cx = grid.centre(v).x();
          if (c.isApprox(red, 1e-4) || c.isApprox(blue, 1e-4)) {
            ++pure;
            EXPECT_TRUE(c.isApprox(edge(cx), 1e-4) || std::abs(cx - 10) <= 0.5) << cx;
          } else {
            EXPECT_LE(std::abs(cx - 10), 0.5 + 1e-9) << "a mixed colour at x = " << cx;
          }
        }
  }
  EXPECT_GT(pure, 1000u);
}

TEST(ColourField, AnEdgeSeenByManyNoisyFramesStaysInPlaceAndSharp) {
  // A plane painted red for x < 10.1 and blue beyond (off the lattice), seen by 24 frames with
  // depth noise of half a voxel, each sampling it at its own offset (voxels 0.5, samples 0.5
  // apart), each sample coloured by the true surface it saw. Along every row the fused colour
  // at the surface (interpolated to the zero crossing) must step at the true edge to within
  // half a voxel, and keep at least 0.6 of the step across the voxel pair that straddles it.
  const Colour red(1, 0, 0), blue(0, 0, 1);
  const double edgeAt = 10.1, voxel = 0.5;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.5 * voxel);
  std::uniform_real_distribution<double> offset(0, 0.5);
  std::vector<PrismScan> scans;
  for (int frame = 0; frame < 24; ++frame) {
    RangeGrid g;
    g.cols = 40, g.rows = 30;
    g.colourKind = ColourKind::rgb;
    const double ox = offset(rng), oy = offset(rng);
    for (int y = 0; y < g.rows; ++y)
      for (int x = 0; x < g.cols; ++x) {
        const double px = x * 0.5 + ox, py = y * 0.5 + oy;
        g.cell.push_back(static_cast<int32_t>(g.points.size()));
        g.points.emplace_back(px, py, 10 + noise(rng));
        g.colours.push_back(px < edgeAt ? red : blue);
      }
    PrismScan s;
    s.surface = buildScanSurface(g, Pose{}, SurfaceOptions{});
    s.limits = computePrismLimits(s.surface, 1.5);
    scans.push_back(std::move(s));
  }
  const BrickStore store = fused(scans, 1);
  const VoxelGrid& grid = store.grid();
  // The red channel at the surface of the voxel column (x, y): the zero crossing along z.
  auto surfaceRed = [&](const VoxelIndex& column, double& red) {
    for (VoxelIndex v = column; v.z() < column.z() + 8; ++v.z()) {
      VoxelIndex above = v;
      ++above.z();
      const int64_t a = store.localBrick(mortonEncode(brickOf(v, grid.brick)));
      const int64_t b = store.localBrick(mortonEncode(brickOf(above, grid.brick)));
      if (a < 0 || b < 0) continue;
      const size_t i = store.offset(size_t(a), v), j = store.offset(size_t(b), above);
      const VoxelSums &lo = store.sums()[i], &hi = store.sums()[j];
      if (!(lo.w > 0 && hi.w > 0)) continue;
      const double dLo = lo.wd / lo.w, dHi = hi.wd / hi.w;
      if ((dLo < 0) == (dHi < 0)) continue;
      const double t = dLo / (dLo - dHi);
      red = (1 - t) * store.colours()[i].value()[0] + t * store.colours()[j].value()[0];
      return true;
    }
    return false;
  };
  const VoxelIndex first = grid.nearest(Eigen::Vector3d(edgeAt, 0, 10 - 2 * voxel));
  double placeError = 0, contrast = 0;
  int rows = 0;
  for (double y = 4; y < 10; y += voxel) {
    VoxelIndex left = grid.nearest(Eigen::Vector3d(edgeAt - 2 * voxel, y, 0));
    left.z() = first.z();
    // Columns from two voxels left of the edge to two right: where red falls through 0.5.
    double previous = 0, previousX = 0;
    bool found = false;
    for (VoxelIndex c = left; c.x() <= left.x() + 4; ++c.x()) {
      double r;
      ASSERT_TRUE(surfaceRed(c, r)) << "no surface at column " << c.transpose();
      const double x = grid.centre(c).x();
      if (c.x() > left.x() && previous >= 0.5 && r < 0.5 && !found) {
        placeError += std::abs(previousX + (previous - 0.5) / (previous - r) * voxel - edgeAt);
        found = true;
      }
      if (x - voxel < edgeAt && x > edgeAt) contrast += previous - r;  // the straddling pair
      previous = r, previousX = x;
    }
    ASSERT_TRUE(found) << "no step in the row at y = " << y;
    ++rows;
  }
  EXPECT_LE(placeError / rows, 0.5 * voxel);
  EXPECT_GE(contrast / rows, 0.6);
}

TEST(ColourField, ThreadsGiveTheSameColourBits) {
  auto stripes = [](double x) {
    return Colour(0.5f + 0.5f * static_cast<float>(std::sin(x)), 0.3f, 0.1f);
  };
  std::vector<PrismScan> scans;
  for (double z : {10.0, 10.3, 9.8}) scans.push_back(patch(z, stripes));
  for (auto& p : scans[2].surface.points) p.z() += 0.05 * p.x();
  const BrickStore one = fused(scans, 1);
  for (int threads : {3, 8}) {
    const BrickStore many = fused(scans, threads);
    ASSERT_EQ(one.colours().size(), many.colours().size());
    for (size_t i = 0; i < one.colours().size(); ++i)
      for (int k = 0; k < 3; ++k) ASSERT_EQ(one.colours()[i].c[k], many.colours()[i].c[k]) << i;
  }
}

namespace {

/// A fine grid 0.1 apart on a plane, coloured cell by cell with an edge at column 101.
RangeGrid checkedPlane() {
  RangeGrid g;
  g.cols = 200, g.rows = 160;
  g.colourKind = ColourKind::rgb;
  for (int y = 0; y < g.rows; ++y)
    for (int x = 0; x < g.cols; ++x) {
      g.cell.push_back(static_cast<int32_t>(g.points.size()));
      g.points.emplace_back(x * 0.1, y * 0.1, 10);
      g.colours.push_back(planeColour(x, y));
    }
  return g;
}

/// Checks, at random points of the triangles `which` accepts, that the colour is the original
/// cell's nearest that point (brute force: by its coordinates), not the blend of the corners.
/// Returns how many points were checked.
template <class Which>
size_t expectNearestCell(const ScanSurface& s, Which which) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  size_t checked = 0;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const Triangle& tri = s.triangles[t];
    if (!which(tri)) continue;
    for (int n = 0; n < 4; ++n) {
      double a = unit(rng), b = unit(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Eigen::Vector3d bary(1 - a - b, a, b);
      const Eigen::Vector3d p =
          bary[0] * s.points[tri[0]] + bary[1] * s.points[tri[1]] + bary[2] * s.points[tri[2]];
      const double col = p.x() / 0.1, row = p.y() / 0.1;
      // Halfway between two cells either may answer.
      if (std::abs(col - std::round(col) - 0.5) < 1e-6 ||
          std::abs(row - std::round(row) - 0.5) < 1e-6)
        continue;
      const Colour want =
          colourOf(texelOf(planeColour(int(std::lround(col)), int(std::lround(row)))));
      EXPECT_TRUE(surfaceColour(s, tri, bary).isApprox(want, 1e-6))
          << "at " << col << ", " << row << ": " << surfaceColour(s, tri, bary).transpose()
          << " want " << want.transpose();
      if (::testing::Test::HasFailure()) return checked;
      ++checked;
    }
  }
  return checked;
}

/// Whether a triangle of `s` spans more than one block: a joined flat block's.
bool spansTwoBlocks(const ScanSurface& s, const Triangle& t) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j)
      for (int a = 0; a < 2; ++a)
        if (std::abs(s.blocks[t[i]][a] - s.blocks[t[j]][a]) > 1) return true;
  return false;
}

}  // namespace

TEST(SurfaceColour, MergedCellsShowTheOriginalCellNearestTheFoot) {
  // Merged into blocks of k x k: anywhere in a merged triangle the colour is the nearest
  // original cell's.
  const RangeGrid g = checkedPlane();
  SurfaceOptions options;
  options.mergeTarget = 0.5;
  const ScanSurface s = buildScanSurface(g, Pose{}, options);
  const int k = s.texelSide;
  ASSERT_GT(k, 1);
  ASSERT_EQ(g.cols % k, 0);
  ASSERT_EQ(g.rows % k, 0);
  EXPECT_EQ(s.texels.rows(), g.rows);
  EXPECT_EQ(s.texels.cells.size(), size_t(g.rows) * g.cols);
  ASSERT_EQ(s.blocks.size(), s.points.size());
  EXPECT_GT(expectNearestCell(s, [](const Triangle&) { return true; }), 1000u);
}

TEST(SurfaceColour, JoinedFlatBlocksShowTheOriginalCellNearestTheFoot) {
  // Joined flat blocks span two cells, merged or not: their feet still take the nearest
  // original cell's colour, also from the blocks between their corners.
  const RangeGrid g = checkedPlane();
  for (double merge : {0.0, 0.5}) {
    SurfaceOptions options;
    options.mergeTarget = merge;
    options.flatTolerance = 0.01;
    const ScanSurface s = buildScanSurface(g, Pose{}, options);
    ASSERT_FALSE(s.texels.empty()) << merge;
    size_t joined = 0;
    for (const Triangle& t : s.triangles) joined += spansTwoBlocks(s, t);
    EXPECT_GT(joined, s.triangles.size() / 2) << merge;
    const size_t checked =
        expectNearestCell(s, [&](const Triangle& t) { return spansTwoBlocks(s, t); });
    EXPECT_GT(checked, 1000u) << merge;
  }
}

TEST(SurfaceColour, UnmergedCellsBlendTheirCorners) {
  // Cells neither merged nor joined interpolate their corners' colours: the texels are only
  // for triangles that span more than a cell.
  const RangeGrid g = checkedPlane();
  SurfaceOptions options;
  options.flatTolerance = 0.01;
  const ScanSurface s = buildScanSurface(g, Pose{}, options);
  size_t checked = 0;
  for (const Triangle& t : s.triangles) {
    if (spansTwoBlocks(s, t)) continue;
    const Eigen::Vector3d bary(0.2, 0.3, 0.5);
    const Colour want = 0.2f * s.colours[t[0]] + 0.3f * s.colours[t[1]] + 0.5f * s.colours[t[2]];
    ASSERT_TRUE(surfaceColour(s, t, bary).isApprox(want, 1e-6));
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}
