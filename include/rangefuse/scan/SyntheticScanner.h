// A synthetic pinhole range scanner with ground truth (poses, noise, outliers, patches).
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/core/TriangleMesh.h"
#include "rangefuse/scan/DepthSensorModel.h"

namespace rangefuse {

/// Where the viewpoints lie: spread evenly over a sphere around the object (a turntable or
/// a scanner moved around it), along one orbit around it with a gently rising and falling
/// height (a hand-held depth camera filming a sequence), or inside the scene as terrestrial
/// laser scanner stations (spherical grids: width columns of a full turn, height rows from 80
/// degrees below the horizon to 80 above). Two depth-camera paths as a person walks them: around
/// the object, nearer and farther, the view swaying left, right, up and down in fast turns
/// (handheld); or inside the scene, along a loop, looking ahead and swaying (walk: rooms).
/// FastTurns is the hand-held path with the view swaying twice as far, 2.5 times as often: turns
/// of up to about 6 degrees a frame, as TUM's fr1/rpy records them.
enum class ViewPath { Sphere, Orbit, Stations, Handheld, Walk, FastTurns };

struct ScanSettings {
  int views = 24;
  ViewPath path = ViewPath::Sphere;
  int width = 320;
  int height = 240;
  double voxel = 1.0;       ///< unit of noise and translation
  double fovDeg = 0;        ///< vertical field of view; 0 = fitted to the object
  double noise = 0;         ///< Gaussian range noise sigma, voxels
  bool depthNoise = false;  ///< sigma grows with the square of the range (depth cameras), equal
                            ///< to `noise` at the viewpoints' distance from the object's centre
  double outliers = 0;      ///< fraction of samples moved to a random depth on their ray
  /// Structured-light depth (a Kinect's): the baseline (world units) of a camera whose depth
  /// comes from disparity in steps of 1/8 pixel, so that depth falls in steps growing with
  /// its square; 0: not quantised. Pinhole views only.
  double disparityBaseline = 0;
  int patches = 0;      ///< extraneous flat patches, each seen by one scan only
  double rotDeg = 0;    ///< perturbation: rotation about each axis uniform in [-A, A]
  double transVox = 0;  ///< perturbation: translation along each axis uniform in [-T, T]
  uint64_t seed = 1;
  double texture = 0;  ///< checks of this side (world units) colour the surface; 0: no colour
  /// The colour image misregistered with the depth by this many pixels along its rows (a
  /// colour camera beside the depth camera, calibrated to within about a pixel). Pinhole views.
  double colourShift = 0;
  DepthSensorModel sensor;  ///< a depth camera's faults (pinhole views; inactive by default)
};

/// An extraneous patch: a square floating in front of the object in one scan only.
struct SyntheticPatch {
  int scan = 0;
  std::array<Eigen::Vector3d, 4> corners;  ///< world coordinates
};

struct SyntheticScan {
  std::string name;  ///< file name, scan_NNN.ply
  RangeGrid grid;    ///< scan frame: sensor at the origin (pinhole looking toward -z, or station)
  Pose truth;        ///< exact scan-to-world pose
  Pose perturbed;    ///< truth moved by the drawn perturbation (scan 0 exact)
  Eigen::Vector3d rotationDeg = Eigen::Vector3d::Zero();  ///< drawn angles about x, y, z
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  ///< drawn translation, world units
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
};

struct SyntheticSet {
  std::vector<SyntheticScan> scans;
  std::vector<SyntheticPatch> patches;
  Eigen::Vector3d centre;  ///< centre of the object's bounding sphere
  double radius = 0;       ///< its radius
};

/// Renders `settings.views` range grids of the mesh from viewpoints on `settings.path`, by exact
/// first-hit ray casting through a BVH, then applies the corruptions. Deterministic for a given
/// seed. Throws InputError on bad settings.
SyntheticSet scanMesh(const TriangleMesh& mesh, const ScanSettings& settings);

/// The synthetic scenes' analytic colour at world point p: cubes of side `size` alternating
/// orange and blue, so that a surface shows checks whose edges are sharp at any scale. The
/// cubes' edges lie 0.382 of a side off round coordinates, so that no plane at a round
/// coordinate (a room's floor at 0) lies on one.
Colour checkColour(const Eigen::Vector3d& p, double size);

/// The colour of an extraneous patch (magenta: told apart from both checks).
Colour patchColour();

/// The scanner's pose perturbation: rotation about x, y, z by angles uniform in [-rotDeg,
/// rotDeg] about `centre`, then a shift uniform in [-shift, shift] per axis (world units).
/// Returns the perturbed pose; `angles` (degrees) and `translation` receive what was drawn.
Pose perturbPose(const Pose& truth, const Eigen::Vector3d& centre, double rotDeg, double shift,
                 std::mt19937_64& rng, Eigen::Vector3d& angles, Eigen::Vector3d& translation);

/// A mesh of the patches (two triangles each), e.g. to measure what survives of them.
TriangleMesh patchMesh(const std::vector<SyntheticPatch>& patches);

}  // namespace rangefuse
