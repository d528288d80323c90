#include <gtest/gtest.h>

#include <cmath>

#include "rangefuse/robust/SightMap.h"
#include "rangefuse/robust/SpaceCarving.h"
#include "rangefuse/robust/SurfaceHypotheses.h"

namespace rangefuse {
namespace {

/// A pinhole grid seeing the plane z = -10 except in the pixels with c >= holeFrom.
RangeGrid planeGrid(int holeFrom) {
  RangeGrid g;
  g.cols = 40, g.rows = 30;
  g.pinhole = Pinhole{20, 20, 19.5, 14.5};
  g.cell.assign(g.cols * g.rows, -1);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < holeFrom; ++c) {
      const double x = (c - 19.5) / 20, y = (r - 14.5) / 20;
      g.cell[r * g.cols + c] = static_cast<int32_t>(g.points.size());
      g.points.emplace_back(10 * x, 10 * y, -10);
    }
  return g;
}

TEST(SightMap, PinholeClearanceIsTheDepthInFrontOfThePlane) {
  for (int k : {1, 2}) {
    SightMap m = SightMap::fromPinholeGrid(planeGrid(40), k);
    Pose pose;
    pose.t = Eigen::Vector3d(5, -3, 2);  // placed: queries are in the world
    m.place(pose);
    const Eigen::Vector3d ray(0.1, -0.05, -1);
    EXPECT_NEAR(m.clearance(pose.t + 4 * ray), 6, 1e-5);
    EXPECT_NEAR(m.clearance(pose.t + 12 * ray), -2, 1e-5);
    EXPECT_TRUE(std::isnan(m.clearance(pose.t + 4 * Eigen::Vector3d(3, 0, -1))));  // off frame
    EXPECT_TRUE(std::isnan(m.clearance(pose.t + Eigen::Vector3d(0, 0, 4))));       // behind
  }
}

TEST(SightMap, ABoxItCannotCoverAnswersNaNEverywhere) {
  // Brute force: random boxes around a placed pinhole map and an orthographic one; where
  // mayCover says no, every sampled point of the box answers NaN, and boxes of each kind occur.
  SightMap pinhole = SightMap::fromPinholeGrid(planeGrid(40), 2);
  Pose pose;
  pose.t = Eigen::Vector3d(1, 2, 3);
  pinhole.place(pose);
  ScanSurface square;  // [0, 10]^2 at z = 2, seen from +z
  square.points = {{0, 0, 2}, {10, 0, 2}, {10, 10, 2}, {0, 10, 2}};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  const SightMap ortho = SightMap::fromSurface(square, 0.5);
  std::srand(7);
  auto uniform = [](double lo, double hi) { return lo + (hi - lo) * std::rand() / RAND_MAX; };
  for (const SightMap* m : std::vector<const SightMap*>{&pinhole, &ortho}) {
    int covered = 0, apart = 0;
    for (int b = 0; b < 400; ++b) {
      const Eigen::Vector3d c(uniform(-20, 20), uniform(-20, 20), uniform(-25, 15));
      const Eigen::Vector3d half(uniform(0.1, 3), uniform(0.1, 3), uniform(0.1, 3));
      const Eigen::AlignedBox3d box(c - half, c + half);
      if (m->mayCover(box)) {
        ++covered;
        continue;
      }
      ++apart;
      for (int s = 0; s < 200; ++s) {
        const Eigen::Vector3d p(uniform(box.min().x(), box.max().x()),
                                uniform(box.min().y(), box.max().y()),
                                uniform(box.min().z(), box.max().z()));
        ASSERT_TRUE(std::isnan(m->clearance(p))) << "box " << b;
      }
    }
    EXPECT_GT(covered, 20);
    EXPECT_GT(apart, 20);
  }
}

TEST(SightMap, NoReturnSawThroughEverything) {
  const SightMap m = SightMap::fromPinholeGrid(planeGrid(20), 1);
  EXPECT_EQ(m.clearance(Eigen::Vector3d(0.25 * 5, 0, -5)), INFINITY);    // column 24: no return
  EXPECT_NEAR(m.clearance(Eigen::Vector3d(-0.25 * 5, 0, -5)), 5, 1e-5);  // column 14: plane
  // Beside the edge of what was seen the nearest return counts: no free-space claim.
  EXPECT_LT(m.clearance(Eigen::Vector3d(0.0125 * 5, 0, -5)), 6);
}

/// planeGrid's map as a depth camera's frame.
SightMap depthCameraMap(const RangeGrid& grid, int k) {
  return SightMap::fromPinholeGrid(grid, k, SightMap::NoReturn::DepthCamera);
}

TEST(SightMap, ADepthCamerasEmptyPixelsSayNothingBeyondItsReach) {
  // The plane at depth 10 is the farthest the frame measured: its empty half is empty space
  // in front of that depth and unknown beyond it (the camera may not reach so far).
  for (int k : {1, 2}) {
    const SightMap m = depthCameraMap(planeGrid(20), k);
    EXPECT_EQ(m.clearance(Eigen::Vector3d(0.4 * 8, 0, -8)), INFINITY);  // column 27.5
    EXPECT_TRUE(std::isnan(m.clearance(Eigen::Vector3d(0.4 * 12, 0, -12))));
    EXPECT_NEAR(m.clearance(Eigen::Vector3d(-0.25 * 5, 0, -5)), 5, 1e-5);  // column 14
  }
}

TEST(SightMap, ADepthCamerasDropoutInsideWhatItSawSaysNothing) {
  // A hole of 6 x 6 pixels in the plane (a dark patch): its rays may well have met the plane.
  // Opened to the frame's top border, the same hole is a view past what the frame saw.
  RangeGrid g = planeGrid(40);
  for (int r = 12; r < 18; ++r)
    for (int c = 17; c < 23; ++c) g.cell[r * g.cols + c] = -1;
  const Eigen::Vector3d centre(0, 0, -5);
  EXPECT_TRUE(std::isnan(depthCameraMap(g, 1).clearance(centre)));
  EXPECT_EQ(SightMap::fromPinholeGrid(g, 1).clearance(centre), INFINITY);  // a scanner's
  for (int r = 0; r < 12; ++r)
    for (int c = 19; c < 21; ++c) g.cell[r * g.cols + c] = -1;
  EXPECT_EQ(depthCameraMap(g, 1).clearance(centre), INFINITY);
}

TEST(SightMap, ADepthCamerasBlindBandSaysNothing) {
  // The last 2 of 40 columns without a return beside a full column: the camera's blind band
  // (a sixteenth of the side at most). Half the frame empty is a view into empty space (above).
  for (int k : {1, 2}) {
    const SightMap band = depthCameraMap(planeGrid(38), k);
    EXPECT_TRUE(std::isnan(band.clearance(Eigen::Vector3d(0.925 * 5, 0, -5))));  // column 38
    EXPECT_NEAR(band.clearance(Eigen::Vector3d(0.6 * 5, 0, -5)), 5, 1e-5);       // column 31
  }
}

TEST(SightMap, OrthographicSurfaceAndUnknownOutsideIt) {
  ScanSurface s;  // the square [0, 10]^2 at z = 2, seen from +z
  s.points = {{0, 0, 2}, {10, 0, 2}, {10, 10, 2}, {0, 10, 2}};
  s.triangles = {{0, 1, 2}, {0, 2, 3}};
  const SightMap m = SightMap::fromSurface(s, 0.5);
  EXPECT_NEAR(m.clearance(Eigen::Vector3d(5, 5, 6)), 4, 1e-6);
  EXPECT_NEAR(m.clearance(Eigen::Vector3d(3, 7, 1)), -1, 1e-6);
  EXPECT_TRUE(std::isnan(m.clearance(Eigen::Vector3d(20, 5, 6))));
}

TEST(SpaceCarving, InsideTakesTwoThirdsOfTheScansHidingAPointAndNoneLookingThrough) {
  // Maps of the plane z = -10 seen from the origin; "away" maps are the same scan moved 1000
  // aside, which know nothing of the points asked.
  const SightMap plane = SightMap::fromPinholeGrid(planeGrid(40), 1);
  SightMap away = plane;
  Pose aside;
  aside.t = Eigen::Vector3d(1000, 0, 0);
  away.place(aside);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, -1, -13), Eigen::Vector3d(1, 1, -3));
  const std::vector<Eigen::Vector3d> points = {{0, 0, -12}, {0, 0, -5}, {0, 0, -9.5}};
  auto inside = [&](int hiding, int unknowing) {
    std::vector<SightMap> maps(hiding, plane);
    maps.insert(maps.end(), unknowing, away);
    return SpaceCarving(maps, 1).inside(box, points);
  };
  // Behind the plane: inside with 3 of 3 and 4 of 6 (two thirds); not with 3 of 6.
  EXPECT_EQ(inside(3, 0), (std::vector<uint8_t>{1, 0, 0}));
  EXPECT_EQ(inside(4, 2), (std::vector<uint8_t>{1, 0, 0}));
  EXPECT_EQ(inside(3, 3), (std::vector<uint8_t>{0, 0, 0}));
  // One scan that looked through the point settles it, however many hid it.
  SightMap deeper = SightMap::fromPinholeGrid(planeGrid(40), 1);
  Pose back;
  back.t = Eigen::Vector3d(0, 0, -5);  // sees its plane at z = -15: looked through z = -12
  deeper.place(back);
  std::vector<SightMap> maps(5, plane);
  maps.push_back(deeper);
  EXPECT_EQ(SpaceCarving(maps, 1).inside(box, points)[0], 0);
}

