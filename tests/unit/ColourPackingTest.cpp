// Routing packs colours, texel blocks and texels narrow when every one allows it (decision 54):
// each form against the bits it was given, byte colours against all 256 byte values, and the
// sizes the narrow forms promise.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <numeric>
#include <random>

#include "../common/PackedRoundTrip.h"
#include "route/ColourPacking.h"

using namespace rangefuse;
using namespace rangefuse::internal;

namespace {

constexpr size_t kHead = sizeof(Form) + sizeof(uint64_t);

std::vector<uint32_t> allOf(size_t n) {
  std::vector<uint32_t> pick(n);
  std::iota(pick.begin(), pick.end(), 0u);
  return pick;
}

bool sameBits(const std::vector<Colour>& a, const std::vector<Colour>& b) {
  // memcmp wants pointers even for no bytes, and an empty vector may have none.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Colour)) == 0);
}

/// Packs the picked colours after a marker, unpacks them, and checks that skipping lands where
/// unpacking did.
std::vector<Colour> roundTrip(const std::vector<Colour>& v, const std::vector<uint32_t>& pick,
                              size_t& bytes) {
  std::vector<char> buf(5, 'x');
  packColours(buf, v, pick);
  bytes = buf.size() - 5;
  return test::unpackedFrom<Colour>(buf, 5, unpackColours, skipColours);
}

/// Every byte colour, channels in turn.
std::vector<Colour> byteColours() {
  std::vector<Colour> v;
  for (int b = 0; b < 256; ++b)
    v.push_back(colourOf({uint8_t(b), uint8_t(255 - b), uint8_t(b * 7 % 256), 255}));
  return v;
}

}  // namespace

TEST(ColourPacking, AFloatIsAByteColourExactlyWhenSomeByteGivesItsBits) {
  std::mt19937 random(5);
  std::uniform_int_distribution<uint32_t> anyBits(0, 0x3f800000);  // the floats in [0, 1]
  std::vector<float> tried = {-0.0f, 1.0f, std::nextafter(1.0f, 2.0f),
                              std::numeric_limits<float>::quiet_NaN()};
  for (int b = 0; b < 256; ++b) {
    const float c = colourOf({uint8_t(b), 0, 0, 255})[0];
    tried.insert(tried.end(), {c, std::nextafter(c, -1.0f), std::nextafter(c, 2.0f)});
  }
  for (int k = 0; k < 20000; ++k) {
    const uint32_t bits = anyBits(random);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    tried.push_back(f);
  }
  for (const float f : tried) {
    int byte = -1;  // brute force: the byte whose channel has f's bits
    for (int b = 0; b < 256; ++b) {
      const float c = colourOf({uint8_t(b), 0, 0, 255})[0];
      if (std::memcmp(&c, &f, sizeof f) == 0) byte = b;
    }
    uint8_t got[3];
    ASSERT_EQ(byteColour(Colour(f, f, f), got), byte >= 0) << f;
    if (byte >= 0) {
      EXPECT_EQ(got[0], byte) << f;
    }
  }
}

TEST(ColourPacking, ByteColoursTakeThreeBytesAndComeBackBitForBit) {
  const std::vector<Colour> v = byteColours();
  std::vector<uint32_t> pick = {7, 3, 255, 0, 3, 128};  // any order, repeats too
  size_t bytes;
  const std::vector<Colour> back = roundTrip(v, pick, bytes);
  EXPECT_EQ(bytes, kHead + 3 * pick.size());
  std::vector<Colour> picked;
  for (uint32_t i : pick) picked.push_back(v[i]);
  EXPECT_TRUE(sameBits(back, picked));
  EXPECT_TRUE(sameBits(roundTrip(v, allOf(v.size()), bytes), v));
}

TEST(ColourPacking, OneColourNotAByteSendsThemAllAsFloats) {
  const std::vector<Colour> bytesOnly = byteColours();
  for (const float odd : {0.5f, -0.0f, std::numeric_limits<float>::quiet_NaN(), 1.5f}) {
    std::vector<Colour> v = bytesOnly;
    v[200][1] = odd;
    size_t bytes;
    EXPECT_TRUE(sameBits(roundTrip(v, allOf(v.size()), bytes), v)) << odd;
    EXPECT_EQ(bytes, kHead + v.size() * sizeof(Colour)) << odd;
    // Left out of the part, it does not count.
    std::vector<uint32_t> without = allOf(v.size());
    without.erase(without.begin() + 200);
    roundTrip(v, without, bytes);
    EXPECT_EQ(bytes, kHead + 3 * without.size()) << odd;
  }
}

TEST(ColourPacking, NoColoursPackAsNone) {
  size_t bytes;
  EXPECT_TRUE(roundTrip({}, allOf(9), bytes).empty());
  EXPECT_EQ(bytes, kHead);
}

TEST(ColourPacking, BlocksWithinSixteenBitsTakeFourBytes) {
  using Block = std::array<int32_t, 2>;
  const std::vector<Block> narrow = {{0, 0}, {65535, 3}, {17, 65535}, {480, 640}};
  for (const Block odd : {Block{-1, 0}, Block{0, 65536}, Block{INT32_MIN, INT32_MAX}}) {
    for (const bool withOdd : {false, true}) {
      std::vector<Block> v = narrow;
      if (withOdd) v.push_back(odd);
      std::vector<char> buf;
      packBlocks(buf, v, allOf(v.size()));
      EXPECT_EQ(buf.size(), kHead + v.size() * (withOdd ? 8 : 4));
      EXPECT_EQ(test::unpackedFrom<Block>(buf, 0, unpackBlocks, skipBlocks), v);
    }
  }
}

TEST(ColourPacking, TexelsTakeABitAndThreeBytesEachSampledOne) {
  std::mt19937 random(9);
  for (const size_t n : {size_t(0), size_t(1), size_t(8), size_t(13), size_t(1000)}) {
    std::vector<Texel> v(n, Texel{0, 0, 0, 0});
    size_t sampled = 0;
    // The first half all sampled (whole bytes of the mask set), the rest two in three.
    for (size_t k = 0; k < n; ++k)
      if (Texel& t = v[k]; k < n / 2 || random() % 3 != 0) {
        t = {uint8_t(random()), uint8_t(random()), uint8_t(random()), 255};
        ++sampled;
      }
    for (const Texel odd : {Texel{}, Texel{1, 2, 3, 7}, Texel{0, 0, 1, 0}}) {
      std::vector<Texel> w = v;
      const bool asIs = odd != Texel{};
      if (asIs) w.insert(w.begin() + long(w.size() / 2), odd);  // amid sampled ones, too
      std::vector<char> buf;
      packTexelCells(buf, w);
      EXPECT_EQ(buf.size(), kHead + (asIs ? w.size() * sizeof(Texel) : (n + 7) / 8 + 3 * sampled));
      EXPECT_EQ(test::unpackedFrom<Texel>(buf, 0, unpackTexelCells, skipTexelCells), w) << n;
    }
  }
}
