#include "rangefuse/route/RoutingPlan.h"

#include <algorithm>

#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {

std::vector<size_t> routingWindows(const std::vector<uint64_t>& scanBytes,
                                   const std::vector<uint8_t>& kept, int ranks, uint64_t budget) {
  std::vector<size_t> ends;
  const size_t n = scanBytes.size(), step = static_cast<size_t>(std::max(1, ranks));
  uint64_t held = 0;  // bytes of the window open so far (none at the start)
  for (size_t first = 0; first < n; first += step) {
    uint64_t round = 0;
    for (size_t i = first; i < std::min(n, first + step); ++i)
      if (!kept[i]) round += scanBytes[i];
    if (first > 0 && held + round > budget) ends.push_back(first), held = 0;
    held += round;
  }
  if (n > 0) ends.push_back(n);
  return ends;
}

std::vector<size_t> wholeScanWindows(std::vector<size_t> ends, const std::vector<size_t>& scanOf) {
  for (size_t& e : ends)
    while (e < scanOf.size() && e > 0 && scanOf[e] == scanOf[e - 1]) ++e;
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  return ends;
}

std::vector<int> assignReadersNearby(const std::vector<Eigen::Vector3d>& positions,
                                     const std::vector<uint64_t>& fileBytes, int ranks) {
  const size_t n = positions.size();
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : positions) box.extend(p);
  // Positions on a lattice of 2^20 steps an axis (a coarser one for one spread thinner).
  const double span = n == 0 ? 1 : std::max(box.sizes().maxCoeff(), 1e-300);
  std::vector<std::pair<uint64_t, size_t>> order;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = (positions[i] - box.min()) / span * double((1 << 20) - 1);
    order.emplace_back(mortonEncode(q.array().round().cast<int>().matrix()), i);
  }
  std::sort(order.begin(), order.end());
  uint64_t total = 0;
  for (uint64_t b : fileBytes) total += b + 1;  // + 1: empty files count as scans too
  std::vector<int> reader(n, 0);
  uint64_t before = 0;
  for (const auto& [code, i] : order) {
    // The rank whose share of the bytes holds the middle of this scan's.
    const double middle = before + 0.5 * double(fileBytes[i] + 1);
    reader[i] = std::min(ranks - 1, static_cast<int>(middle * ranks / double(total)));
    before += fileBytes[i] + 1;
  }
  return reader;
}

}  // namespace rangefuse
