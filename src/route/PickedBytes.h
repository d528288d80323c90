// Appending listed elements of a vector to a byte buffer (private to route/): what every packed
// vector of a part starts from, in its own form or as its elements are.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

namespace rangefuse::internal {

/// Grows buf by `bytes` and gives where they start (grown once and written in place: an
/// insert a value costs more than the copy).
inline char* grow(std::vector<char>& buf, size_t bytes) {
  const size_t at = buf.size();
  buf.resize(at + bytes);
  return buf.data() + at;
}

/// Appends, for each listed i, v's `per` elements from i * per, as they are.
template <class T>
void appendPicked(std::vector<char>& buf, const std::vector<T>& v,
                  const std::vector<uint32_t>& pick, size_t per = 1) {
  const size_t bytes = per * sizeof(T);
  char* out = grow(buf, pick.size() * bytes);
  for (uint32_t i : pick) std::memcpy(out, v.data() + size_t(i) * per, bytes), out += bytes;
}

}  // namespace rangefuse::internal
