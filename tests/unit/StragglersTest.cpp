#include <gtest/gtest.h>

#include "rangefuse/register/Stragglers.h"

namespace rangefuse {
namespace {

RegistrationStep fit(size_t scan, double rms, uint64_t correspondences, bool applied = true) {
  RegistrationStep s;
  s.scan = scan, s.rms = rms, s.correspondences = correspondences, s.applied = applied;
  return s;
}

/// Eight scans that fit alike (residual 0.10-0.107, 1000-1070 correspondences), each fitted
/// twice: only the last fit counts.
std::vector<RegistrationStep> alike() {
  std::vector<RegistrationStep> steps;
  for (size_t k = 0; k < 8; ++k) steps.push_back(fit(k, 1.0, 10));
  for (size_t k = 0; k < 8; ++k) steps.push_back(fit(k, 0.1 + 0.001 * k, 1000 + 10 * k));
  return steps;
}

std::vector<size_t> flagged(const std::vector<RegistrationStep>& steps) {
  std::vector<size_t> out;
  for (const ScanStanding& s : findStragglers(lastStandings(steps))) out.push_back(s.scan);
  return out;
}

TEST(Stragglers, ScansThatFitAlikeFlagNone) {
  EXPECT_TRUE(flagged(alike()).empty());
  const std::vector<ScanStanding> s = lastStandings(alike());
  ASSERT_EQ(s.size(), 8u);
  EXPECT_DOUBLE_EQ(s[3].rms, 0.103);
  EXPECT_EQ(s[3].correspondences, 1030u);
}

TEST(Stragglers, AHighResidualOrALostOverlapIsFlagged) {
  std::vector<RegistrationStep> steps = alike();
  steps.push_back(fit(2, 0.4, 1020));   // far off the others' residual
  steps.push_back(fit(5, 0.104, 300));  // a third of the others' overlap, lost
  EXPECT_EQ(flagged(steps), (std::vector<size_t>{2, 5}));
  // 20 % above the median: inside the spread a noisy set may show, not flagged.
  steps = alike();
  steps.push_back(fit(6, 0.124, 1060));
  EXPECT_TRUE(flagged(steps).empty());
}

TEST(Stragglers, NoSpreadFlagsAnyScanClearlyAbove) {
  std::vector<RegistrationStep> steps;
  for (size_t k = 0; k < 6; ++k) steps.push_back(fit(k, 0.1, 1000));
  steps.push_back(fit(6, 0.2, 1000));
  EXPECT_EQ(flagged(steps), (std::vector<size_t>{6}));
}

TEST(Stragglers, TooFewScansFlagNoneAndAFitTooSmallToApplyCounts) {
  std::vector<RegistrationStep> steps = {fit(0, 0.1, 1000), fit(1, 0.1, 1000), fit(2, 5, 10)};
  EXPECT_TRUE(flagged(steps).empty());
  steps = alike();
  steps.push_back(fit(3, 0.1, 12, false));  // too few correspondences to move it: its overlap
  EXPECT_EQ(flagged(steps), (std::vector<size_t>{3}));
}

}  // namespace
TEST(Stragglers, AScanTheOthersAloneWouldMoveIsNamedUnlessLooseOrNamedAlready) {
  // Voxel 0.5: the others' fit names a scan it moves more than 0.12 voxel (0.06).
  auto others = [](size_t scan, double motion) {
    RegistrationStep s;
    s.algorithm = FitAlgorithm::Others, s.scan = scan, s.othersMotion = motion;
    s.rms = 0.1, s.correspondences = 1000;
    return s;
  };
  std::vector<RegistrationStep> steps = alike();
  steps[15].loose.hold = 0.5 * kLooseHold;  // scan 7's last joint fit left it loose
  steps.push_back(fit(2, 0.4, 1020));       // scan 2 is named by its residual already
  for (const auto& [scan, motion] : std::vector<std::pair<size_t, double>>{
           {1, 0.07}, {2, 0.2}, {4, 0.05}, {6, 0.0601}, {7, 0.3}})
    steps.push_back(others(scan, motion));
  std::vector<size_t> named;
  for (const RegistrationStep& s : findOthersStragglers(steps, 0.5)) named.push_back(s.scan);
  EXPECT_EQ(named, (std::vector<size_t>{1, 6}));
  // The check's steps are not registration fits: the standings do not see them.
  EXPECT_EQ(lastStandings(steps).size(), 8u);
  EXPECT_DOUBLE_EQ(lastStandings(steps)[1].rms, 0.101);
}

}  // namespace rangefuse
