#include "rangefuse/scan/SyntheticScanner.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "rangefuse/core/Error.h"
#include "rangefuse/scan/Bvh.h"

namespace rangefuse {
namespace {

constexpr double kDistance = 3.0;  // camera distance, in bounding radii

void validate(const TriangleMesh& mesh, const ScanSettings& s) {
  if (mesh.faces.empty()) throw InputError("scan: the mesh has no triangles");
  if (s.views < 1) throw InputError("scan: --views must be at least 1");
  if (s.width < 2 || s.height < 2)
    throw InputError("scan: --width and --height must be at least 2");
  if (!(s.voxel > 0)) throw InputError("scan: --voxel must be positive");
  if (s.noise < 0) throw InputError("scan: --noise must not be negative");
  if (!(s.disparityBaseline >= 0))
    throw InputError("scan: --disparity-baseline must not be negative");
  if (s.outliers < 0 || s.outliers > 1) throw InputError("scan: --outliers must be in [0, 1]");
  if (s.patches < 0 || s.patches > s.views)
    throw InputError("scan: --patches must be between 0 and the number of views");
  if (s.rotDeg < 0 || s.transVox < 0)
    throw InputError("scan: --rot-deg and --trans-vox must not be negative");
  if (s.fovDeg < 0 || s.fovDeg >= 180) throw InputError("scan: --fov must be in (0, 180) degrees");
  if (s.sensor.active() && (s.noise > 0 || s.outliers > 0 || s.disparityBaseline > 0))
    throw InputError(
        "scan: --sensor models the camera's noise itself: leave out --noise, --outliers and "
        "--disparity");
  if (s.sensor.active() && s.path == ViewPath::Stations)
    throw InputError("scan: --sensor is a depth camera's: give camera views, not --path stations");
  if (s.path == ViewPath::Stations && s.patches > 0)
    throw InputError("scan: --patches needs camera views (--path sphere or orbit), not stations");
}

/// Camera looking at `target` from `eye`: columns x, y, z with the sensor looking along -z, x
/// level (z up) unless the view is steeper than `steepest` (|z.z| above it: y up instead).
Pose cameraPose(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, double steepest = 0.9) {
  const Eigen::Vector3d z = (eye - target).normalized();
  Eigen::Vector3d up =
      std::abs(z.z()) < steepest ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = up.cross(z).normalized(), y = z.cross(x);
  Pose p;
  p.R.col(0) = x;
  p.R.col(1) = y;
  p.R.col(2) = z;
  p.t = eye;
  return p;
}

Eigen::Vector3d fibonacciDirection(int i, int n) {
  const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z);
  const double phi = i * M_PI * (3 - std::sqrt(5.0));
  return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
}

/// Stations spread on a ring at the middle of the scene, a third of the way to its walls, each
/// turned a little from the last (a survey placing its tripods through a room).
Eigen::Vector3d stationPosition(int i, int n, const Eigen::AlignedBox3d& box) {
  const double a = 2 * M_PI * i / n + 0.3;
  const Eigen::Vector3d half = 0.5 * box.sizes();
  return box.center() +
         Eigen::Vector3d(0.3 * half.x() * std::cos(a), 0.3 * half.y() * std::sin(a), 0);
}

/// Unit ray of a station's cell: columns a full turn of azimuth, rows from 80 degrees below the
/// horizon to 80 above.
Eigen::Vector3d stationRay(const RangeGrid& g, int r, int c) {
  const double az = 2 * M_PI * c / g.cols, el = (-80 + 160.0 * r / (g.rows - 1)) * M_PI / 180;
  return Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

Eigen::Vector3d pinholeRay(const RangeGrid& g, double r, double c) {
  return Eigen::Vector3d((c - g.pinhole->cx) / g.pinhole->fx, (r - g.pinhole->cy) / g.pinhole->fy,
                         -1)
      .normalized();
}

/// One turn around the object, 15-45 degrees above its equator: consecutive frames overlap
/// as in a hand-held sequence.
Eigen::Vector3d orbitDirection(double i, int n) {
  const double phi = 2 * M_PI * i / n, elevation = (30 + 15 * std::sin(3 * phi)) * M_PI / 180;
  return Eigen::Vector3d(std::cos(elevation) * std::cos(phi), std::cos(elevation) * std::sin(phi),
                         std::sin(elevation));
}

/// A hand-held camera around the object at time i (frames): one turn at 0.75-0.95 of the
/// orbit's distance, rising and falling, aimed at a point that sways by up to `sway` bounding
/// radii (0.8: about 15 degrees of turn) with periods of 40-60 frames divided by `pace`.
Pose handheldPose(double i, int n, const Eigen::Vector3d& centre, double radius, double distance,
                  double sway = 0.8, double pace = 1) {
  const double phi = 2 * M_PI * i / n, a = 2 * M_PI * i * pace;
  const double reach = distance * (0.85 + 0.1 * std::sin(2.3 * phi));
  const Eigen::Vector3d eye = centre + reach * orbitDirection(i, n);
  const Eigen::Vector3d aim(std::sin(a / 43), std::cos(a / 59), 0.5 * std::sin(a / 37));
  // Level up to nearly straight down: a hand-held camera does not roll a quarter turn in a frame.
  return cameraPose(eye, centre + sway * radius * aim, 0.999);
}

/// A camera carried inside the scene along a loop a third of the way to its walls, at half its
/// height, aimed across the room at a point that wanders around its middle (what a person
/// scanning a room looks at), so each view holds more than a wall and the floor.
Pose walkPose(double i, int n, const Eigen::AlignedBox3d& box) {
  const double phi = 2 * M_PI * i / n;
  const Eigen::Vector3d half = 0.5 * box.sizes(), c = box.center();
  const Eigen::Vector3d eye(c.x() + 0.33 * half.x() * std::cos(phi),
                            c.y() + 0.33 * half.y() * std::sin(phi),
                            box.min().z() + 0.5 * box.sizes().z() + 0.05 * std::sin(5 * phi));
  const Eigen::Vector3d target(c.x() - 0.5 * half.x() * std::cos(phi + 0.6 * std::sin(3 * phi)),
                               c.y() - 0.5 * half.y() * std::sin(phi + 0.6 * std::sin(3 * phi)),
                               box.min().z() + 0.25 * box.sizes().z() * (1 + std::sin(7 * phi)));
  return cameraPose(eye, target);
}

/// A square in front of the camera, between it and what it sees: in front of the object for
/// views around one, and a fifth of the scene's radius ahead for a camera walking inside it (a
/// person or an object passing close by).
SyntheticPatch drawPatch(int scan, const Pose& cam, const Eigen::Vector3d& centre, double radius,
                         bool inside, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const double ahead = inside ? 0.2 * radius : (cam.t - centre).norm() - 1.25 * radius;
  const double side = inside ? 0.05 * radius : 0.25 * radius;
  const Eigen::Vector3d look = -cam.R.col(2);
  const Eigen::Vector3d mid =
      cam.t + ahead * look + side * (u(rng) * cam.R.col(0) + u(rng) * cam.R.col(1));
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.25 * u(rng), cam.R.col(0)) *
                                Eigen::AngleAxisd(0.25 * u(rng), cam.R.col(1)))
                                   .toRotationMatrix();
  const Eigen::Vector3d ax = tilt * cam.R.col(0), ay = tilt * cam.R.col(1);
  const double h = (inside ? 0.05 : 0.175) * radius;
  SyntheticPatch p;
  p.scan = scan;
  p.corners = {mid - h * ax - h * ay, mid + h * ax - h * ay, mid + h * ax + h * ay,
               mid - h * ax + h * ay};
  return p;
}

