#include <gtest/gtest.h>

#include "SphereField.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/render/Render.h"

using namespace rangefuse;
using namespace rangefuse::test;

namespace {

/// The picture one rank draws from the whole field.
Image serialPicture(const ViewSettings& view) {
  const BrickLayout layout = sphereLayout(1);
  BrickStore store(layout, 0);
  fillSphere(store);
  return renderField(SparseField::gather(store, 0, 0, MPI_COMM_SELF), view);
}

size_t shadedPixels(const Image& img) {
  size_t n = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3) n += img.rgb[i] != 255;
  return n;
}

}  // namespace

TEST(DistributedRender, SamePixelsAsTheGatheredFieldFromEveryView) {
  const BrickLayout layout = sphereLayout(mpi::size());
  BrickStore store(layout, mpi::rank());
  fillSphere(store);
  for (const auto& [az, el] : {std::pair{0.0, 20.0}, {135.0, -40.0}, {250.0, 85.0}}) {
    ViewSettings view;
    view.azimuthDeg = az;
    view.elevationDeg = el;
    view.width = 96;
    view.height = 80;
    const Image composite = renderDistributed(store, 0, view, 0, MPI_COMM_WORLD);
    if (mpi::rank() != 0) continue;
    const Image one = serialPicture(view);
    EXPECT_EQ(composite.rgb, one.rgb) << "view " << az << "," << el;
    // The view frames the bricks' bounding sphere (radius R) in 2R of height: the sphere's
    // silhouette covers pi r^2 of the picture's (2R)^2 aspect.
    const double R = 0.5 * brickBounds(layout.grid, layout.codes).diagonal().norm();
    const double aspect = double(view.width) / view.height;
    const double expected = M_PI * kRadius * kRadius / (4 * R * R * aspect);
    EXPECT_NEAR(double(shadedPixels(one)) / (view.width * view.height), expected, 0.1 * expected);
  }
}
