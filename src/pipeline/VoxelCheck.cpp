#include "rangefuse/pipeline/VoxelCheck.h"

#include <cmath>
#include <cstdio>

namespace rangefuse {

std::string voxelUnitWarning(double voxel, const Eigen::AlignedBox3d& bounds) {
  if (bounds.isEmpty() || !(voxel > 0)) return "";
  const double span = bounds.sizes().maxCoeff();
  const double across = span / voxel;
  if (!(span > 0) || (across >= 20 && across <= 50000)) return "";
  // The power of ten that brings the voxel nearest to 300 across (log scale): a unit slip is
  // a factor of 10, 100 or 1000.
  const double power = std::round(std::log10(across / 300));
  char text[256];
  std::snprintf(text, sizeof text,
                "--voxel %g gives %.3g voxels across the scans, which span %.3g units: did you "
                "mean %g?",
                voxel, across, span, voxel * std::pow(10.0, power));
  return text;
}

}  // namespace rangefuse