/// Casts one ray per pixel; returns the hit distance along the unit ray, or NaN; `onPatch`
/// tells whether an extraneous patch was hit.
double castPixel(const Bvh& bvh, const TriangleMesh& patches, const Eigen::Vector3d& eye,
                 const Eigen::Vector3d& dir, bool& onPatch) {
  RayHit hit;
  double t = bvh.firstHit(eye, dir, 0, INFINITY, hit) ? hit.t : NAN;
  onPatch = false;
  for (const Triangle& f : patches.faces) {
    double tp;
    const double limit = std::isnan(t) ? INFINITY : t;
    if (intersectTriangle(eye, dir, patches.vertices[f[0]], patches.vertices[f[1]],
                          patches.vertices[f[2]], 0, limit, tp))
      t = tp, onPatch = true;
  }
  return t;
}

/// Range t along unit `ray` as a structured-light camera measures it: depth from a disparity
/// rounded to 1/8 pixel.
double quantisedRange(double t, const Eigen::Vector3d& ray, const Pinhole& lens,
                      const ScanSettings& set) {
  const double z = -t * ray.z(), fb = lens.fx * set.disparityBaseline;
  if (!(z > 0)) return t;
  const double disparity = std::max(0.125, std::round(8 * fb / z) / 8);
  return fb / disparity / -ray.z();
}

