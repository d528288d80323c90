#include "rangefuse/volume/BrickLayout.h"

#include <algorithm>
#include <numeric>

namespace rangefuse {
namespace {

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

BrickCoord mortonDecode(uint64_t code) {
  return BrickCoord(static_cast<int>(compactBits(code)), static_cast<int>(compactBits(code >> 1)),
                    static_cast<int>(compactBits(code >> 2)));
}

int64_t BrickLayout::find(uint64_t code) const {
  auto it = std::lower_bound(codes.begin(), codes.end(), code);
  return (it != codes.end() && *it == code) ? it - codes.begin() : -1;
}

uint64_t BrickLayout::bytes() const {
  return sizeof(uint64_t) *
             (codes.capacity() + work.capacity() + firstCodes.capacity() + globalStart.capacity()) +
         sizeof(size_t) * rankStart.capacity();
}

void BrickLayout::setRuns(std::vector<size_t> start) {
  rankStart = std::move(start);
  firstCodes.assign(rankStart.size(), ~uint64_t{0});
  globalStart.assign(rankStart.begin(), rankStart.end());
  firstCodes[0] = 0;
  for (size_t r = 1; r + 1 < rankStart.size(); ++r)
    if (rankStart[r] < codes.size()) firstCodes[r] = codes[rankStart[r]];
}

int BrickLayout::ownerOf(size_t i) const {
  return static_cast<int>(std::upper_bound(rankStart.begin(), rankStart.end(), i) -
                          rankStart.begin()) -
         1;
}

int BrickLayout::ownerOfCode(uint64_t code) const {
  // The last rank whose range starts at or before the code (empty runs share their start).
  const auto last = firstCodes.end() - 1;
  return static_cast<int>(std::upper_bound(firstCodes.begin(), last, code) - firstCodes.begin()) -
         1;
}

int BrickLayout::mayOwn(uint64_t code, int me) const {
  const int64_t at = find(code);
  if (at >= 0) return ownerOf(static_cast<size_t>(at));
  if (whole()) return -1;
  const int owner = ownerOfCode(code);
  return owner == me ? -1 : owner;
}

int BrickLayout::neighbourOwner(uint64_t code, int me) const {
  const int64_t at = find(code);
  if (at >= 0) return ownerOf(static_cast<size_t>(at));
  return borderKnown ? -1 : mayOwn(code, me);
}

std::vector<uint64_t> neighbourCodes(uint64_t code) {
  std::vector<uint64_t> out;
  out.reserve(26);
  const BrickCoord c = mortonDecode(code);
  for (int o = 0; o < 27; ++o) {
    const BrickCoord n = c + BrickCoord(o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1);
    if (o != 13 && (n.array() >= 0).all()) out.push_back(mortonEncode(n));
  }
  return out;
}

BrickLayout directoryOf(const BrickLayout& whole, int me) {
  std::vector<size_t> held;
  for (size_t i = whole.rankStart[me]; i < whole.rankStart[me + 1]; ++i) {
    held.push_back(i);
    for (uint64_t n : neighbourCodes(whole.codes[i])) {
      const int64_t at = whole.find(n);
      if (at >= 0 && whole.ownerOf(static_cast<size_t>(at)) != me)
        held.push_back(static_cast<size_t>(at));
    }
  }
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  BrickLayout d;
  d.grid = whole.grid;
  for (size_t i : held) d.codes.push_back(whole.codes[i]), d.work.push_back(whole.work[i]);
  d.firstCodes = whole.firstCodes;
  d.globalStart = whole.globalStart;
  d.rankStart = runsOf(d.codes, d.firstCodes);
  return d;
}

std::vector<size_t> runsOf(const std::vector<uint64_t>& codes,
                           const std::vector<uint64_t>& firstCodes) {
  std::vector<size_t> start(firstCodes.size(), codes.size());
  for (size_t r = 0; r + 1 < firstCodes.size(); ++r)
    start[r] = static_cast<size_t>(std::lower_bound(codes.begin(), codes.end(), firstCodes[r]) -
                                   codes.begin());
  start[0] = 0;
  return start;
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
