// An 8-bit RGB picture.
#pragma once

#include <cstdint>
#include <vector>

namespace rangefuse {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< row-major, top row first, 3 bytes a pixel

  Image() = default;
  Image(int w, int h, uint8_t grey) : width(w), height(h), rgb(size_t(w) * h * 3, grey) {}
  void set(int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    uint8_t* p = &rgb[(size_t(y) * width + x) * 3];
    p[0] = r, p[1] = g, p[2] = b;
  }
};

}  // namespace rangefuse
