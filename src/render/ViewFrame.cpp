#include <algorithm>
#include <cmath>

#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

/// How much wider than its extent a picture is: a thin margin all round.
constexpr double kMargin = 1.06;

}  // namespace

Eigen::Matrix3d viewAxes(const ViewSettings& view) {
  const double az = view.azimuthDeg * M_PI / 180, el = view.elevationDeg * M_PI / 180;
  const Eigen::Vector3d toCamera(std::cos(el) * std::sin(az), std::sin(el),
                                 std::cos(el) * std::cos(az));
  // Looking straight down or up, +y cannot be up: +z takes its place.
  const Eigen::Vector3d worldUp =
      std::abs(toCamera.y()) > 0.99 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d right = worldUp.cross(toCamera).normalized();
  Eigen::Matrix3d axes;
  axes.row(0) = right;
  axes.row(1) = toCamera.cross(right);
  axes.row(2) = toCamera;
  if (view.up == 'y') return axes;
  // The same view of a z-up world: the quarter turn about x that takes +y to +z.
  Eigen::Matrix3d yToZ;
  yToZ << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  return axes * yToZ.transpose();
}

ViewFrame::ViewFrame(const ViewSettings& view, const Eigen::AlignedBox3d& framed)
    : axes(viewAxes(view)), extent(framed), width(view.width), height(view.height) {
  const Eigen::Vector3d size =
      extent.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Ones()) : Eigen::Vector3d(extent.sizes());
  pixel = kMargin * std::max(size.x() / width, size.y() / height);
  // A flat or point-like extent still needs a finite pixel.
  if (!(pixel > 0)) pixel = std::max(size.maxCoeff(), 1e-9) / std::min(width, height);
}

Eigen::Vector3d ViewFrame::project(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = axes * p, c = extent.center();
  return {0.5 * width + (q.x() - c.x()) / pixel, 0.5 * height - (q.y() - c.y()) / pixel,
          extent.max().z() - q.z()};
}

Eigen::Vector3d ViewFrame::rayOrigin(double x, double y, double ahead) const {
  const Eigen::Vector3d c = extent.center();
  const Eigen::Vector3d q(c.x() + (x - 0.5 * width) * pixel, c.y() - (y - 0.5 * height) * pixel,
                          extent.max().z() + ahead);
  return axes.transpose() * q;
}

}  // namespace rangefuse
