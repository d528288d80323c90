// Pictures of a fused field: ray-cast surface (Tubic §4.7) and distance slices.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rangefuse/core/Image.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/render/SparseField.h"

namespace rangefuse {

/// Orthographic view from azimuth (about +y, 0 = from +z) and elevation (toward +y).
struct ViewSettings {
  double azimuthDeg = 0;
  double elevationDeg = 20;
  /// The world's up axis, 'y' (azimuth about +y, 0 = from +z) or 'z' as scanner stations
  /// have it (azimuth about +z, 0 = from -y).
  char up = 'y';
  int width = 512;
  int height = 512;
  /// When set, a perspective picture from this camera (camera to world; x right, y down,
  /// looking along +z) with `focal` pixels, seeing up to `farthest`, instead of the orbit view.
  std::optional<Pose> camera;
  double focal = 0, farthest = 0;
};

/// What a picture shows where no surface is: a dark slate that a pale surface, and a hole in
/// it, stand out against.
inline constexpr std::array<uint8_t, 3> kBackground{44, 48, 58};

/// An orthographic view's axes as rows: right, up, and toward the camera.
Eigen::Matrix3d viewAxes(const ViewSettings& view);

/// Where an orthographic picture looks. `extent` is what it frames, in view coordinates (the
/// rows of viewAxes); the picture fills with it, keeping a small margin, whatever its shape.
struct ViewFrame {
  Eigen::Matrix3d axes;
  Eigen::AlignedBox3d extent;
  double pixel = 0;  ///< world size of a pixel
  int width = 0, height = 0;

  ViewFrame(const ViewSettings& view, const Eigen::AlignedBox3d& extent);
  /// Continuous pixel coordinates of p (x right, y down; pixel centres at k + 0.5) and its
  /// depth, the distance behind the extent's near face.
  Eigen::Vector3d project(const Eigen::Vector3d& p) const;
  /// The world point on the extent's near face, moved `ahead` toward the camera, that pixel
  /// position (x, y) sees.
  Eigen::Vector3d rayOrigin(double x, double y, double ahead) const;
};

/// Which bricks a caller takes crossings from (null: all).
using BrickFilter = std::function<bool(const BrickCoord&)>;

/// The first surface crossing of one pixel's ray: its depth (NaN: none) and shaded colour.
struct PixelHit {
  double t = NAN;
  std::array<uint8_t, 3> rgb{};
};

/// One ray per pixel of a view framing `extent` (view coordinates, see ViewFrame), cast through
/// `field` to the first outside-to-inside crossing whose later sample lies in a brick `counts`
/// accepts.
std::vector<PixelHit> castRays(const SparseField& field, const Eigen::AlignedBox3d& extent,
                               const ViewSettings& view, const BrickFilter& counts);

/// View-coordinate box of the field's observed voxels within one voxel of the surface: what an
/// orthographic picture of it frames.
Eigen::AlignedBox3d surfaceExtent(const SparseField& field, const Eigen::Matrix3d& axes);

/// Casts a ray per pixel to the first outside-to-inside zero crossing of the trilinear
/// distance, shaded by the stored gradient at the nearest voxel. Empty bricks are skipped. The
/// orbit view frames the surface.
Image renderField(const SparseField& field, const ViewSettings& view);

/// One lattice plane across `axis` (0, 1, 2) at world coordinate `value`: grey by |d| (black
/// on the surface), unobserved voxels in blue. x slices show (y, z), y (x, z), z (x, y).
Image renderSlice(const SparseField& field, int axis, double value);

/// Collective: the surface picture of a distributed field on `root` (blank elsewhere), the
/// same pixels renderField gives on the gathered field. Each rank casts every ray through its
/// bricks and their neighbours only, and the pictures are composited by depth.
Image renderDistributed(const BrickStore& store, float minWeight, const ViewSettings& view,
                        int root, MPI_Comm comm);

/// Lattice index along `axis` of the slice plane at world coordinate `value`.
int slicePlane(const VoxelGrid& grid, int axis, double value);

/// "AZ,EL" in degrees; throws InputError.
void parseView(const std::string& text, ViewSettings& view);

/// The up axis an --up setting names: 'y' or 'z' as given; for "auto", 'z' when the scans are
/// scanner stations (`stations`), else 'y'. Throws InputError for any other setting.
char upAxis(const std::string& setting, bool stations);
/// "x=VALUE" (or y, z); throws InputError.
void parseSlice(const std::string& text, int& axis, double& value);

}  // namespace rangefuse
