#include "E57Pages.h"

#include <boost/crc.hpp>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "rangefuse/core/Error.h"

namespace rangefuse::io::internal {
namespace {

/// Pages loaded at once: 256 KiB of file a read.
constexpr uint64_t kBlockPages = 256;

std::string hex(uint32_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

}  // namespace

uint32_t crc32cPortable(const uint8_t* data, size_t n) {
  boost::crc_optimal<32, 0x1EDC6F41, 0xFFFFFFFF, 0xFFFFFFFF, true, true> crc;
  crc.process_bytes(data, n);
  return crc.checksum();
}

#if defined(__x86_64__)
namespace {

/// The CPU's own CRC-32C (SSE 4.2), eight bytes an instruction: checking every page then costs
/// a small part of decoding it.
__attribute__((target("sse4.2"))) uint32_t crc32cSse42(const uint8_t* data, size_t n) {
  uint64_t crc = 0xFFFFFFFF;
  for (; n >= 8; data += 8, n -= 8) {
    uint64_t word;
    std::memcpy(&word, data, 8);
    crc = __builtin_ia32_crc32di(crc, word);
  }
  auto c = static_cast<uint32_t>(crc);
  for (; n > 0; ++data, --n) c = __builtin_ia32_crc32qi(c, *data);
  return c ^ 0xFFFFFFFF;
}

}  // namespace

uint32_t crc32c(const uint8_t* data, size_t n) {
  static const bool sse42 = __builtin_cpu_supports("sse4.2");
  return sse42 ? crc32cSse42(data, n) : crc32cPortable(data, n);
}
#else
uint32_t crc32c(const uint8_t* data, size_t n) {
  return crc32cPortable(data, n);
}
#endif

E57Pages::E57Pages(const std::string& path) : path_(path), file_(nullptr, &std::fclose) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path + ": is a folder, not an E57 file");
  file_.reset(std::fopen(path.c_str(), "rb"));
  if (!file_) throw InputError(path + ": cannot open file");
  if (std::fseek(file_.get(), 0, SEEK_END) != 0) throw InputError(path + ": cannot seek");
  const long size = std::ftell(file_.get());
  if (size < 0) throw InputError(path + ": cannot tell its size");
  size_ = static_cast<uint64_t>(size);
  if (size_ == 0 || size_ % kE57Page != 0)
    throw InputError(path + ": " + std::to_string(size_) +
                     " bytes is not a whole number of 1024-byte E57 pages (truncated?)");
}

void E57Pages::load(uint64_t page) {
  const uint64_t total = size_ / kE57Page;
  if (page >= total)
    throw InputError(path_ + ": truncated: data runs past the last page (byte " +
                     std::to_string(page * kE57Page) + " of " + std::to_string(size_) + ")");
  pages_ = std::min(kBlockPages, total - page);
  firstPage_ = page;
  block_.resize(pages_ * kE57Page);
  if (std::fseek(file_.get(), static_cast<long>(page * kE57Page), SEEK_SET) != 0 ||
      std::fread(block_.data(), 1, block_.size(), file_.get()) != block_.size())
    throw InputError(path_ + ": read error at byte " + std::to_string(page * kE57Page));
  for (uint64_t k = 0; k < pages_; ++k) {
    const uint8_t* p = block_.data() + k * kE57Page;
    const uint32_t stored = uint32_t(p[1020]) << 24 | uint32_t(p[1021]) << 16 |
                            uint32_t(p[1022]) << 8 | uint32_t(p[1023]);
    const uint32_t computed = crc32c(p, kE57PageData);
    if (stored != computed) {
      pages_ = 0;
      throw InputError(path_ + ": page " + std::to_string(page + k) + " (bytes " +
                       std::to_string((page + k) * kE57Page) + "-" +
                       std::to_string((page + k + 1) * kE57Page - 1) +
                       "): checksum mismatch, stored " + hex(stored) + ", computed " +
                       hex(computed) + " (the file is damaged)");
    }
  }
}

void E57Pages::read(uint64_t at, void* out, size_t n) {
  auto* to = static_cast<uint8_t*>(out);
  while (n > 0) {
    const uint64_t page = at / kE57PageData, within = at % kE57PageData;
    if (pages_ == 0 || page < firstPage_ || page >= firstPage_ + pages_) load(page);
    const size_t take = static_cast<size_t>(std::min<uint64_t>(n, kE57PageData - within));
    std::memcpy(to, block_.data() + (page - firstPage_) * kE57Page + within, take);
    to += take, at += take, n -= take;
  }
}

}  // namespace rangefuse::io::internal
