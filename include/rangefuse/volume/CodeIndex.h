// The local index of each brick a rank holds, by its Morton code: asked at every brick a prism
// reaches and at every control point a fit samples, so it is one flat table, not a map of nodes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rangefuse::internal {

/// Morton codes to local brick indices: open addressing with linear probing, at most half full,
/// each entry's code and index side by side (a lookup mostly reads one cache line). Codes of 21-bit
/// coordinates never reach ~0, the empty slot's mark.
class CodeIndex {
 public:
  /// The index of `code`, or -1 when it is not held.
  int64_t find(uint64_t code) const {
    if (entries_.empty()) return -1;
    for (size_t s = slotOf(code);; s = (s + 1) & mask_) {
      if (entries_[s].code == code) return entries_[s].local;
      if (entries_[s].code == kEmpty) return -1;
    }
  }
  /// Sets the index of `code`, adding it when it is not held.
  void set(uint64_t code, int64_t local);
  /// Holds exactly `codes`, code k at index k.
  void assign(const std::vector<uint64_t>& codes);
  size_t size() const { return size_; }
  /// Bytes of its table.
  uint64_t bytes() const { return sizeof(Entry) * entries_.capacity(); }

 private:
  struct Entry {
    uint64_t code;
    int64_t local;
  };
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  static constexpr int kLeastBits = 4;

  size_t slotOf(uint64_t code) const { return (code * 0x9E3779B97F4A7C15ull) >> shift_; }
  /// Empties the table and gives it 2^bits slots.
  void reset(int bits);

  std::vector<Entry> entries_;
  size_t size_ = 0, mask_ = 0;
  int shift_ = 64;
};

}  // namespace rangefuse::internal
