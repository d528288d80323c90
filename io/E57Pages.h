// E57's paged file layer (private to io/): physical offsets count every byte of the file,
// logical offsets skip the 4-byte checksum at the end of each 1024-byte page.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace rangefuse::io::internal {

constexpr uint64_t kE57Page = 1024, kE57PageData = 1020;

inline uint64_t e57Logical(uint64_t physical) {
  const uint64_t within = physical % kE57Page;
  return physical / kE57Page * kE57PageData + (within < kE57PageData ? within : kE57PageData);
}

inline uint64_t e57Physical(uint64_t logical) {
  return logical / kE57PageData * kE57Page + logical % kE57PageData;
}

/// CRC-32C (Castagnoli) of n bytes, as E57 stores it (big-endian) at the end of each page: by
/// the CPU's instruction where it has one, else by table.
uint32_t crc32c(const uint8_t* data, size_t n);
/// The same by table alone (for tests of the fast path).
uint32_t crc32cPortable(const uint8_t* data, size_t n);

/// An E57 file read by logical bytes. Pages are loaded a block at a time and each page's
/// checksum is checked as it is loaded, so every byte read was checked.
class E57Pages {
 public:
  /// Opens `path`; throws InputError when it cannot be opened or is not a whole number of pages.
  explicit E57Pages(const std::string& path);

  const std::string& path() const { return path_; }
  uint64_t physicalSize() const { return size_; }
  uint64_t logicalSize() const { return size_ / kE57Page * kE57PageData; }

  /// Copies n logical bytes starting at logical offset `at`. Throws InputError naming the file,
  /// the page and its byte offset on a checksum mismatch, or when the bytes run past the end.
  void read(uint64_t at, void* out, size_t n);

 private:
  void load(uint64_t page);

  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  uint64_t size_ = 0;
  std::vector<uint8_t> block_;  ///< whole pages, checked
  uint64_t firstPage_ = 0, pages_ = 0;
};

}  // namespace rangefuse::io::internal
