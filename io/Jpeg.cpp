#include "rangefuse/io/Jpeg.h"

// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>

#include <algorithm>
#include <cctype>
#include <csetjmp>
#include <cstddef>
#include <cstdio>
#include <filesystem>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/Png.h"

namespace rangefuse::io {
namespace {

/// libjpeg reports errors through a callback that must not return: it jumps back to the reader
/// with the library's message, which becomes an InputError there (no exception may cross C).
struct ErrorJump {
  jpeg_error_mgr mgr;
  std::jmp_buf back;
  char message[JMSG_LENGTH_MAX];
};

void jumpBack(j_common_ptr info) {
  auto* e = reinterpret_cast<ErrorJump*>(info->err);
  (*info->err->format_message)(info, e->message);
  std::longjmp(e->back, 1);
}

/// Owns the FILE and the decompressor, so every way out closes both.
struct Reading {
  std::FILE* file = nullptr;
  jpeg_decompress_struct info{};
  ErrorJump error{};
  bool created = false;
  ~Reading() {
    if (created) jpeg_destroy_decompress(&info);
    if (file) std::fclose(file);
  }
};

std::string lowerExtension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

/// Decodes into `image`; returns "" or the reason it failed. Holds no C++ objects with
/// destructors between setjmp and a longjmp (the image is sized before decoding starts).
std::string decode(Reading& r, Image& image, uint64_t maxPixels) {
  r.info.err = jpeg_std_error(&r.error.mgr);
  r.error.mgr.error_exit = jumpBack;
  if (setjmp(r.error.back)) return r.error.message;
  jpeg_create_decompress(&r.info);
  r.created = true;
  jpeg_stdio_src(&r.info, r.file);
  jpeg_read_header(&r.info, TRUE);
  if (r.info.jpeg_color_space == JCS_CMYK || r.info.jpeg_color_space == JCS_YCCK)
    return "is CMYK; colour images must be RGB or greyscale";
  if (uint64_t(r.info.image_width) * r.info.image_height > maxPixels)
    return "holds " + std::to_string(r.info.image_width) + " x " +
           std::to_string(r.info.image_height) + " pixels, more than --max-grid-cells allows";
  r.info.out_color_space = JCS_RGB;
  jpeg_start_decompress(&r.info);
  image = Image(static_cast<int>(r.info.output_width), static_cast<int>(r.info.output_height), 0);
  while (r.info.output_scanline < r.info.output_height) {
    JSAMPROW row = image.rgb.data() + size_t(r.info.output_scanline) * image.width * 3;
    jpeg_read_scanlines(&r.info, &row, 1);
  }
  jpeg_finish_decompress(&r.info);
  return "";
}

}  // namespace

Image readJpeg(const std::string& path, uint64_t maxPixels) {
  Reading r;
  r.file = std::fopen(path.c_str(), "rb");
  if (!r.file) throw InputError(path + ": cannot open JPEG file");
  Image image;
  const std::string why = decode(r, image, maxPixels);
  if (!why.empty()) throw InputError(path + ": cannot read JPEG: " + why);
  return image;
}

void writeJpeg(const std::string& path, const Image& image, int quality) {
  const std::string tmp = temporaryPath(path);
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (!file) throw InputError(path + ": cannot write JPEG (cannot create " + tmp + ")");
  jpeg_compress_struct info{};
  jpeg_error_mgr error{};
  info.err = jpeg_std_error(&error);  // writing our own image: only I/O can fail, checked below
  jpeg_create_compress(&info);
  jpeg_stdio_dest(&info, file);
  info.image_width = static_cast<JDIMENSION>(image.width);
  info.image_height = static_cast<JDIMENSION>(image.height);
  info.input_components = 3;
  info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  // Full-resolution chroma (4:4:4): synthetic textures' sharp edges would bleed at 4:2:0.
  for (int c = 0; c < info.num_components; ++c)
    info.comp_info[c].h_samp_factor = info.comp_info[c].v_samp_factor = 1;
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row =
        const_cast<uint8_t*>(image.rgb.data()) + size_t(info.next_scanline) * image.width * 3;
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  const bool written = std::ferror(file) == 0;
  if (std::fclose(file) != 0 || !written) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write JPEG (disk full?)");
  }
  moveIntoPlace(tmp, path);
}

bool isColourImageName(const std::string& path) {
  const std::string e = lowerExtension(path);
  return e == ".png" || e == ".jpg" || e == ".jpeg";
}

Image readColourImage(const std::string& path, uint64_t maxPixels) {
  const std::string e = lowerExtension(path);
  if (e == ".png") return readPng(path);
  if (e == ".jpg" || e == ".jpeg") return readJpeg(path, maxPixels);
  throw InputError(path + ": colour images must be PNG or JPEG (.png, .jpg, .jpeg)");
}

}  // namespace rangefuse::io
