// Bounds on what outside input may make rangefuse allocate, each raised by an option.
#pragma once

#include <cstdint>
#include <string>

namespace rangefuse {

/// Input is refused, before anything is allocated for it, when it would exceed one of these.
/// The defaults keep a 24 GiB node safe; a bigger job raises them on the command line.
struct InputLimits {
  uint64_t maxElements = 200'000'000;   ///< items in one PLY element (--max-elements)
  uint64_t maxGridCells = 100'000'000;  ///< cells of one range grid (--max-grid-cells)
  uint64_t maxVoxels = 1'000'000'000;   ///< allocated voxels of a field, all ranks (--max-voxels)
};

/// A number as a message shows it: up to 6 significant digits ("1e+12", "0.001").
std::string formatNumber(double value);

/// Throws InputError "WHERE: WHAT VALUE exceeds the limit LIMIT (raise it with --OPTION)"
/// when value > limit. `value` is a double so that overflowing products are still compared.
void checkLimit(const std::string& where, const std::string& what, double value, uint64_t limit,
                const std::string& option);

}  // namespace rangefuse