/// The colour a camera at `eye` sees along the unit world direction `dir` that meets the
/// scene at range `t` (NaN: nothing, black), on a patch or not.
Colour colourAlong(const Eigen::Vector3d& eye, const Eigen::Vector3d& dir, double t, bool onPatch,
                   double texture) {
  if (std::isnan(t)) return Colour(0, 0, 0);
  return onPatch ? patchColour() : checkColour(eye + t * dir, texture);
}

void render(SyntheticScan& s, const Bvh& bvh, const TriangleMesh& patches, double depthLo,
            double depthHi, double eyeDistance, const ScanSettings& set, std::mt19937_64& rng) {
  RangeGrid& g = s.grid;
  g.colourKind = set.texture > 0 ? ColourKind::rgb : ColourKind::none;
  g.cols = set.width;
  g.rows = set.height;
  g.cell.assign(static_cast<size_t>(g.cols) * g.rows, -1);
  std::normal_distribution<double> noise(0, set.noise * set.voxel);
  auto growth = [&](double t) {
    return set.depthNoise ? (t / eyeDistance) * (t / eyeDistance) : 1.0;
  };
  std::uniform_real_distribution<double> unit(0, 1), depth(depthLo, depthHi);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector3d ray = g.spherical ? stationRay(g, r, c) : pinholeRay(g, r, c);
      bool onPatch;
      double t = castPixel(bvh, patches, s.truth.t, s.truth.R * ray, onPatch);
      if (std::isnan(t)) continue;
      // The colour of what the ray truly hits: a colour camera is not fooled by a depth outlier.
      // A colour image shifted against the depth sees along its own ray.
      if (set.texture > 0 && (g.spherical || set.colourShift == 0)) {
        g.colours.push_back(colourAlong(s.truth.t, s.truth.R * ray, t, onPatch, set.texture));
      } else if (set.texture > 0) {
        const Eigen::Vector3d dir = s.truth.R * pinholeRay(g, r, c + set.colourShift);
        bool seenOnPatch;
        const double seen = castPixel(bvh, patches, s.truth.t, dir, seenOnPatch);
        g.colours.push_back(colourAlong(s.truth.t, dir, seen, seenOnPatch, set.texture));
      }
      if (set.outliers > 0 && unit(rng) < set.outliers)
        t = depth(rng);
      else if (set.noise > 0)
        t += growth(t) * noise(rng);
      if (set.disparityBaseline > 0 && g.pinhole) t = quantisedRange(t, ray, *g.pinhole, set);
      g.cell[static_cast<size_t>(r) * g.cols + c] = static_cast<int32_t>(g.points.size());
      g.points.push_back(t * ray);
    }
}

/// What a depth camera's rays meet: the scene and its extraneous patches.
struct Scene {
  const TriangleMesh& mesh;
  const Bvh& bvh;
  const TriangleMesh& patches;

  /// The first hit along the unit ray from `eye` (NaN: none) and the surface's unit normal
  /// there; `onPatch` tells whether it is a patch.
  double cast(const Eigen::Vector3d& eye, const Eigen::Vector3d& dir, Eigen::Vector3d& normal,
              bool& onPatch) const {
    RayHit hit;
    double t = bvh.firstHit(eye, dir, 0, INFINITY, hit) ? hit.t : NAN;
    if (!std::isnan(t)) normal = faceNormal(mesh, hit.face);
    onPatch = false;
    for (size_t f = 0; f < patches.faces.size(); ++f) {
      const Triangle& tri = patches.faces[f];
      double tp;
      if (intersectTriangle(eye, dir, patches.vertices[tri[0]], patches.vertices[tri[1]],
                            patches.vertices[tri[2]], 0, std::isnan(t) ? INFINITY : t, tp))
        t = tp, onPatch = true, normal = faceNormal(patches, static_cast<int32_t>(f));
    }
    return t;
  }

  /// True when something lies between `from` and `to`.
  bool blocked(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
    const Eigen::Vector3d d = to - from;
    const double length = d.norm();
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    bool onPatch;
    const double t = cast(from + 1e-6 * length * d / length, d / length, n, onPatch);
    return t < length * (1 - 2e-6);
  }

  static Eigen::Vector3d faceNormal(const TriangleMesh& m, int32_t f) {
    const Triangle& t = m.faces[f];
    return (m.vertices[t[1]] - m.vertices[t[0]])
        .cross(m.vertices[t[2]] - m.vertices[t[0]])
        .normalized();
  }
};

