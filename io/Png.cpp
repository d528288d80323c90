#include "rangefuse/io/Png.h"

#include <png.h>

#include <cstdio>
#include <memory>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {

void writePng(const std::string& path, const Image& image) {
  const std::string tmp = temporaryPath(path);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = image.width;
  png.height = image.height;
  png.format = PNG_FORMAT_RGB;
  faultPoint("write", path);
  if (!png_image_write_to_file(&png, tmp.c_str(), 0, image.rgb.data(), 0, nullptr)) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write PNG: " + png.message);
  }
  moveIntoPlace(tmp, path);
}

Image readPng(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw InputError(path + ": cannot read PNG: " + png.message);
  png.format = PNG_FORMAT_RGB;
  Image image(png.width, png.height, 0);
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr))
    throw InputError(path + ": cannot decode PNG: " + png.message);
  return image;
}

}  // namespace rangefuse::io
