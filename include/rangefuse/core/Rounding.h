// Rounding a double to an int without a library call, where it runs per prism, row or sample.
#pragma once

namespace rangefuse {

/// std::ceil and std::floor to an int, exactly, for values in int's range: through the int
/// conversion, which x86-64 without SSE4.1 makes far cheaper than the rounding itself (boxes
/// are rounded for every prism, spans for every row, texels for every voxel sample).
inline int ceilToInt(double x) {
  const int t = static_cast<int>(x);
  return t + (t < x);
}
inline int floorToInt(double x) {
  const int t = static_cast<int>(x);
  return t - (t > x);
}

}  // namespace rangefuse
