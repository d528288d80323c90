// The memory ledger keeps each part's bytes at the moment their sum peaked.
#include <gtest/gtest.h>

#include <vector>

#include "rangefuse/core/MemoryLedger.h"

using namespace rangefuse;

TEST(MemoryLedger, KeepsThePartsAsTheyWereWhenTheirSumPeaked) {
  MemoryLedger ledger;
  ledger.set(Held::keptScans, 100);
  ledger.set(Held::field, 50);        // 150: the peak so far
  ledger.set(Held::keptScans, 20);    // 70
  ledger.set(Held::routedScans, 60);  // 130: below the peak, which stays as it was
  EXPECT_EQ(ledger.peakTotal(), 150u);
  EXPECT_EQ(ledger.atPeak()[size_t(Held::keptScans)], 100u);
  EXPECT_EQ(ledger.atPeak()[size_t(Held::routedScans)], 0u);
  ledger.set(Held::integrator, 30);  // 160: a new peak, with every part as it is now
  EXPECT_EQ(ledger.peakTotal(), 160u);
  EXPECT_EQ(ledger.atPeak()[size_t(Held::keptScans)], 20u);
  EXPECT_EQ(ledger.atPeak()[size_t(Held::routedScans)], 60u);
  EXPECT_EQ(ledger.atPeak()[size_t(Held::field)], 50u);
}

TEST(MemoryLedger, StartsFromWhatTheProcessHolds) {
  MemoryLedger ledger;
  ledger.set(Held::field, 1 << 20);
  ledger.start();
  EXPECT_EQ(ledger.peakTotal(), 0u);
  // A vector of 64 MiB, touched, shows in what the process holds.
  const uint64_t before = residentBytes();
  std::vector<char> touched(64 << 20, 1);
  EXPECT_GT(ledger.processBytes(), 0u);
  EXPECT_GE(residentBytes(), before + (60u << 20)) << int(touched[12345]);
}