TEST(SightMap, AnOrthographicGridKnowsWhereItsScannerGotNoReturn) {
  // A 0.5-spaced orthographic grid of 41 x 41 cells over [0, 20]^2 seeing z = 2 where x < 10:
  // given the grid, the cells of its frame with no return saw nothing; without it, or off the
  // frame, nothing is known there. A point with no triangle still counts as a return.
  RangeGrid g;
  g.cols = g.rows = 41;
  g.cell.assign(41 * 41, -1);
  for (int r = 0; r < 41; ++r)
    for (int c = 0; c < 41; ++c)
      if (c < 20 || (r == 30 && c == 30)) {
        g.cell[r * 41 + c] = static_cast<int32_t>(g.points.size());
        g.points.emplace_back(0.5 * c, 0.5 * r, 2);
      }
  ScanSurface s;
  for (int r = 0; r < 41; ++r)
    for (int c = 0; c < 20; ++c) s.points.emplace_back(0.5 * c, 0.5 * r, 2);
  for (int r = 0; r + 1 < 41; ++r)
    for (int c = 0; c + 1 < 20; ++c) {
      const int32_t a = r * 20 + c;
      s.triangles.push_back({a, a + 1, a + 20});
      s.triangles.push_back({a + 1, a + 21, a + 20});
    }
  const SightMap framed = SightMap::fromSurface(s, 0.5, &g), bare = SightMap::fromSurface(s, 0.5);
  EXPECT_NEAR(framed.clearance(Eigen::Vector3d(4, 10, 5)), 3, 1e-6);  // the plane
  EXPECT_EQ(framed.clearance(Eigen::Vector3d(16, 5, 5)), INFINITY);   // no return there
  EXPECT_TRUE(std::isnan(bare.clearance(Eigen::Vector3d(16, 5, 5))));
  EXPECT_TRUE(std::isnan(framed.clearance(Eigen::Vector3d(30, 5, 5))));  // off the frame
  EXPECT_FALSE(framed.clearance(Eigen::Vector3d(15, 15, 5)) == INFINITY)
      << "beside the lone return at (15, 15)";
  EXPECT_TRUE(framed.lookedThrough(Eigen::Vector3d(16, 5, -50), 1));
}

