// FNV-1a 64: the checksum of scan files and of every part of a checkpoint.
#pragma once

#include <cstddef>
#include <cstdint>

namespace rangefuse::io {

constexpr uint64_t kFnvOffset = 1469598103934665603ULL;

/// FNV-1a 64 of n bytes, continuing from h (chain calls to digest pieces as one stream).
inline uint64_t fnv1a64(const void* data, size_t n, uint64_t h = kFnvOffset) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ULL;
  }
  return h;
}

}  // namespace rangefuse::io
