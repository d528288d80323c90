// A compact scan's normals go as 32-bit octahedral codes and its confidences as 16-bit
// fractions (decision 58): against the directions and values given, to the stated bounds, and
// every code comes back from the value it stands for, so packing a compact scan loses nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "route/CompactAttributes.h"

using namespace rangefuse::internal;

namespace {

/// The angle between two unit vectors, exact for small angles.
double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// A code of octahedral steps u and v (each in [-32767, 32767]).
uint32_t codeOf(int u, int v) {
  return static_cast<uint16_t>(static_cast<int16_t>(u)) |
         uint32_t(static_cast<uint16_t>(static_cast<int16_t>(v))) << 16;
}

}  // namespace

TEST(CompactAttributes, NormalsComeBackWithinTheBoundAndOnceRoundedStay) {
  std::mt19937_64 random(11);
  std::normal_distribution<double> gauss;
  double worst = 0;
  for (int k = 0; k < 1000000; ++k) {
    const Eigen::Vector3d n =
        Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    const Eigen::Vector3d q = quantisedNormal(n);
    worst = std::max(worst, angleBetween(n, q));
    EXPECT_NEAR(q.norm(), 1, 1e-15);
    ASSERT_EQ(quantisedNormal(q), q) << n.transpose();
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(worst, 3e-5) << "the bound is far from what 16 bits give";
}

TEST(CompactAttributes, EveryCodeComesBackFromItsNormal) {
  // The square's edges and diagonals (where the lower half folds), the axes, and random codes.
  std::vector<uint32_t> codes;
  for (int s = -32767; s <= 32767; s += 7)
    for (const auto& [u, v] : {std::pair{s, 32767}, std::pair{s, -32767}, std::pair{32767, s},
                               std::pair{-32767, s}, std::pair{s, 32767 - std::abs(s)},
                               std::pair{s, std::abs(s) - 32767}, std::pair{s, 0}, std::pair{0, s}})
      codes.push_back(codeOf(u, v));
  std::mt19937 random(12);
  std::uniform_int_distribution<int> step(-32767, 32767);
  for (int k = 0; k < 1000000; ++k) codes.push_back(codeOf(step(random), step(random)));
  for (uint32_t c : codes) ASSERT_EQ(normalCode(normalOf(c)), c) << std::hex << c;
}

TEST(CompactAttributes, AxesAreExactAndZeroStaysZero) {
  for (int a = 0; a < 3; ++a)
    for (double s : {1.0, -1.0}) {
      const Eigen::Vector3d axis = s * Eigen::Vector3d::Unit(a);
      EXPECT_EQ(quantisedNormal(axis), axis) << axis.transpose();
    }
  EXPECT_EQ(quantisedNormal(Eigen::Vector3d::Zero()), Eigen::Vector3d::Zero());
  EXPECT_EQ(quantisedNormal(Eigen::Vector3d(NAN, 0, 1)), Eigen::Vector3d::Zero());
  EXPECT_NE(normalCode(Eigen::Vector3d::Zero()), normalCode(Eigen::Vector3d(0, 0, 1)));
}

TEST(CompactAttributes, ConfidencesComeBackWithinHalfAStep) {
  for (uint32_t c = 0; c <= 0xffff; ++c)
    ASSERT_EQ(confidenceCode(confidenceOf(static_cast<uint16_t>(c))), c);
  std::mt19937_64 random(13);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int k = 0; k < 100000; ++k) {
    const double c = unit(random);
    EXPECT_LE(std::abs(quantisedConfidence(c) - c), 0.5 / 65535 + 1e-16);
  }
  EXPECT_EQ(quantisedConfidence(0), 0);
  EXPECT_EQ(quantisedConfidence(1), 1);
  EXPECT_EQ(quantisedConfidence(1 + 1e-12), 1);  // a dot product of unit vectors past 1
  EXPECT_EQ(quantisedConfidence(NAN), 0);
}
