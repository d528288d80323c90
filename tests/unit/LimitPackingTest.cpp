// Routing packs each end of a part's prism limits as a bit a triangle where it is the part's
// outermost value, and the value where not (decision 54): against the limits given, in floats
// and doubles, with truncated ends, signed zeros and NaN among them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "../common/PackedRoundTrip.h"
#include "route/LimitPacking.h"

using namespace rangefuse;
using namespace rangefuse::internal;

namespace {

using Limits = std::vector<std::array<double, 2>>;

/// x rounded to a float. Through a volatile: GCC 12.2 drops the rounding of both values of a
/// pair built as {double(float(a)), double(float(b))} at -O2 (the test failed on that).
double throughFloat(double x) {
  volatile float f = static_cast<float>(x);
  return f;
}

/// The picked limits as unpacking must give them: rounded to floats when `single`.
Limits picked(const Limits& limits, const std::vector<uint32_t>& pick, bool single) {
  Limits out;
  if (limits.empty()) return out;  // a scan without limits packs none, whatever is picked
  for (uint32_t t : pick) {
    std::array<double, 2> l = limits[t];
    if (single) l = {throughFloat(l[0]), throughFloat(l[1])};
    out.push_back(l);
  }
  return out;
}

bool sameBits(const Limits& a, const Limits& b) {
  // memcmp wants pointers even for no bytes, and an empty vector may have none.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

/// Packs after a marker and reads back; gives the bytes the limits took.
size_t packedBytes(const Limits& limits, const std::vector<uint32_t>& pick, bool single) {
  std::vector<char> buf(7, 'x');
  packLimits(buf, limits, pick, single);
  const Limits back = test::unpackedFrom<std::array<double, 2>>(
      buf, 7, [=](auto& b, size_t& p, Limits& l) { unpackLimits(b, p, l, single); },
      [=](auto& b, size_t& p) { skipLimits(b, p, single); });
  EXPECT_TRUE(sameBits(back, picked(limits, pick, single))) << single;
  return buf.size() - 7;
}

}  // namespace

TEST(LimitPacking, WholeEnvelopesTakeTwoBitsATriangle) {
  const double eps = 0.02;
  for (const bool single : {true, false}) {
    const Limits limits(1000, {-eps, eps});
    std::vector<uint32_t> pick(1000);
    for (uint32_t t = 0; t < 1000; ++t) pick[t] = 999 - t;
    const size_t real = single ? sizeof(float) : sizeof(double);
    EXPECT_EQ(packedBytes(limits, pick, single), 8 + 2 * (real + 125)) << single;
  }
}

TEST(LimitPacking, TruncatedEndsAndOddValuesComeBackBitForBit) {
  const double eps = 0.02;
  std::mt19937 random(6);
  std::uniform_real_distribution<double> inside(0.001, eps);
  for (const bool single : {true, false}) {
    Limits limits(997, {-eps, eps});
    size_t own = 0;  // ends that are not the part's outermost value
    for (auto& l : limits)
      for (int end : {0, 1})
        if (random() % 10 == 0) l[end] = (end == 0 ? -1 : 1) * inside(random), ++own;
    limits[3] = {-0.0, 0.0};  // zeros of either sign are values of their own
    limits[4] = {0.0, -0.0};
    limits[5][1] = std::numeric_limits<double>::quiet_NaN();
    own += 5;
    std::vector<uint32_t> pick(limits.size());
    for (uint32_t t = 0; t < pick.size(); ++t) pick[t] = t;
    const size_t real = single ? sizeof(float) : sizeof(double);
    EXPECT_EQ(packedBytes(limits, pick, single), 8 + 2 * (real + 125) + own * real) << single;
    // A part of them, in any order.
    const std::vector<uint32_t> some = {900, 4, 3, 5, 17, 17, 0};
    packedBytes(limits, some, single);
  }
}

TEST(LimitPacking, NoLimitsPackAsTheCountAlone) {
  EXPECT_EQ(packedBytes({}, {0, 1, 2}, true), 8u);
  EXPECT_EQ(packedBytes({{-1, 1}}, {}, false), 8u);
}