/// The colour image's pixel at depth pixel (r, c), whose ray `dir` hit at range `t`
/// (`onPatch`): shifted by set.colourShift pixels along the row, the colour camera's own ray
/// may meet something else.
Colour sensorColour(const Scene& scene, const Pose& cam, const Eigen::Vector3d& dir, double t,
                    bool onPatch, const RangeGrid& g, int r, int c, const ScanSettings& set) {
  if (set.colourShift == 0) return colourAlong(cam.t, dir, t, onPatch, set.texture);
  const Eigen::Vector3d shifted = cam.R * pinholeRay(g, r, c + set.colourShift);
  Eigen::Vector3d normal;
  const double seen = scene.cast(cam.t, shifted, normal, onPatch);
  return colourAlong(cam.t, shifted, seen, onPatch, set.texture);
}

/// Frame i of a depth camera under set.sensor: each row seen from where the camera was when
/// the row was read (rolling shutter, time offset), rays the projector cannot reach (its
/// shadows), grazing rays, dark surfaces and depths out of range return nothing, then the
/// image's own faults (DepthSensorModel.h). The points are stored in the frame of the pose
/// reported for the frame, s.truth, as a sensor's driver gives them.
void renderSensor(SyntheticScan& s, const Scene& scene, const std::function<Pose(double)>& poseAt,
                  int i, const ScanSettings& set, std::mt19937_64& rng) {
  const DepthSensorModel& m = set.sensor;
  RangeGrid& g = s.grid;
  g.colourKind = set.texture > 0 ? ColourKind::rgb : ColourKind::none;
  g.cols = set.width, g.rows = set.height;
  const size_t cells = static_cast<size_t>(g.cols) * g.rows;
  std::vector<double> depth(cells, 0);
  std::vector<Colour> colour(set.texture > 0 ? cells : 0);
  for (int r = 0; r < g.rows; ++r) {
    // Grid row r is image row rows - 1 - r; the image is read from its top row down.
    const double read = (g.rows - 1 - r) / std::max(1.0, g.rows - 1.0) - 0.5;
    const Pose cam = poseAt(i + m.timeOffset + m.rollingShutter * read);
    const Eigen::Vector3d projector = cam.apply(Eigen::Vector3d(m.baseline, 0, 0));
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector3d ray = pinholeRay(g, r, c), dir = cam.R * ray;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      bool onPatch;
      const double t = scene.cast(cam.t, dir, normal, onPatch);
      const double z = -t * ray.z();
      if (std::isnan(t) || z < m.nearest || (m.farthest > 0 && z > m.farthest)) continue;
      const Eigen::Vector3d hit = cam.t + t * dir;
      if (std::abs(normal.dot(dir)) < m.grazingCos) continue;
      if (onDarkSurface(hit.x(), hit.y(), hit.z(), m)) continue;
      if (m.shadows && scene.blocked(hit, projector)) continue;
      const size_t k = static_cast<size_t>(r) * g.cols + c;
      depth[k] = z;
      if (set.texture > 0) colour[k] = sensorColour(scene, cam, dir, t, onPatch, g, r, c, set);
    }
  }
  applyImageFaults(depth, g.cols, g.rows, g.pinhole->fx, m, rng);
  g.cell.assign(cells, -1);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const size_t k = static_cast<size_t>(r) * g.cols + c;
      if (!(depth[k] > 0)) continue;
      const Eigen::Vector3d ray = pinholeRay(g, r, c);
      g.cell[k] = static_cast<int32_t>(g.points.size());
      g.points.push_back(depth[k] / -ray.z() * ray);
      if (set.texture > 0) g.colours.push_back(colour[k]);
    }
}

}  // namespace

Colour checkColour(const Eigen::Vector3d& p, double size) {
  // Scenes put planes at round coordinates (a room's floor at 0): a check edge there would
  // split the plane's colour by the sign of its noise.
  constexpr double kOffset = 0.382;  // of a side
  const long parity = static_cast<long>(std::floor(p.x() / size + kOffset)) +
                      static_cast<long>(std::floor(p.y() / size + kOffset)) +
                      static_cast<long>(std::floor(p.z() / size + kOffset));
  return parity % 2 == 0 ? Colour(0.85f, 0.35f, 0.15f) : Colour(0.15f, 0.45f, 0.80f);
}

Colour patchColour() {
  return Colour(0.9f, 0.1f, 0.9f);
}

