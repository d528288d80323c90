// What a scan's samples carry besides their position: a colour or an intensity.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace rangefuse {

/// What the input's samples carry. An intensity is kept as a colour with three equal channels,
/// so that it is fused and interpolated the same way.
enum class ColourKind : uint8_t { none, rgb, intensity };

/// One sample's colour, each channel in [0, 1].
using Colour = Eigen::Vector3f;

/// A channel in [0, 1] as the byte files store (clamped, rounded to the nearest of 0..255,
/// halves up; NaN gives 0).
inline uint8_t colourByte(float channel) {
  const float c = channel > 0 ? (channel < 1 ? channel : 1.0f) : 0.0f;
  // In double, c * 255 + 0.5 is exact: truncating it is lround's answer, without a call.
  return static_cast<uint8_t>(static_cast<int>(static_cast<double>(c * 255) + 0.5));
}

/// The channel of each byte value, b / 255 as a float division rounds it (a look-up where
/// colours are made per voxel sample).
inline constexpr std::array<float, 256> kByteChannels = [] {
  std::array<float, 256> c{};
  for (int b = 0; b < 256; ++b) c[size_t(b)] = static_cast<float>(b) / 255.0f;
  return c;
}();

/// One cell of a scan's original colour grid in 8 bits a channel; alpha 0 where the cell has no
/// sample of the surface (4 bytes: a quarter of a Colour).
using Texel = std::array<uint8_t, 4>;

inline Texel texelOf(const Colour& c) {
  return {colourByte(c[0]), colourByte(c[1]), colourByte(c[2]), 255};
}
inline Colour colourOf(const Texel& t) {
  return Colour(kByteChannels[t[0]], kByteChannels[t[1]], kByteChannels[t[2]]);
}

/// "none", "rgb" or "intensity".
std::string colourKindName(ColourKind kind);

/// The kind a `--colour` value asks for: "auto" gives `given` (what the input has), the others
/// their kind. Throws InputError for anything else.
ColourKind parseColourKind(const std::string& text, ColourKind given);

/// A voxel's fused colour: the weighted mean of its samples' colours in 16-bit fixed point
/// (6 bytes, a quarter of the distance sums' 24). It is updated with the same weights and in
/// the same order as the distance sums, so it is the same bits on any rank count.
struct VoxelColour {
  uint16_t c[3] = {0, 0, 0};

  /// Adds a sample of weight `w` to a voxel whose samples so far weigh `before`.
  void add(const Colour& colour, float w, float before) {
    const float share = w / (before + w);
    for (int k = 0; k < 3; ++k) {
      const float mean = c[k] * (1.0f / 65535) + share * (colour[k] - c[k] * (1.0f / 65535));
      c[k] = static_cast<uint16_t>(std::min(1.0f, std::max(0.0f, mean)) * 65535 + 0.5f);
    }
  }
  Colour value() const { return Colour(c[0], c[1], c[2]) / 65535; }
};
static_assert(sizeof(VoxelColour) == 6, "checkpoints store a voxel's colour as 3 uint16");

}  // namespace rangefuse
