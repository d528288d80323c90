#include "PreviewView.h"

#include <algorithm>
#include <cmath>

#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

/// A camera (x right, y down, looking along +z) at a station, level in the station's frame
/// (z up) and turned toward `target`, or along the station's x axis when right above it.
Pose stationCamera(const Pose& station, const Eigen::Vector3d& target) {
  Eigen::Vector3d ahead = station.R.transpose() * (target - station.t);
  ahead.z() = 0;
  ahead = ahead.norm() > 1e-12 ? ahead.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), right = ahead.cross(up);
  Eigen::Matrix3d inStation;
  inStation << right, -up, ahead;
  return Pose{station.R * inStation, station.t};
}

/// The farthest corner of `box` from `p`.
double farthestCorner(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  double far = 0;
  for (int k = 0; k < 8; ++k)
    far = std::max(far, (box.corner(Eigen::AlignedBox3d::CornerType(k)) - p).norm());
  return far;
}

}  // namespace

ViewSettings previewView(const std::string& view, const std::string& up, const LoadedScans& scans,
                         const MeshPart& mesh, MPI_Comm comm) {
  ViewSettings v;
  const io::SensorKind kind =
      scans.paths.empty() ? io::SensorKind::grid : io::sensorKindOf(scans.paths[0]);
  if (!view.empty()) {
    parseView(view, v);
    v.up = upAxis(up, kind == io::SensorKind::station);
    return v;
  }
  if (kind == io::SensorKind::grid) return v;
  Eigen::AlignedBox3d mine;
  for (const Eigen::Vector3d& p : mesh.mesh.vertices) mine.extend(p);
  const Eigen::AlignedBox3d box = mpi::unitedBox(mine, comm);
  if (box.isEmpty()) return v;
  const Pose& first = scans.poses[0];
  v.camera =
      kind == io::SensorKind::station ? stationCamera(first, box.center()) : io::cameraPose(first);
  v.width = 640, v.height = 480;
  // Stations see all round: a 90-degree view; depth cameras about 60 degrees.
  const double halfAngle = (kind == io::SensorKind::station ? 45 : 30) * M_PI / 180;
  v.focal = 0.5 * v.width / std::tan(halfAngle);
  v.farthest = farthestCorner(box, v.camera->t);
  return v;
}

}  // namespace rangefuse::internal