/// A station's view of the sphere of radius 5 about it: 2-degree steps of azimuth and
/// elevation up to 80 degrees, as a scan-frame surface.
ScanSurface stationSphere() {
  ScanSurface s;
  const double step = 2 * M_PI / 180;
  const int cols = 180, rows = 81;  // azimuth -179..179 (no column on the seam), elevation +-80
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double az = -M_PI + (c + 0.5) * step, el = (r - 40) * step;
      s.points.push_back(5 * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                             std::cos(el) * std::sin(az), std::sin(el)));
    }
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const int a = r * cols + c;
      s.triangles.push_back({a, a + 1, a + cols});
      s.triangles.push_back({a + 1, a + cols + 1, a + cols});
    }
  return s;
}

TEST(SightMap, StationClearanceIsTheRangeInFrontOfWhatItSaw) {
  SightMap m = SightMap::fromStation(stationSphere(), 2 * M_PI / 180);
  Pose pose;
  pose.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  pose.t = Eigen::Vector3d(10, 20, 1);
  m.place(pose);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(1, 0.3, 0.2), Eigen::Vector3d(-1, -0.5, -0.6),
                                     Eigen::Vector3d(0.1, 1, 0.9), Eigen::Vector3d(-0.3, 0.2, 0)}) {
    const Eigen::Vector3d u = pose.R * dir.normalized();  // a line of sight, in the world
    EXPECT_NEAR(m.clearance(pose.t + 3 * u), 2, 1e-5) << dir.transpose();
    EXPECT_NEAR(m.clearance(pose.t + 7 * u), -2, 1e-5) << dir.transpose();
  }
  // Straight up, past the scan's 80 degrees of elevation: nothing known.
  EXPECT_TRUE(std::isnan(m.clearance(pose.t + 3 * (pose.R * Eigen::Vector3d::UnitZ()))));
}

