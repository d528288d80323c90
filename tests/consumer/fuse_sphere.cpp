// Six depth cameras around a sphere, fused through the installed library; the mesh must lie on
// the sphere. Exit code 0 when it does. Run alone or under mpirun: the same mesh either way.
#include <rangefuse/rangefuse.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

namespace {

constexpr double kRadius = 0.5, kDistance = 2.0, kVoxel = 0.01;
constexpr int kSize = 120;

/// Depth counts (mm) of the sphere at the origin seen from `eye` looking at it.
rangefuse::io::DepthImage sphereDepth(const rangefuse::io::DepthCamera& k,
                                      const rangefuse::Pose& cameraToWorld) {
  rangefuse::io::DepthImage image{kSize, kSize, std::vector<uint16_t>(kSize * kSize, 0)};
  const Eigen::Vector3d eye = cameraToWorld.t;
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1);  // camera depth 1
      const Eigen::Vector3d d = cameraToWorld.R * ray;
      // |eye + s d| = r: the nearer root is the depth along the camera's axis.
      const double a = d.squaredNorm(), b = 2 * eye.dot(d),
                   c = eye.squaredNorm() - kRadius * kRadius;
      const double disc = b * b - 4 * a * c;
      if (disc < 0) continue;
      const double s = (-b - std::sqrt(disc)) / (2 * a);
      image.counts[v * kSize + u] = static_cast<uint16_t>(std::lround(s * 1000));
    }
  return image;
}

/// A camera at `eye` looking at the origin (OpenCV axes: z forward, y down).
rangefuse::Pose lookingAtTheOrigin(const Eigen::Vector3d& eye) {
  const Eigen::Vector3d z = -eye.normalized();
  const Eigen::Vector3d up =
      std::abs(z.y()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = up.cross(z).normalized(), y = z.cross(x);
  rangefuse::Pose p;
  p.R.col(0) = x, p.R.col(1) = y, p.R.col(2) = z;
  p.t = eye;
  return p;
}

int run() {
  rangefuse::FieldSettings field;
  field.voxel = kVoxel;
  int started = 0;
  MPI_Initialized(&started);
  if (!started) MPI_Init(nullptr, nullptr);
  rangefuse::Fusion fusion(field, MPI_COMM_WORLD);
  const rangefuse::io::DepthCamera camera{150, 150, 59.5, 59.5, kSize, kSize, 1e-3, 0};
  const Eigen::Vector3d eyes[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (const Eigen::Vector3d& e : eyes) {
    const rangefuse::Pose pose = lookingAtTheOrigin(kDistance * e);
    fusion.addDepth(sphereDepth(camera, pose), camera, pose);
  }
  int failed = 0;
  try {  // the library's exceptions reach the caller as its own type
    rangefuse::Pose bad = lookingAtTheOrigin(kDistance * eyes[0]);
    bad.t.x() = NAN;
    fusion.addDepth(sphereDepth(camera, lookingAtTheOrigin(kDistance * eyes[0])), camera, bad);
    failed = 1;
  } catch (const rangefuse::InputError& e) {
    if (std::string(e.what()) != "frame_6: the pose is not finite") failed = 1;
  }
  const rangefuse::TriangleMesh mesh = fusion.mesh();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    double worst = 0;
    for (const Eigen::Vector3d& p : mesh.vertices)
      worst = std::max(worst, std::abs(p.norm() - kRadius));
    std::printf("rangefuse %s: %zu vertices, %zu faces, farthest %.4f from the sphere\n",
                rangefuse::libraryVersion(), mesh.vertices.size(), mesh.faces.size(), worst);
    failed |= mesh.faces.size() < 1000 || !(worst < kVoxel);
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}

}  // namespace

int main() {
  try {
    return run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuse_sphere: %s\n", e.what());
    return 1;
  }
}
