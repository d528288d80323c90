// What a rank's brick directory must hold, against the whole list planned on one rank.
#pragma once

#include <gtest/gtest.h>

#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse::test {

/// `got` is rank me's part of `whole`: its bricks, those bordering them, every rank's range.
inline void expectDirectory(const BrickLayout& got, const BrickLayout& whole, int me) {
  const BrickLayout want = directoryOf(whole, me);
  EXPECT_EQ(got.codes, want.codes);
  EXPECT_EQ(got.work, want.work);
  EXPECT_EQ(got.rankStart, want.rankStart);
  EXPECT_EQ(got.firstCodes, whole.firstCodes);
  EXPECT_EQ(got.globalStart, whole.globalStart);
  EXPECT_EQ(got.totalBricks(), whole.codes.size());
}

}  // namespace rangefuse::test
