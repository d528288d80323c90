#include "OrderStatistics.h"

#include <algorithm>
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

/// The keys (of values or keys, read through keyOf) whose digit at `shift` is the one holding
/// the k-th smallest, with k made their own rank among them.
template <class T>
std::vector<uint64_t> bucketHolding(const std::vector<T>& values, int shift, size_t& k) {
  // Four counts a digit, taken in turn: a depth camera's steps repeat a few values, and
  // counting them on one counter would wait on each previous count.
  std::vector<uint32_t> count(4 * kBuckets, 0);
  const size_t n = values.size();
  auto digit = [&](T v) { return (keyOf(v) >> shift) & (kBuckets - 1); };
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (size_t j = 0; j < 4; ++j) ++count[j * kBuckets + digit(values[i + j])];
  for (; i < n; ++i) ++count[digit(values[i])];
  size_t d = 0, inD = 0;
  for (;; ++d) {
    inD = count[d] + count[kBuckets + d] + count[2 * kBuckets + d] + count[3 * kBuckets + d];
    if (k < inD) break;
    k -= inD;
  }
  std::vector<uint64_t> kept;
  kept.reserve(inD);
  for (T v : values)
    if (digit(v) == d) kept.push_back(keyOf(v));
  return kept;
}

/// The least and greatest key of `values`.
template <class T>
std::pair<uint64_t, uint64_t> keyRange(const std::vector<T>& values) {
  uint64_t lo = ~uint64_t{0}, hi = 0;
  for (T v : values) lo = std::min(lo, keyOf(v)), hi = std::max(hi, keyOf(v));
  return {lo, hi};
}

}  // namespace

double nthSmallest(const std::vector<double>& values, size_t k) {
  // A non-negative double's bits, read as an unsigned integer, order as the double does, so
  // the digits below the bits all keys share narrow the search to the k-th's digit: the
  // values are read twice (range, then counts) and only the k-th's digit's are copied.
  if (values.size() < kSortBelow) {
    std::vector<double> copy = values;
    std::nth_element(copy.begin(), copy.begin() + static_cast<std::ptrdiff_t>(k), copy.end());
    return copy[k];
  }
  const auto [lo, hi] = keyRange(values);
  int shift = digitShift(lo, hi);
  if (shift < 0) return values[0];
  std::vector<uint64_t> keys = bucketHolding(values, shift, k);
  while (keys.size() >= kSortBelow) {
    const auto [klo, khi] = keyRange(keys);
    if ((shift = digitShift(klo, khi)) < 0) return valueOf(keys[0]);
    keys = bucketHolding(keys, shift, k);
  }
  std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(k), keys.end());
  return valueOf(keys[k]);
}

double sumOfSmallestSquares(const std::vector<double>& values, size_t count) {
  if (count == 0) return 0;
  // The `count` smallest are every value below the count-th smallest, then as many copies of
  // it as make up the count.
  const double last = nthSmallest(values, count - 1);
  double sum = 0;
  size_t below = 0;
  for (double v : values)
    if (v < last) sum += v * v, ++below;
  return sum + static_cast<double>(count - below) * (last * last);
}

}  // namespace rangefuse::internal
