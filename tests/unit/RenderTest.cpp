#include <gtest/gtest.h>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/render/Render.h"

using namespace rangefuse;

namespace {

const Eigen::Vector3d kCentre(16.3, 15.8, 16.1);
const double kRadius = 9.0;
const Colour kOrange(0.85f, 0.35f, 0.15f), kBlue(0.15f, 0.45f, 0.80f);

/// An analytic sphere field, observed within 3 voxels of the surface; with `painted`, its
/// voxels are orange for x below the centre and blue above.
SparseField sphereField(bool painted = false) {
  VoxelGrid grid;
  grid.brick = 8;
  SparseField f(grid, 0);
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        std::vector<VoxelSums> sums(512);
        std::vector<VoxelColour> colours(painted ? 512 : 0);
        bool any = false;
        for (int i = 0; i < 512; ++i) {
          const Eigen::Vector3d p(8 * x + i % 8, 8 * y + (i / 8) % 8, 8 * z + i / 64);
          const double d = (p - kCentre).norm() - kRadius;
          if (std::abs(d) > 3) continue;
          const Eigen::Vector3d n = (p - kCentre).normalized();
          sums[i] = VoxelSums{float(d), 1, {float(n.x()), float(n.y()), float(n.z())}};
          if (painted) colours[i].add(p.x() < kCentre.x() ? kOrange : kBlue, 1, 0);
          any = true;
        }
        if (any) f.addBrick(mortonEncode({x, y, z}), std::move(sums), std::move(colours));
      }
  return f;
}

bool isBackground(const Image& img, int x, int y) {
  const uint8_t* p = &img.rgb[(size_t(y) * img.width + x) * 3];
  return p[0] == kBackground[0] && p[1] == kBackground[1] && p[2] == kBackground[2];
}

}  // namespace

TEST(Png, WriteThenReadGivesSamePixels) {
  test::TempDir dir;
  Image img(7, 5, 0);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) img.set(x, y, uint8_t(30 * x), uint8_t(50 * y), 200);
  io::writePng(dir.file("a.png"), img);
  const Image back = io::readPng(dir.file("a.png"));
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, img.rgb);
  EXPECT_THROW(io::readPng(dir.write("b.png", "not a png")), InputError);
}

TEST(RenderField, SphereSilhouetteAndShading) {
  const SparseField f = sphereField();
  ViewSettings view;
  view.elevationDeg = 0;
  view.width = view.height = 200;
  const Image img = renderField(f, view);
  EXPECT_EQ(img.width, 200);
  EXPECT_FALSE(isBackground(img, 100, 100));
  EXPECT_TRUE(isBackground(img, 2, 2));
  // Facing the camera at the centre: full headlight shading.
  EXPECT_GT(img.rgb[(100 * 200 + 100) * 3], 225);
  // The view frames the surface: the silhouette's row through the centre spans most of the
  // picture, and its area is that of a disc of that width.
  int left = 200, right = -1;
  size_t covered = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      if (!isBackground(img, x, y)) {
        ++covered;
        if (y == 100) left = std::min(left, x), right = std::max(right, x);
      }
  const double across = right - left + 1;
  EXPECT_GT(across, 0.85 * 200);
  EXPECT_LT(across, 0.97 * 200);
  EXPECT_NEAR(covered / (M_PI / 4 * across * across), 1.0, 0.03);
}

TEST(RenderField, AColouredFieldIsShownInItsColours) {
  // A pixel shows the voxel colour times its shade: orange left of the centre, blue right of
  // it, on a sphere seen from +z (compared as hues: each scaled by its largest channel).
  const SparseField f = sphereField(true);
  ViewSettings view;
  view.elevationDeg = 0;
  view.width = view.height = 200;
  const Image img = renderField(f, view);
  auto pixel = [&](int x, int y) -> Colour {
    const uint8_t* p = &img.rgb[(size_t(y) * img.width + x) * 3];
    const Colour c(p[0], p[1], p[2]);
    return c / c.maxCoeff();
  };
  auto hue = [](const Colour& c) -> Colour { return c / c.maxCoeff(); };
  EXPECT_LT((pixel(90, 100) - hue(kOrange)).cwiseAbs().maxCoeff(), 0.03f) << pixel(90, 100);
  EXPECT_LT((pixel(110, 100) - hue(kBlue)).cwiseAbs().maxCoeff(), 0.03f) << pixel(110, 100);
  // Without colour, the same view keeps its warm grey.
  const Image grey = renderField(sphereField(), view);
  const uint8_t* g = &grey.rgb[(100 * 200 + 90) * 3];
  EXPECT_GT(g[0], g[2]);
  EXPECT_GT(g[2], 180);
}

TEST(RenderSlice, SurfaceDarkUnobservedBlue) {
  const SparseField f = sphereField();
  const Image img = renderSlice(f, 2, kCentre.z());
  ASSERT_GT(img.width, 10);
  // The centre of the sphere is beyond the band: unobserved, blue.
  const int cx = img.width / 2, cy = img.height / 2;
  const uint8_t* p = &img.rgb[(size_t(cy) * img.width + cx) * 3];
  EXPECT_LT(p[0], p[2]);
  size_t dark = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3)
    dark += img.rgb[i] < 40 && img.rgb[i] == img.rgb[i + 2];
  EXPECT_GT(dark, 20u);  // the zero crossing
}

TEST(RenderOptions, BadViewAndSliceAreRefused) {
  ViewSettings v;
  EXPECT_NO_THROW(parseView("30,-10", v));
  EXPECT_EQ(v.azimuthDeg, 30);
  EXPECT_EQ(v.elevationDeg, -10);
  EXPECT_THROW(parseView("30", v), InputError);
  EXPECT_THROW(parseView("a,b", v), InputError);
  int axis;
  double value;
  EXPECT_NO_THROW(parseSlice("y=0.25", axis, value));
  EXPECT_EQ(axis, 1);
  EXPECT_EQ(value, 0.25);
  EXPECT_THROW(parseSlice("w=1", axis, value), InputError);
  EXPECT_THROW(parseSlice("z=", axis, value), InputError);
}

TEST(ViewAxes, AZUpOrbitKeepsZUpInThePicture) {
  // Known answers: azimuth 0, elevation 30 looks from -y (z up) or from +z (y up), tilted
  // up by 30 degrees, with the up axis pointing up the picture.
  ViewSettings v;
  v.azimuthDeg = 0, v.elevationDeg = 30;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  const Eigen::Matrix3d yUp = viewAxes(v);
  EXPECT_LT((yUp.row(2).transpose() - Eigen::Vector3d(0, s, c)).norm(), 1e-12);
  EXPECT_GT(yUp(1, 1), 0.8);
  v.up = 'z';
  const Eigen::Matrix3d zUp = viewAxes(v);
  EXPECT_LT((zUp.row(2).transpose() - Eigen::Vector3d(0, -c, s)).norm(), 1e-12);
  EXPECT_LT((zUp.row(1).transpose() - Eigen::Vector3d(0, s, c)).norm(), 1e-12);
  EXPECT_LT((zUp.row(0).transpose() - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_NEAR(zUp.determinant(), 1, 1e-12);
  // Azimuth turns about +z: 90 degrees looks from +x.
  v.azimuthDeg = 90;
  EXPECT_LT((viewAxes(v).row(2).transpose() - Eigen::Vector3d(c, 0, s)).norm(), 1e-12);
  EXPECT_EQ(upAxis("auto", true), 'z');
  EXPECT_EQ(upAxis("auto", false), 'y');
  EXPECT_EQ(upAxis("y", true), 'y');
  EXPECT_THROW(upAxis("x", false), InputError);
}
