#include "rangefuse/register/Stragglers.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace rangefuse {
namespace {

double median(std::vector<double> v) {
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2) return v[mid];
  return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + mid));
}

constexpr double kScore = 5;               // robust deviations above the median residual
constexpr double kAbove = 1.25;            // ... and this share of it
constexpr double kOverlapShare = 1 / 3.0;  // correspondences against the median scan's

}  // namespace

std::vector<ScanStanding> lastStandings(const std::vector<RegistrationStep>& steps) {
  std::map<size_t, ScanStanding> last;
  for (const RegistrationStep& s : steps)
    if (s.algorithm != FitAlgorithm::Others)
      last[s.scan] = ScanStanding{s.scan, s.rms, s.correspondences, 0, 1, s.loose};
  std::vector<ScanStanding> out;
  for (const auto& [scan, standing] : last) out.push_back(standing);
  if (out.empty()) return out;
  std::vector<double> rms, overlap;
  for (const ScanStanding& s : out) rms.push_back(s.rms), overlap.push_back(s.correspondences);
  const double m = median(rms), o = median(overlap);
  std::vector<double> deviation;
  for (double r : rms) deviation.push_back(std::abs(r - m));
  const double spread = 1.4826 * median(deviation);
  for (ScanStanding& s : out) {
    // Every other scan alike (no spread): any scan above them is out of line.
    s.rmsScore = spread > 0 ? (s.rms - m) / spread : s.rms > m ? INFINITY : 0;
    s.overlapShare = o > 0 ? s.correspondences / o : 1;
  }
  return out;
}

std::vector<ScanStanding> findStragglers(const std::vector<ScanStanding>& standings) {
  std::vector<ScanStanding> out;
  if (standings.size() < kFewestJudged) return out;
  std::vector<double> rms;
  for (const ScanStanding& s : standings) rms.push_back(s.rms);
  const double m = median(rms);
  for (const ScanStanding& s : standings)
    if ((s.rmsScore > kScore && s.rms > kAbove * m) || s.overlapShare < kOverlapShare)
      out.push_back(s);
  return out;
}

std::vector<RegistrationStep> findOthersStragglers(const std::vector<RegistrationStep>& steps,
                                                   double voxel) {
  const std::vector<ScanStanding> standings = lastStandings(steps);
  const std::vector<ScanStanding> loose = findLooseScans(standings),
                                  named = findStragglers(standings);
  auto among = [](const std::vector<ScanStanding>& list, size_t scan) {
    return std::any_of(list.begin(), list.end(),
                       [&](const ScanStanding& s) { return s.scan == scan; });
  };
  std::map<size_t, RegistrationStep> out;
  for (const RegistrationStep& s : steps)
    if (s.algorithm == FitAlgorithm::Others && s.othersMotion > kOthersMotion * voxel &&
        !among(loose, s.scan) && !among(named, s.scan))
      out[s.scan] = s;
  std::vector<RegistrationStep> list;
  for (const auto& [scan, step] : out) list.push_back(step);
  return list;
}

std::vector<ScanStanding> findLooseScans(const std::vector<ScanStanding>& standings) {
  std::vector<ScanStanding> out;
  for (const ScanStanding& s : standings)
    if (s.loose.hold < kLooseHold) out.push_back(s);
  return out;
}

}  // namespace rangefuse
