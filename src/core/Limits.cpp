#include "rangefuse/core/Limits.h"

#include <cstdio>

#include "rangefuse/core/Error.h"

namespace rangefuse {

std::string formatNumber(double value) {
  char number[32];
  std::snprintf(number, sizeof(number), "%.6g", value);
  return number;
}

void checkLimit(const std::string& where, const std::string& what, double value, uint64_t limit,
                const std::string& option) {
  if (value <= static_cast<double>(limit)) return;
  throw InputError(where + ": " + what + " " + formatNumber(value) + " exceeds the limit " +
                   std::to_string(limit) + " (raise it with --" + option + ")");
}

}  // namespace rangefuse
