#include "rangefuse/core/RangeGrid.h"

#include <algorithm>

namespace rangefuse {

int bandCount(int cols, int rows, uint64_t maxCells) {
  const uint64_t cells = static_cast<uint64_t>(cols) * static_cast<uint64_t>(rows);
  if (maxCells == 0 || cells <= maxCells) return 1;
  const uint64_t wanted = (cells + maxCells - 1) / maxCells;
  return static_cast<int>(
      std::max<uint64_t>(1, std::min<uint64_t>(wanted, cols / kMinBandColumns)));
}

}  // namespace rangefuse
