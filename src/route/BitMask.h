// A bit a value, eight to a byte, the first value in the lowest bit (private to route/): how
// packed parts say which of their texels are sampled and which prism limits are the part's own.
#pragma once

#include <bitset>
#include <cstddef>
#include <cstdint>

namespace rangefuse::internal {

/// Bytes of the mask of n values.
inline size_t maskBytes(uint64_t n) {
  return size_t((n + 7) / 8);
}

/// Whether bit k of the mask is set.
inline bool bitAt(const char* mask, size_t k) {
  return (mask[k / 8] >> (k % 8)) & 1;
}

/// Sets bit k of the mask.
inline void setBit(char* mask, size_t k) {
  mask[k / 8] = char(mask[k / 8] | 1 << (k % 8));
}

/// Set bits in the mask of n values (the last byte's spare bits are clear).
inline size_t setBits(const char* mask, uint64_t n) {
  size_t count = 0;
  for (size_t k = 0; k < maskBytes(n); ++k) count += std::bitset<8>(uint8_t(mask[k])).count();
  return count;
}

}  // namespace rangefuse::internal
