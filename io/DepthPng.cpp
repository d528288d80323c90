#include "rangefuse/io/DepthPng.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/core/Limits.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

/// libpng reports errors by longjmp: the message lands here and the caller turns it into an
/// exception once libpng's frames are gone (throwing through C frames is not safe).
struct PngFailure {
  char message[256] = "";
};

void onPngError(png_structp png, png_const_charp message) {
  auto* failure = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(failure->message, sizeof failure->message, "%s", message);
  std::longjmp(png_jmpbuf(png), 1);
}

void onPngWarning(png_structp, png_const_charp) {}

/// PNG stores 16-bit samples big-endian.
bool littleEndian() {
  const uint16_t one = 1;
  return *reinterpret_cast<const uint8_t*>(&one) == 1;
}

using File = std::unique_ptr<FILE, int (*)(FILE*)>;

File openFile(const std::string& path, const char* mode) {
  File f(std::fopen(path.c_str(), mode), &std::fclose);
  if (!f)
    throw InputError(path + ": cannot open for " + (mode[0] == 'r' ? "reading" : "writing") + ": " +
                     std::strerror(errno));
  return f;
}

/// The header, then (when it is a 16-bit grey image within the limit) the pixels. Returns an
/// empty string on success, else what is wrong. No C++ object is created after setjmp.
std::string decode(FILE* file, uint64_t maxPixels, DepthImage& image) {
  PngFailure failure;
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &failure, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return "out of memory";
  }
  const char* problem = nullptr;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return std::string("corrupt or truncated PNG: ") + failure.message;
  }
  png_init_io(png, file);
#ifdef PNG_IGNORE_ADLER32
  // Each chunk's CRC still guards the pixels; zlib's own checksum over them again took 0.45 %
  // of a depth stream's CPU (adler32_z under perf, the synthetic room without colour).
  png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info),
                    height = png_get_image_height(png, info);
  const int depth = png_get_bit_depth(png, info), colour = png_get_color_type(png, info);
  if (depth != 16 || colour != PNG_COLOR_TYPE_GRAY)
    problem = "not a 16-bit greyscale PNG (depth images are)";
  else if (static_cast<double>(width) * height > static_cast<double>(maxPixels))
    problem = "too many pixels for --max-grid-cells";
  if (problem) {
    png_destroy_read_struct(&png, &info, nullptr);
    return problem;
  }
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.counts.resize(static_cast<size_t>(width) * height);
  if (littleEndian()) png_set_swap(png);
  for (png_uint_32 v = 0; v < height; ++v)
    png_read_row(png, reinterpret_cast<png_bytep>(&image.counts[static_cast<size_t>(v) * width]),
                 nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return "";
}

/// Writes the image to an open file; empty string on success, else what went wrong.
std::string encode(FILE* file, const DepthImage& image) {
  PngFailure failure;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &failure, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return "out of memory";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return std::string("cannot write PNG: ") + failure.message;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, image.width, image.height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (littleEndian()) png_set_swap(png);
  for (int v = 0; v < image.height; ++v)
    png_write_row(png, reinterpret_cast<png_const_bytep>(
                           &image.counts[static_cast<size_t>(v) * image.width]));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return "";
}

}  // namespace

DepthImage readDepthPng(const std::string& path, uint64_t maxPixels) {
  File file = openFile(path, "rb");
  DepthImage image;
  const std::string problem = decode(file.get(), maxPixels, image);
  if (!problem.empty()) throw InputError(path + ": " + problem);
  return image;
}

uint64_t pngPixels(const std::string& path) {
  // The signature (8 bytes), then the IHDR chunk: length, type, width and height, big-endian.
  unsigned char head[24];
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return 0;
  const size_t got = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  if (got != sizeof head || png_sig_cmp(head, 0, 8) != 0 || std::memcmp(head + 12, "IHDR", 4) != 0)
    return 0;
  const auto word = [&](int at) {
    return uint64_t(head[at]) << 24 | uint64_t(head[at + 1]) << 16 | uint64_t(head[at + 2]) << 8 |
           uint64_t(head[at + 3]);
  };
  return word(16) * word(20);
}

void writeDepthPng(const std::string& path, const DepthImage& image) {
  const std::string tmp = temporaryPath(path);
  faultPoint("write", path);
  std::string problem;
  {
    File file = openFile(tmp, "wb");
    problem = encode(file.get(), image);
    if (problem.empty() && std::fflush(file.get()) != 0) problem = std::strerror(errno);
  }
  std::error_code ec;
  if (problem.empty()) std::filesystem::rename(tmp, path, ec);
  if (!problem.empty() || ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": " + (problem.empty() ? ec.message() : problem));
  }
}

}  // namespace rangefuse::io