TEST(SightMap, TheMapsOfAStationsHalvesJoinIntoTheMapOfTheWhole) {
  // The halves of a station read in bands: the triangles east of the station and the others.
  const ScanSurface whole = stationSphere();
  ScanSurface east = whole, west = whole;
  east.triangles.clear(), west.triangles.clear();
  for (const Triangle& t : whole.triangles)
    (whole.points[t[0]].x() > 0 ? east : west).triangles.push_back(t);
  ASSERT_FALSE(east.triangles.empty());
  ASSERT_FALSE(west.triangles.empty());
  const double angle = 2 * M_PI / 180;
  const SightMap all = SightMap::fromStation(whole, angle);
  SightMap joined;  // empty: takes the first part whole
  joined.join(SightMap::fromStation(east, angle));
  joined.join(SightMap::fromStation(west, angle));
  std::vector<char> a, b, half;
  all.pack(a);
  joined.pack(b);
  EXPECT_TRUE(a == b);
  // A half's map keeps its own azimuths only: about half the whole raster is sent.
  SightMap::fromStation(east, angle).pack(half);
  EXPECT_LT(half.size(), 0.6 * a.size());
  // Either half alone knows nothing of the other side, nor of the strip along their border.
  const SightMap eastOnly = SightMap::fromStation(east, angle);
  EXPECT_TRUE(std::isnan(eastOnly.clearance(Eigen::Vector3d(-3, 0.1, 0.2))));
  EXPECT_TRUE(std::isnan(eastOnly.clearance(Eigen::Vector3d(0, 3, 0.2))));
  EXPECT_NEAR(joined.clearance(Eigen::Vector3d(0, 3, 0.2)),
              all.clearance(Eigen::Vector3d(0, 3, 0.2)), 0);
  EXPECT_THROW(joined.join(SightMap::fromStation(east, 2 * angle)), std::logic_error);
}

TEST(SightMap, PackUnpackRoundTrip) {
  SightMap m = SightMap::fromPinholeGrid(planeGrid(30), 2);
  Pose pose;
  pose.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  m.place(pose);
  std::vector<char> bytes;
  m.pack(bytes);
  size_t pos = 0;
  const SightMap back = SightMap::unpack(bytes, pos);
  EXPECT_EQ(pos, bytes.size());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1, 0, -4), Eigen::Vector3d(-2, 1, -7)})
    EXPECT_EQ(back.clearance(pose.apply(p)), m.clearance(pose.apply(p)));
  SightMap camera = depthCameraMap(planeGrid(30), 2);  // its reach travels with it
  camera.place(pose);
  bytes.clear(), pos = 0;
  camera.pack(bytes);
  const SightMap cameraBack = SightMap::unpack(bytes, pos);
  EXPECT_EQ(cameraBack.clearance(pose.apply(Eigen::Vector3d(5.6, 0, -8))), INFINITY);
  EXPECT_TRUE(std::isnan(cameraBack.clearance(pose.apply(Eigen::Vector3d(7.7, 0, -11)))));
  SightMap station = SightMap::fromStation(stationSphere(), 0.05);
  station.place(pose);
  bytes.clear(), pos = 0;
  station.pack(bytes);
  const SightMap stationBack = SightMap::unpack(bytes, pos);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1, 0, -4), Eigen::Vector3d(-2, 1, 3)}) {
    EXPECT_EQ(stationBack.clearance(pose.apply(p)), station.clearance(pose.apply(p)));
    EXPECT_TRUE(std::isfinite(station.clearance(pose.apply(p))));
  }
}

