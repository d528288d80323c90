#include "rangefuse/core/Limits.h"

#include <cstdio>

#include "rangefuse/core/Error.h"

namespace rangefuse {

void checkLimit(const std::string& where, const std::string& what, double value, uint64_t limit,
                const std::string& option) {
  if (value <= static_cast<double>(limit)) return;
  char number[64];
  std::snprintf(number, sizeof(number), "%.6g", value);
  throw InputError(where + ": " + what + " " + number + " exceeds the limit " +
                   std::to_string(limit) + " (raise it with --" + option + ")");
}

}  // namespace rangefuse
