// 16-bit greyscale PNG depth images (TUM RGB-D, Redwood, most RGB-D cameras' exports).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rangefuse::io {

/// Raw depth counts, row-major from the top-left pixel; 0 means no measurement.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<uint16_t> counts;

  uint16_t at(int u, int v) const { return counts[static_cast<size_t>(v) * width + u]; }
};

/// Reads a 16-bit greyscale PNG exactly (no gamma or scaling). Throws InputError naming the
/// file for a missing or corrupt file, another pixel format, or more than `maxPixels` pixels.
DepthImage readDepthPng(const std::string& path, uint64_t maxPixels);

/// The pixels of a PNG as its header gives them (width x height), without decoding it; 0 for a
/// file that cannot be read or is not a PNG (reading it says why).
uint64_t pngPixels(const std::string& path);

/// Writes a 16-bit greyscale PNG atomically (temporary name, then rename).
void writeDepthPng(const std::string& path, const DepthImage& image);

}  // namespace rangefuse::io