/// One brick of 2^3 voxels at the origin, voxel 1: centres are their indices.
BrickStore tinyStore() {
  BrickLayout layout;
  layout.grid.voxel = 1, layout.grid.brick = 2;
  layout.codes = {mortonEncode(BrickCoord(0, 0, 0))};
  layout.work = {1};
  layout.setRuns({0, 1});
  return BrickStore(layout, 0);
}

/// Voxel 0 (centre 0): three images agree, summed as the prism field sums them, and one image
/// saw an opposite surface at z = -1.5. Voxel 1 (centre (1, 0, 0)): one image, at z = -0.3.
/// Voxel 3: a sample without weight.
void addSamples(SurfaceHypotheses& h, VoxelSums& agreed) {
  const float up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  for (float d : {0.25f, 0.5f, 0.75f}) {
    h.add(0, d, 0.5f, up);
    agreed.wd += 0.5f * d, agreed.w += 0.5f, agreed.wf[2] += 0.5f * up[2], agreed.images += 1;
  }
  h.add(0, -1.5f, 0.9f, down);
  h.add(1, 0.3f, 0.8f, up);
  h.add(3, 0.3f, 0.0f, up);
}

TEST(SurfaceHypotheses, AgreementStandsAndALoneSurfaceGoesOnlyWhereSomeoneLookedThrough) {
  const HypothesisParams params{2, 0.7, 2, 3};
  VoxelSums agreed;
  BrickStore alone = tinyStore();  // no other image: everything stands
  SurfaceHypotheses h(alone, params);
  addSamples(h, agreed);
  EXPECT_GT(h.extraBytes(), 0u) << "voxel 0 holds two hypotheses";
  HypothesisStats s = h.resolve({});
  EXPECT_EQ(s.agreed, 1u);
  EXPECT_EQ(s.unopposed, 1u);
  EXPECT_EQ(s.removed, 0u);
  EXPECT_EQ(alone.sums()[0].wd, agreed.wd + 0.9f * -1.5f);
  EXPECT_EQ(alone.sums()[0].images, 4);
  EXPECT_EQ(alone.sums()[3].images, 0);

  // A sensor 5 above, looking down at its plane 10 away (z = -5): it looked 3.5 past the lone
  // surface of voxel 0 and 4.7 past voxel 1's, more than the margin of 3.
  SightMap sight = SightMap::fromPinholeGrid(planeGrid(40), 1);
  Pose above;
  above.t = Eigen::Vector3d(0, 0, 5);
  sight.place(above);
  BrickStore seen = tinyStore();
  SurfaceHypotheses g(seen, params);
  agreed = VoxelSums{};
  addSamples(g, agreed);
  s = g.resolve({sight});
  EXPECT_EQ(s.agreed, 1u);
  EXPECT_EQ(s.removed, 1u);
  EXPECT_EQ(seen.sums()[0].wd, agreed.wd);
  EXPECT_EQ(seen.sums()[0].w, agreed.w);
  EXPECT_EQ(seen.sums()[0].images, 3);
  EXPECT_EQ(seen.sums()[1].images, 0) << "removed: the sums are cleared";
}

