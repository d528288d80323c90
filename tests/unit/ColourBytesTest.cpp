// A colour channel to its byte and back (core/Colour.h), inline where colours are made per
// voxel sample: against the library calls they stand for, over every half-way point, floats
// around them and a sweep of all floats from -1 to 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "rangefuse/core/Colour.h"

using namespace rangefuse;

namespace {

/// The byte as lround rounds it (what colourByte stands for).
uint8_t byteByLround(float channel) {
  return static_cast<uint8_t>(std::lround(std::clamp(channel, 0.0f, 1.0f) * 255));
}

float fromBits(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace

TEST(ColourBytes, AChannelRoundsToTheByteLroundGives) {
  std::vector<float> tried = {0.0f,
                              -0.0f,
                              1.0f,
                              -1.0f,
                              2.0f,
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::denorm_min()};
  for (int b = 0; b < 256; ++b) {  // each half-way point and 64 floats either side of it
    float half = (b + 0.5f) / 255, below = half, above = half;
    for (int k = 0; k < 64; ++k) {
      tried.insert(tried.end(), {below, above});
      below = std::nextafter(below, -1.0f), above = std::nextafter(above, 2.0f);
    }
  }
  size_t swept = 0;
  for (uint64_t bits = 0; bits <= 0xffffffffull; bits += 4099) {  // every sign and exponent
    const float f = fromBits(static_cast<uint32_t>(bits));
    if (!std::isnan(f) && f >= -1 && f <= 2) tried.push_back(f), ++swept;
  }
  ASSERT_GT(swept, 400000u);
  for (const float f : tried) ASSERT_EQ(colourByte(f), byteByLround(f)) << f;
  EXPECT_EQ(colourByte(std::numeric_limits<float>::quiet_NaN()), 0);
}

TEST(ColourBytes, AByteChannelIsTheDivisionsBits) {
  volatile float divisor = 255;  // kept from the compiler: the division happens here, at run time
  for (int b = 0; b < 256; ++b) {
    volatile float byte = static_cast<float>(b);
    const float divided = byte / divisor;
    ASSERT_EQ(std::memcmp(&kByteChannels[size_t(b)], &divided, sizeof divided), 0) << b;
    ASSERT_EQ(colourOf({uint8_t(b), uint8_t(255 - b), 0, 255}),
              Colour(divided, (255 - b) / divisor, 0.0f));
  }
}

TEST(ColourBytes, EveryByteComesBackThroughItsChannel) {
  for (int b = 0; b < 256; ++b) EXPECT_EQ(colourByte(kByteChannels[size_t(b)]), b);
}