SyntheticSet scanMesh(const TriangleMesh& mesh, const ScanSettings& set) {
  validate(mesh, set);
  SyntheticSet out;
  Eigen::AlignedBox3d box;
  for (const auto& v : mesh.vertices) box.extend(v);
  out.centre = box.center();
  for (const auto& v : mesh.vertices) out.radius = std::max(out.radius, (v - out.centre).norm());
  const Bvh bvh(mesh);
  std::mt19937_64 rng(set.seed);
  const bool walk = set.path == ViewPath::Walk;
  // Inside a scene, depth noise holds at a typical wall distance, and the lens is a depth
  // camera's (45 degrees vertical) unless given.
  const double eyeDistance = walk ? 0.5 * out.radius : kDistance * out.radius;
  const double halfFov = set.fovDeg > 0 ? 0.5 * set.fovDeg * M_PI / 180
                         : walk         ? 22.5 * M_PI / 180
                                        : 1.05 * std::asin(out.radius / eyeDistance);
  const double f = 0.5 * std::min(set.width, set.height) / std::tan(halfFov);
  // Patches go to evenly spaced scans so that no two share one.
  std::vector<int> patchOf(set.views, -1);
  for (int k = 0; k < set.patches; ++k) patchOf[(k * set.views) / set.patches] = k;
  for (int i = 0; i < set.views; ++i) {
    SyntheticScan s;
    char name[32];
    std::snprintf(name, sizeof(name), "scan_%03d.ply", i);
    s.name = name;
    if (set.path == ViewPath::Stations) {
      s.viewpoint = stationPosition(i, set.views, box);
      s.truth = Pose{Eigen::Matrix3d::Identity(), s.viewpoint};
      s.grid.spherical = true;
      render(s, bvh, {}, 0.1 * out.radius, 2 * out.radius, out.radius, set, rng);
    } else {
      // The camera at time tau (frames); views spread over a sphere have no time between them.
      auto poseAt = [&](double tau) {
        switch (set.path) {
          case ViewPath::Handheld:
            return handheldPose(tau, set.views, out.centre, out.radius, eyeDistance);
          case ViewPath::FastTurns:
            return handheldPose(tau, set.views, out.centre, out.radius, eyeDistance, 0.8, 1.6);
          case ViewPath::Walk:
            return walkPose(tau, set.views, box);
          case ViewPath::Orbit:
            return cameraPose(out.centre + eyeDistance * orbitDirection(tau, set.views),
                              out.centre);
          default:
            return cameraPose(out.centre + eyeDistance * fibonacciDirection(i, set.views),
                              out.centre);
        }
      };
      s.truth = poseAt(i);
      s.viewpoint = s.truth.t;
      s.grid.pinhole = Pinhole{f, f, 0.5 * (set.width - 1), 0.5 * (set.height - 1)};
      TriangleMesh patches;
      if (patchOf[i] >= 0) {
        out.patches.push_back(drawPatch(i, s.truth, out.centre, out.radius, walk, rng));
        patches = patchMesh({out.patches.back()});
      }
      const double near = walk ? 0.02 * out.radius : eyeDistance - out.radius;
      const double far = walk ? 2 * out.radius : eyeDistance + out.radius;
      if (set.sensor.active())
        renderSensor(s, Scene{mesh, bvh, patches}, poseAt, i, set, rng);
      else
        render(s, bvh, patches, near, far, eyeDistance, set, rng);
    }
    s.perturbed = s.truth;
    if (i > 0)
      s.perturbed = perturbPose(s.truth, out.centre, set.rotDeg, set.transVox * set.voxel, rng,
                                s.rotationDeg, s.translation);
    out.scans.push_back(std::move(s));
  }
  return out;
}

Pose perturbPose(const Pose& truth, const Eigen::Vector3d& centre, double rotDeg, double shift,
                 std::mt19937_64& rng, Eigen::Vector3d& angles, Eigen::Vector3d& translation) {
  std::uniform_real_distribution<double> angle(-rotDeg, rotDeg), move(-shift, shift);
  for (int a = 0; a < 3; ++a) angles[a] = angle(rng);
  for (int a = 0; a < 3; ++a) translation[a] = move(rng);
  const Eigen::Vector3d rad = angles * M_PI / 180;
  const Eigen::Matrix3d dR = (Eigen::AngleAxisd(rad.z(), Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(rad.y(), Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(rad.x(), Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix();
  Pose p;
  p.R = dR * truth.R;
  p.t = dR * (truth.t - centre) + centre + translation;
  return p;
}

TriangleMesh patchMesh(const std::vector<SyntheticPatch>& patches) {
  TriangleMesh m;
  for (const auto& p : patches) {
    const int32_t b = static_cast<int32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), p.corners.begin(), p.corners.end());
    m.faces.push_back({b, b + 1, b + 2});
    m.faces.push_back({b, b + 2, b + 3});
  }
  return m;
}

}  // namespace rangefuse
