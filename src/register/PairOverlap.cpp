#include "rangefuse/register/PairOverlap.h"

#include <map>
#include <set>
#include <utility>

namespace rangefuse {

std::vector<PairOverlap> pairOverlaps(const std::vector<RegistrationStep>& steps) {
  using Key = std::pair<uint32_t, uint32_t>;
  std::map<Key, PairOverlap> pairs;
  std::set<size_t> started;
  std::map<size_t, const RegistrationStep*> lastOf;
  for (const RegistrationStep& s : steps) {
    if (s.algorithm != FitAlgorithm::Joint) continue;
    lastOf[s.scan] = &s;
    if (!started.insert(s.scan).second) continue;
    for (const auto& [t, points] : s.overlap) {
      PairOverlap& p = pairs[{static_cast<uint32_t>(s.scan), t}];
      p.a = static_cast<uint32_t>(s.scan), p.b = t, p.first = points;
    }
  }
  for (const auto& [scan, step] : lastOf)
    for (const auto& [t, points] : step->overlap) {
      PairOverlap& p = pairs[{static_cast<uint32_t>(scan), t}];
      p.a = static_cast<uint32_t>(scan), p.b = t, p.last = points;
    }
  std::vector<PairOverlap> out;
  for (const auto& [key, p] : pairs) out.push_back(p);
  return out;
}

size_t pairsLosing(const std::vector<PairOverlap>& pairs, double share) {
  size_t n = 0;
  for (const PairOverlap& p : pairs)
    n += p.first >= kOverlapPoints && static_cast<double>(p.last) < share * p.first;
  return n;
}

std::pair<size_t, size_t> overlappingPairs(const std::vector<PairOverlap>& pairs) {
  std::pair<size_t, size_t> n{0, 0};
  for (const PairOverlap& p : pairs) {
    n.first += p.first >= kOverlapPoints;
    n.second += p.last >= kOverlapPoints;
  }
  return n;
}

}  // namespace rangefuse
