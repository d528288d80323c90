// A packed vector read back: what routing's packing tests share.
#pragma once

#include <gtest/gtest.h>

#include <vector>

namespace rangefuse::test {

/// Reads the vector packed into buf from `from` on with `unpack`, and checks that unpacking and
/// `skip` both end at buf's end. Returns what was unpacked, for the caller to compare.
template <class T, class Unpack, class Skip>
std::vector<T> unpackedFrom(const std::vector<char>& buf, size_t from, Unpack unpack, Skip skip) {
  size_t pos = from, skipped = from;
  std::vector<T> back;
  unpack(buf, pos, back);
  skip(buf, skipped);
  EXPECT_EQ(pos, buf.size());
  EXPECT_EQ(skipped, buf.size());
  return back;
}

}  // namespace rangefuse::test
