#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <unordered_map>
#include <vector>

#include "rangefuse/volume/BrickLayout.h"
#include "rangefuse/volume/CodeIndex.h"

namespace rangefuse {
namespace {

using internal::CodeIndex;

/// Codes of random bricks in a cube of `side` bricks: neighbours' codes crowd the low bits,
/// which a poor hash would pile into few slots.
std::vector<uint64_t> randomCodes(size_t n, int side, std::mt19937& rng) {
  std::uniform_int_distribution<int> at(0, side - 1);
  std::vector<uint64_t> codes;
  for (size_t k = 0; k < n; ++k)
    codes.push_back(mortonEncode(BrickCoord(at(rng), at(rng), at(rng))));
  return codes;
}

TEST(CodeIndex, AnswersAsAMapDoesThroughSetsAndReassignments) {
  std::mt19937 rng(7);
  CodeIndex index;
  std::unordered_map<uint64_t, int64_t> truth;
  EXPECT_EQ(index.find(0), -1);                                     // empty: every code is absent
  const std::vector<uint64_t> codes = randomCodes(20000, 64, rng);  // with repeats
  for (size_t k = 0; k < codes.size(); ++k) {
    index.set(codes[k], static_cast<int64_t>(k));
    truth[codes[k]] = static_cast<int64_t>(k);
    if (k % 997 == 0) {  // growing through every size
      for (const auto& [code, local] : truth) ASSERT_EQ(index.find(code), local);
    }
  }
  EXPECT_EQ(index.size(), truth.size());
  for (const uint64_t code : randomCodes(20000, 96, rng)) {
    const auto it = truth.find(code);
    EXPECT_EQ(index.find(code), it == truth.end() ? -1 : it->second) << code;
  }
}

TEST(CodeIndex, AssignHoldsExactlyTheListGiven) {
  std::mt19937 rng(11);
  CodeIndex index;
  for (uint64_t code : randomCodes(5000, 32, rng)) index.set(code, 1);
  std::vector<uint64_t> list = randomCodes(3000, 32, rng);
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
  index.assign(list);
  EXPECT_EQ(index.size(), list.size());
  for (size_t k = 0; k < list.size(); ++k) EXPECT_EQ(index.find(list[k]), static_cast<int64_t>(k));
  for (uint64_t code : randomCodes(5000, 32, rng)) {
    if (!std::binary_search(list.begin(), list.end(), code)) {
      EXPECT_EQ(index.find(code), -1);
    }
  }
  index.assign({});
  EXPECT_EQ(index.size(), 0u);
  EXPECT_EQ(index.find(list.front()), -1);
}

}  // namespace
}  // namespace rangefuse
