#include "OrderStatistics.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <utility>

namespace rangefuse::internal {
namespace {

constexpr int kDigitBits = 11;
constexpr size_t kBuckets = size_t(1) << kDigitBits;
constexpr size_t kSortBelow = 2048;  // fewer values than this are selected by comparison

uint64_t keyOf(double v) {
  uint64_t key;
  std::memcpy(&key, &v, sizeof key);
  return key;
}

uint64_t keyOf(uint64_t key) {
  return key;
}

double valueOf(uint64_t key) {
  double v;
  std::memcpy(&v, &key, sizeof v);
  return v;
}

/// Where the digit that tells keys from `lo` to `hi` apart starts: they share every bit above
/// the highest one where lo and hi differ (-1 when lo == hi).
int digitShift(uint64_t lo, uint64_t hi) {
  if (lo == hi) return -1;
  const int bits = 64 - __builtin_clzll(lo ^ hi);
  return std::max(0, bits - kDigitBits);
}

/// Each digit's count at `shift` over `values` (of values or keys, read through keyOf), four
/// counters a digit taken in turn: a depth camera's steps repeat a few values, and counting
/// them on one counter would wait on each previous count.
template <class T>
std::vector<uint32_t> digitCounts(const std::vector<T>& values, int shift) {
  std::vector<uint32_t> count(4 * kBuckets, 0);
  const size_t n = values.size();
  auto digit = [&](T v) { return (keyOf(v) >> shift) & (kBuckets - 1); };
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (size_t j = 0; j < 4; ++j) ++count[j * kBuckets + digit(values[i + j])];
  for (; i < n; ++i) ++count[digit(values[i])];
  return count;
}

/// The digit holding the k-th smallest, with k made its rank among that digit's keys.
size_t digitHolding(const std::vector<uint32_t>& count, size_t& k) {
  for (size_t d = 0;; ++d) {
    const size_t inD =
        count[d] + count[kBuckets + d] + count[2 * kBuckets + d] + count[3 * kBuckets + d];
    if (k < inD) return d;
    k -= inD;
  }
}

/// The keys of `values` whose digit at `shift` is d.
template <class T>
std::vector<uint64_t> keysWithDigit(const std::vector<T>& values, int shift, size_t d) {
  std::vector<uint64_t> kept;
  for (T v : values)
    if (((keyOf(v) >> shift) & (kBuckets - 1)) == d) kept.push_back(keyOf(v));
  return kept;
}

/// The keys (of values or keys) whose digit at `shift` is the one holding the k-th smallest,
/// with k made their own rank among them.
template <class T>
std::vector<uint64_t> bucketHolding(const std::vector<T>& values, int shift, size_t& k) {
  return keysWithDigit(values, shift, digitHolding(digitCounts(values, shift), k));
}

/// The least and greatest key of `values`.
template <class T>
std::pair<uint64_t, uint64_t> keyRange(const std::vector<T>& values) {
  uint64_t lo = ~uint64_t{0}, hi = 0;
  for (T v : values) lo = std::min(lo, keyOf(v)), hi = std::max(hi, keyOf(v));
  return {lo, hi};
}

/// The k-th smallest of `keys`, by their digits until few are left.
double smallestAmongKeys(std::vector<uint64_t> keys, size_t k) {
  while (keys.size() >= kSortBelow) {
    const auto [lo, hi] = keyRange(keys);
    const int shift = digitShift(lo, hi);
    if (shift < 0) return valueOf(keys[0]);
    keys = bucketHolding(keys, shift, k);
  }
  std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(k), keys.end());
  return valueOf(keys[k]);
}

/// The k-th smallest of a copy of `values`, by comparison (few values).
double smallestByComparison(std::vector<double> copy, size_t k) {
  std::nth_element(copy.begin(), copy.begin() + static_cast<std::ptrdiff_t>(k), copy.end());
  return copy[k];
}

}  // namespace

// A non-negative double's bits, read as an unsigned integer, order as the double does, so the
// digits below the bits all keys share narrow the search to the k-th's digit: the values are
// read twice (range, then counts) and only the k-th's digit's are copied.
double nthSmallest(const std::vector<double>& values, size_t k) {
  if (values.size() < kSortBelow) return smallestByComparison(values, k);
  const auto [lo, hi] = keyRange(values);
  const int shift = digitShift(lo, hi);
  if (shift < 0) return values[0];
  std::vector<uint64_t> keys = bucketHolding(values, shift, k);  // k becomes its rank there
  return smallestAmongKeys(std::move(keys), k);
}

std::array<double, 2> nthSmallestTwo(const std::vector<double>& values, size_t k1, size_t k2) {
  if (values.size() < kSortBelow)
    return {smallestByComparison(values, k1), smallestByComparison(values, k2)};
  const auto [lo, hi] = keyRange(values);
  const int shift = digitShift(lo, hi);
  if (shift < 0) return {values[0], values[0]};
  // One range and one count serve both; their digits' keys are copied in one pass.
  const std::vector<uint32_t> count = digitCounts(values, shift);
  const size_t d1 = digitHolding(count, k1), d2 = digitHolding(count, k2);
  if (d1 == d2) {
    std::vector<uint64_t> keys = keysWithDigit(values, shift, d1);
    return {smallestAmongKeys(keys, k1), smallestAmongKeys(std::move(keys), k2)};
  }
  std::vector<uint64_t> keys1, keys2;
  for (double v : values) {
    const size_t d = (keyOf(v) >> shift) & (kBuckets - 1);
    if (d == d1) keys1.push_back(keyOf(v));
    if (d == d2) keys2.push_back(keyOf(v));
  }
  return {smallestAmongKeys(std::move(keys1), k1), smallestAmongKeys(std::move(keys2), k2)};
}

double sumOfSmallestSquares(const std::vector<double>& values, size_t count) {
  return count == 0 ? 0 : sumOfSmallestSquares(values, count, nthSmallest(values, count - 1));
}

double sumOfSmallestSquares(const std::vector<double>& values, size_t count, double last) {
  if (count == 0) return 0;
  // The `count` smallest are every value below the count-th smallest, then as many copies of
  // it as make up the count.
  double sum = 0;
  size_t below = 0;
  for (double v : values)
    if (v < last) sum += v * v, ++below;
  return sum + static_cast<double>(count - below) * (last * last);
}

}  // namespace rangefuse::internal