TEST(SurfaceHypotheses, AnAgreedGhostGoesWhenAsManyImagesLookedThroughItAsSawIt) {
  // Voxel 0: `seen` images agree on a surface at z = -0.5. Each map is a camera 5 above
  // looking down at its plane at z = -5: it looked 4.5 past the surface, more than the margin.
  const HypothesisParams params{2, 0.7, 2, 3};
  const float up[3] = {0, 0, 1};
  SightMap sight = SightMap::fromPinholeGrid(planeGrid(40), 1);
  Pose above;
  above.t = Eigen::Vector3d(0, 0, 5);
  sight.place(above);
  auto standsWith = [&](int seen, int lookers) {
    BrickStore store = tinyStore();
    SurfaceHypotheses h(store, params);
    for (int i = 0; i < seen; ++i) h.add(0, 0.5f, 1, up);
    h.resolve(std::vector<SightMap>(lookers, sight));
    return store.sums()[0].images > 0;
  };
  EXPECT_TRUE(standsWith(3, 2));
  EXPECT_FALSE(standsWith(3, 3));
  EXPECT_FALSE(standsWith(1, 1));  // one view's word, looked through once
  EXPECT_TRUE(standsWith(1, 0));
  // Agreed on by kVoteViews images: it stands on agreement alone, whatever saw past it.
  EXPECT_TRUE(standsWith(SurfaceHypotheses::kVoteViews, SurfaceHypotheses::kVoteViews + 4));
}

TEST(SurfaceHypotheses, NoisySamplesAgreeWithinThreeOfTheirDeviations) {
  // Two images 3 apart on a surface: two hypotheses of one image each when their noise is
  // small against sameDistance (2), one of two images when each is 1.2 noisy (3.6 > 3).
  const HypothesisParams params{2, 0.7, 2, 3};
  const float up[3] = {0, 0, 1};
  for (float sigma : {0.0f, 0.5f, 1.2f}) {
    BrickStore store = tinyStore();
    SurfaceHypotheses h(store, params);
    h.add(0, -1.5f, 1, up, sigma);
    h.add(0, 1.5f, 1, up, sigma);
    const HypothesisStats s = h.resolve({});
    EXPECT_EQ(s.agreed, sigma > 1 ? 1u : 0u) << sigma;
    EXPECT_EQ(h.extraBytes() > 0, sigma < 1) << sigma;
  }
}

}  // namespace
}  // namespace rangefuse

namespace rangefuse {
namespace {

/// The scene of addSamples with colours: the agreeing images see orange, the lone opposite
/// surface of voxel 0 is magenta.
void addColouredSamples(SurfaceHypotheses& h, const Colour& orange, const Colour& magenta) {
  const float up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  for (float d : {0.25f, 0.5f, 0.75f}) h.add(0, d, 0.5f, up, 0, &orange);
  h.add(0, -1.5f, 0.9f, down, 0, &magenta);
  h.add(1, 0.3f, 0.8f, up, 0, &magenta);
}

TEST(SurfaceHypotheses, AVoxelKeepsTheColourOfTheHypothesesThatStand) {
  const HypothesisParams params{2, 0.7, 2, 3};
  const Colour orange(0.85f, 0.35f, 0.15f), magenta(0.9f, 0.1f, 0.9f);
  // Every surface stands: voxel 0's colour is the weighted mean of both.
  BrickStore alone = tinyStore();
  alone.enableColour(ColourKind::rgb);
  SurfaceHypotheses h(alone, params);
  addColouredSamples(h, orange, magenta);
  h.resolve({});
  const Colour mean = (1.5f * orange + 0.9f * magenta) / 2.4f;
  EXPECT_LT((alone.colours()[0].value() - mean).cwiseAbs().maxCoeff(), 2e-5f);
  EXPECT_LT((alone.colours()[1].value() - magenta).cwiseAbs().maxCoeff(), 1e-5f);

  // A sensor looked through the lone surfaces: voxel 0 is orange to the last bit, as if the
  // magenta sample had never come, and voxel 1's colour goes with its sums.
  SightMap sight = SightMap::fromPinholeGrid(planeGrid(40), 1);
  Pose above;
  above.t = Eigen::Vector3d(0, 0, 5);
  sight.place(above);
  BrickStore seen = tinyStore();
  seen.enableColour(ColourKind::rgb);
  SurfaceHypotheses g(seen, params);
  addColouredSamples(g, orange, magenta);
  g.resolve({sight});
  VoxelColour want;
  for (float before : {0.0f, 0.5f, 1.0f}) want.add(orange, 0.5f, before);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(seen.colours()[0].c[k], want.c[k]);
    EXPECT_EQ(seen.colours()[1].c[k], 0);
  }
}

}  // namespace
}  // namespace rangefuse
