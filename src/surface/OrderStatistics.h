// Order statistics of large sets of non-negative numbers (steps between grid neighbours,
// second differences of depth), found by their bits rather than by comparison sorting: the
// medians a frame's preparation takes over some 300 000 values each.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace rangefuse::internal {

/// The k-th smallest (from 0) of `values`, all of which must be >= 0 (or +0): exactly the value
/// std::nth_element would place at k. `values` is left as it was. k < values.size().
double nthSmallest(const std::vector<double>& values, size_t k);

/// The k1-th and k2-th smallest of `values`, each exactly as nthSmallest gives it, for about the
/// cost of one: the values' range and digit counts serve both.
std::array<double, 2> nthSmallestTwo(const std::vector<double>& values, size_t k1, size_t k2);

/// The sum of the squares of the `count` smallest of `values` (all >= 0, count <= size), added
/// in the order of `values`: the same bits however the smallest were found.
double sumOfSmallestSquares(const std::vector<double>& values, size_t count);
/// The same, given `last`, the (count - 1)-th smallest (nthSmallest's answer).
double sumOfSmallestSquares(const std::vector<double>& values, size_t count, double last);

}  // namespace rangefuse::internal
