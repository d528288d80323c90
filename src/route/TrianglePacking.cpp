#include "TrianglePacking.h"

#include <algorithm>
#include <cstring>

#include "PickedBytes.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

// A step below 240 takes a byte; one below kTwoBytes two, the first from 240 to 254 holding its
// high bits; any other corner is kEscape and the corner in 32 bits.
constexpr uint32_t kOneByte = 240, kTwoBytes = kOneByte + 15 * 256;
constexpr uint8_t kEscape = 0xff;

/// Writes corner's step below `next` at out (room for two bytes, or grows buf); gives the end.
char* putStep(std::vector<char>& buf, char* out, int64_t next, int32_t corner) {
  const int64_t step = next - corner;
  if (step >= 0 && step < kOneByte) {
    *out++ = static_cast<char>(step);
    return out;
  }
  if (step >= 0 && step < kTwoBytes) {
    const auto high = static_cast<uint32_t>(step - kOneByte);
    *out++ = static_cast<char>(kOneByte + (high >> 8));
    *out++ = static_cast<char>(high & 0xff);
    return out;
  }
  // Two bytes are reserved a corner: an escape needs three more.
  const size_t at = size_t(out - buf.data());
  grow(buf, 3);
  out = buf.data() + at;
  *out++ = static_cast<char>(kEscape);
  std::memcpy(out, &corner, sizeof corner);
  return out + sizeof corner;
}

}  // namespace

void packTriangles(std::vector<char>& buf, const std::vector<Triangle>& triangles,
                   const std::vector<uint32_t>& pick, const std::vector<int32_t>& remap) {
  const uint64_t n = pick.size();
  mpi::pack(buf, &n, 1);
  const size_t head = buf.size();
  uint64_t bytes = 0;
  mpi::pack(buf, &bytes, 1);
  char* out = grow(buf, n * 3 * 2);  // two bytes a corner at most; an escape grows it
  int64_t next = 0;
  for (uint32_t k : pick)
    for (const int32_t v : triangles[k]) {
      const int32_t corner = remap[size_t(v)];
      out = putStep(buf, out, next, corner);
      next = std::max(next, int64_t(corner) + 1);
    }
  const size_t end = size_t(out - buf.data());
  buf.resize(end);
  bytes = end - head - sizeof bytes;
  std::memcpy(buf.data() + head, &bytes, sizeof bytes);
}

void unpackTriangles(const std::vector<char>& buf, size_t& pos, std::vector<Triangle>& v) {
  uint64_t n, bytes;
  mpi::unpack(buf, pos, &n, 1);
  mpi::unpack(buf, pos, &bytes, 1);
  v.resize(n);
  const auto* in = reinterpret_cast<const uint8_t*>(buf.data() + pos);
  int64_t next = 0;
  for (Triangle& t : v)
    for (int32_t& corner : t) {
      const uint32_t first = *in++;
      if (first != kEscape) {
        const uint32_t step =
            first < kOneByte ? first : kOneByte + ((first - kOneByte) << 8 | *in++);
        corner = int32_t(next - step);
        next += step == 0;  // a step of 0 is the next new vertex; any other lies below it
        continue;
      }
      std::memcpy(&corner, in, sizeof corner), in += sizeof corner;
      next = std::max(next, int64_t(corner) + 1);
    }
  pos += bytes;
}

void skipTriangles(const std::vector<char>& buf, size_t& pos) {
  uint64_t n, bytes;
  mpi::unpack(buf, pos, &n, 1);
  mpi::unpack(buf, pos, &bytes, 1);
  pos += bytes;
}

}  // namespace rangefuse::internal
