#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "surface/OrderStatistics.h"

namespace rangefuse::internal {
namespace {

/// The k-th smallest by sorting a copy: the brute-force answer.
double sortedAt(std::vector<double> v, size_t k) {
  std::sort(v.begin(), v.end());
  return v[k];
}

/// Random sets the way a frame's steps come: spread over binades, on few repeated values (a
/// depth camera's quantised steps), with zeros, ties and an infinity; small and large.
std::vector<std::vector<double>> sets() {
  std::mt19937_64 rng(5);
  std::vector<std::vector<double>> out;
  for (size_t n : {1, 2, 7, 2047, 2048, 5000, 300000}) {
    std::lognormal_distribution<double> spread(-6, 2);
    std::uniform_int_distribution<int> step(0, 12);
    std::vector<double> wide(n), quantised(n), flat(n, 0.25);
    for (size_t i = 0; i < n; ++i) wide[i] = spread(rng), quantised[i] = 0.001 * step(rng);
    if (n > 3) wide[1] = 0, wide[2] = INFINITY, wide[3] = wide[0];
    out.push_back(wide), out.push_back(quantised), out.push_back(flat);
  }
  return out;
}

TEST(OrderStatistics, NthSmallestIsTheSortedListsEntry) {
  for (const auto& v : sets())
    for (size_t k : {size_t(0), v.size() / 2, v.size() * 9 / 10, v.size() - 1}) {
      SCOPED_TRACE("n " + std::to_string(v.size()) + ", k " + std::to_string(k));
      EXPECT_EQ(nthSmallest(v, k), sortedAt(v, k));
    }
}

TEST(OrderStatistics, TwoAtOnceAreEachTheSortedListsEntry) {
  // Pairs in one digit and in two, either order, and the same k twice; every k below n.
  for (const auto& v : sets()) {
    const size_t n = v.size();
    for (const auto& [k1, k2] : {std::pair{n / 2, n * 9 / 10}, std::pair{n - 1, size_t(0)},
                                 std::pair{n / 2, n / 2}, std::pair{n / 3, (n / 3 + 1) % n}}) {
      SCOPED_TRACE("n " + std::to_string(n) + ", k " + std::to_string(k1) + " " +
                   std::to_string(k2));
      const std::array<double, 2> both = nthSmallestTwo(v, k1, k2);
      EXPECT_EQ(both[0], sortedAt(v, k1));
      EXPECT_EQ(both[1], sortedAt(v, k2));
    }
  }
}

TEST(OrderStatistics, SumOfSmallestSquaresMatchesTheSortedSum) {
  for (auto v : sets()) {
    for (double& x : v) x = std::min(x, 1e3);  // a square that is finite
    const size_t count = v.size() * 9 / 10;
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    double expected = 0;
    for (size_t i = 0; i < count; ++i) expected += sorted[i] * sorted[i];
    EXPECT_NEAR(sumOfSmallestSquares(v, count), expected, 1e-12 * std::max(1.0, expected))
        << "n " << v.size();
  }
}

TEST(OrderStatistics, LeavesTheValuesAsTheyWere) {
  const std::vector<double> v = sets()[18], before = v;
  nthSmallest(v, v.size() / 2);
  nthSmallestTwo(v, v.size() / 2, v.size() / 5);
  sumOfSmallestSquares(v, v.size() / 3);
  EXPECT_EQ(v, before);
}

}  // namespace
}  // namespace rangefuse::internal
