#include "rangefuse/volume/BrickLayout.h"

#include <algorithm>
#include <numeric>

namespace rangefuse {
namespace {

uint64_t spreadBits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

uint64_t compactBits(uint64_t x) {
  x &= 0x1249249249249249ULL;
  x = (x ^ (x >> 2)) & 0x10c30c30c30c30c3ULL;
  x = (x ^ (x >> 4)) & 0x100f00f00f00f00fULL;
  x = (x ^ (x >> 8)) & 0x1f0000ff0000ffULL;
  x = (x ^ (x >> 16)) & 0x1f00000000ffffULL;
  x = (x ^ (x >> 32)) & 0x1fffff;
  return x;
}

}  // namespace

uint64_t mortonEncode(const BrickCoord& b) {
  return spreadBits(b.x()) | spreadBits(b.y()) << 1 | spreadBits(b.z()) << 2;
}

BrickCoord mortonDecode(uint64_t code) {
  return BrickCoord(static_cast<int>(compactBits(code)), static_cast<int>(compactBits(code >> 1)),
                    static_cast<int>(compactBits(code >> 2)));
}

int64_t BrickLayout::find(uint64_t code) const {
  auto it = std::lower_bound(codes.begin(), codes.end(), code);
  return (it != codes.end() && *it == code) ? it - codes.begin() : -1;
}

uint64_t BrickLayout::bytes() const {
  return sizeof(uint64_t) * (codes.capacity() + work.capacity()) +
         sizeof(size_t) * rankStart.capacity();
}

int BrickLayout::ownerOf(size_t i) const {
  return static_cast<int>(std::upper_bound(rankStart.begin(), rankStart.end(), i) -
                          rankStart.begin()) -
         1;
}

std::vector<size_t> partitionWork(const std::vector<uint64_t>& work, int ranks) {
  const uint64_t total = std::accumulate(work.begin(), work.end(), uint64_t{0});
  std::vector<size_t> start(ranks + 1, work.size());
  start[0] = 0;
  uint64_t prefix = 0;
  int r = 1;
  for (size_t i = 0; i < work.size() && r < ranks; ++i) {
    // Brick i opens rank r's run once the work before it reaches r/ranks of the total.
    while (r < ranks && prefix * ranks >= total * r) start[r++] = i;
    prefix += work[i];
  }
  return start;
}

}  // namespace rangefuse
