// JPEG files through libjpeg (libjpeg-turbo on Debian): the colour images of depth cameras.
#pragma once

#include <cstdint>
#include <string>

#include "rangefuse/core/Image.h"

namespace rangefuse::io {

/// Reads a baseline or progressive JPEG (colour or greyscale) as 8-bit RGB. Throws InputError
/// naming the file when it cannot be opened, is not a JPEG, is damaged, is CMYK, or holds more
/// than `maxPixels` pixels.
Image readJpeg(const std::string& path, uint64_t maxPixels);

/// Writes an RGB JPEG of the given quality (1-100), chroma at full resolution, atomically
/// (temporary name, then rename).
void writeJpeg(const std::string& path, const Image& image, int quality = 95);

/// A colour image by its extension: .png through readPng, .jpg or .jpeg through readJpeg.
/// Throws InputError naming the file for any other extension.
Image readColourImage(const std::string& path, uint64_t maxPixels);

/// True for the extensions readColourImage reads (.png, .jpg, .jpeg, any case).
bool isColourImageName(const std::string& path);

}  // namespace rangefuse::io
