// Pictures of a fused field: ray-cast surface (Tubic §4.7) and distance slices.
#pragma once

#include <string>

#include "rangefuse/core/Image.h"
#include "rangefuse/render/SparseField.h"

namespace rangefuse {

/// Orthographic view from azimuth (about +y, 0 = from +z) and elevation (toward +y).
struct ViewSettings {
  double azimuthDeg = 0;
  double elevationDeg = 20;
  int width = 512;
  int height = 512;
};

/// Casts a ray per pixel to the first outside-to-inside zero crossing of the trilinear
/// distance, shaded by the stored gradient at the nearest voxel. Empty bricks are skipped.
Image renderField(const SparseField& field, const ViewSettings& view);

/// One lattice plane across `axis` (0, 1, 2) at world coordinate `value`: grey by |d| (black
/// on the surface), unobserved voxels in blue. x slices show (y, z), y (x, z), z (x, y).
Image renderSlice(const SparseField& field, int axis, double value);

/// "AZ,EL" in degrees; throws InputError.
void parseView(const std::string& text, ViewSettings& view);
/// "x=VALUE" (or y, z); throws InputError.
void parseSlice(const std::string& text, int& axis, double& value);

}  // namespace rangefuse
