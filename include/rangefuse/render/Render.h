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
  int width = 512;
  int height = 512;
  /// When set, a perspective picture from this camera (camera to world; x right, y down,
  /// looking along +z) with `focal` pixels, seeing up to `farthest`, instead of the orbit view.
  std::optional<Pose> camera;
  double focal = 0, farthest = 0;
};

/// Which bricks a caller takes crossings from (null: all).
using BrickFilter = std::function<bool(const BrickCoord&)>;

/// The first surface crossing of one pixel's ray: its depth (NaN: none) and shaded colour.
struct PixelHit {
  double t = NAN;
  std::array<uint8_t, 3> rgb{};
};

/// One ray per pixel of a view framing `bounds`, cast through `field` to the first
/// outside-to-inside crossing whose later sample lies in a brick `counts` accepts.
std::vector<PixelHit> castRays(const SparseField& field, const Eigen::AlignedBox3d& bounds,
                               const ViewSettings& view, const BrickFilter& counts);

/// Casts a ray per pixel to the first outside-to-inside zero crossing of the trilinear
/// distance, shaded by the stored gradient at the nearest voxel. Empty bricks are skipped.
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
/// "x=VALUE" (or y, z); throws InputError.
void parseSlice(const std::string& text, int& axis, double& value);

}  // namespace rangefuse
