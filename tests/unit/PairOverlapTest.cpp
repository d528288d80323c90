#include <gtest/gtest.h>

#include "rangefuse/register/PairOverlap.h"

namespace rangefuse {
namespace {

RegistrationStep jointFit(size_t scan, std::vector<std::pair<uint32_t, uint64_t>> overlap) {
  RegistrationStep s;
  s.algorithm = FitAlgorithm::Joint;
  s.scan = scan;
  s.overlap = std::move(overlap);
  return s;
}

TEST(PairOverlap, FirstAndLastJointStepsOfEveryPair) {
  RegistrationStep incremental;
  incremental.scan = 0;
  incremental.overlap = {{1, 999}};  // not a joint step: ignored
  const std::vector<RegistrationStep> steps = {
      incremental,
      // first joint iteration: 0-1 and 0-2 overlap, 1-2 too
      jointFit(0, {{1, 100}, {2, 400}}), jointFit(1, {{2, 60}}), jointFit(2, {{3, 10}}),
      // a middle one
      jointFit(0, {{1, 1}}), jointFit(1, {}), jointFit(2, {}), jointFit(3, {}),
      // the last: 0-2 lost, 1-2 grew, 0-1 nearly kept, 2-3 a fringe
      jointFit(0, {{1, 90}}), jointFit(1, {{2, 80}}), jointFit(2, {{3, 2}}), jointFit(3, {})};
  const std::vector<PairOverlap> pairs = pairOverlaps(steps);
  ASSERT_EQ(pairs.size(), 4u);
  EXPECT_EQ(pairs[0].a, 0u);
  EXPECT_EQ(pairs[0].b, 1u);
  EXPECT_EQ(pairs[0].first, 100u);
  EXPECT_EQ(pairs[0].last, 90u);
  EXPECT_EQ(pairs[1].b, 2u);
  EXPECT_EQ(pairs[1].first, 400u);
  EXPECT_EQ(pairs[1].last, 0u);
  EXPECT_EQ(pairs[2].a, 1u);
  EXPECT_EQ(pairs[2].first, 60u);
  EXPECT_EQ(pairs[2].last, 80u);
  EXPECT_EQ(pairs[3].first, 10u);
  EXPECT_EQ(pairs[3].last, 2u);
  // 2-3 overlaps too little to count (under kOverlapPoints), whatever it keeps.
  EXPECT_EQ(pairsLosing(pairs, 0.5), 1u);
  EXPECT_EQ(pairsLosing(pairs, 0.95), 2u);
  EXPECT_EQ(overlappingPairs(pairs), std::make_pair(size_t{3}, size_t{2}));
}

TEST(PairOverlap, NoJointStepNoPairs) {
  RegistrationStep s;
  s.overlap = {{1, 5}};
  EXPECT_TRUE(pairOverlaps({s}).empty());
}

}  // namespace
}  // namespace rangefuse
