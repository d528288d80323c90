// PNG files through libpng.
#pragma once

#include <string>

#include "rangefuse/core/Image.h"

namespace rangefuse::io {

/// Writes an RGB PNG atomically (temporary name, then rename).
void writePng(const std::string& path, const Image& image);

/// Reads a PNG as 8-bit RGB; throws InputError naming the file.
Image readPng(const std::string& path);

}  // namespace rangefuse::io
