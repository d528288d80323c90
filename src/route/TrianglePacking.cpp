#include "TrianglePacking.h"

#include <algorithm>
#include <cstring>

#include "PickedBytes.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

constexpr uint16_t kEscape = 0xffff;

}  // namespace

void packTriangles(std::vector<char>& buf, const std::vector<Triangle>& triangles,
                   const std::vector<uint32_t>& pick, const std::vector<int32_t>& remap) {
  const uint64_t n = pick.size();
  mpi::pack(buf, &n, 1);
  const size_t head = buf.size();
  uint64_t bytes = 0;
  mpi::pack(buf, &bytes, 1);
  char* out = grow(buf, n * 3 * sizeof(uint16_t));  // the steps; an escape grows it further
  int64_t next = 0;
  for (uint32_t k : pick)
    for (const int32_t v : triangles[k]) {
      const int32_t corner = remap[size_t(v)];
      const int64_t step = next - corner;
      next = std::max(next, int64_t(corner) + 1);
      if (step >= 0 && step < kEscape) {
        const uint16_t word = uint16_t(step);
        std::memcpy(out, &word, sizeof word), out += sizeof word;
        continue;
      }
      const size_t at = size_t(out - buf.data());
      grow(buf, sizeof corner);
      out = buf.data() + at;
      std::memcpy(out, &kEscape, sizeof kEscape), out += sizeof kEscape;
      std::memcpy(out, &corner, sizeof corner), out += sizeof corner;
    }
  const size_t at = size_t(out - buf.data());
  bytes = at - head - sizeof bytes;
  std::memcpy(buf.data() + head, &bytes, sizeof bytes);
}

void unpackTriangles(const std::vector<char>& buf, size_t& pos, std::vector<Triangle>& v) {
  uint64_t n, bytes;
  mpi::unpack(buf, pos, &n, 1);
  mpi::unpack(buf, pos, &bytes, 1);
  v.resize(n);
  const char* in = buf.data() + pos;
  int64_t next = 0;
  for (Triangle& t : v)
    for (int32_t& corner : t) {
      uint16_t word;
      std::memcpy(&word, in, sizeof word), in += sizeof word;
      if (word != kEscape) {
        corner = int32_t(next - word);
        next += word == 0;  // a step of 0 is the next new vertex; any other lies below it
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
