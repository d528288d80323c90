// Vertex numbers by lattice edge key, for marching cubes: every triangle corner asks for one.
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rangefuse {

/// A hash table from edge keys to vertex numbers, open addressing with linear probing: a
/// std::unordered_map allocates a node per vertex and misses the cache at every corner.
class EdgeIndex {
 public:
  /// The number of `key`, after inserting `value` for it if it had none; true if it did not.
  std::pair<int32_t, bool> emplace(uint64_t key, int32_t value) {
    if (2 * (size_ + 1) > slots_.size()) rehash(std::max<size_t>(64, 2 * slots_.size()));
    Slot& s = slots_[slotOf(key)];
    if (s.key == key) return {s.value, false};
    s = Slot{key, value};
    ++size_;
    return {value, true};
  }
  /// The number of `key`, or -1.
  int32_t find(uint64_t key) const {
    if (slots_.empty()) return -1;
    const Slot& s = slots_[slotOf(key)];
    return s.key == key ? s.value : -1;
  }
  /// The number of `key`; throws std::out_of_range if it has none.
  int32_t at(uint64_t key) const {
    const int32_t v = find(key);
    if (v < 0) throw std::out_of_range("EdgeIndex: no such edge");
    return v;
  }
  size_t size() const { return size_; }
  /// Room for n keys without growing.
  void reserve(size_t n) {
    size_t want = 64;
    while (want < 2 * n) want *= 2;
    if (want > slots_.size()) rehash(want);
  }

 private:
  static constexpr uint64_t kNone = ~uint64_t{0};  // edge keys use 62 bits
  struct Slot {
    uint64_t key = kNone;
    int32_t value = -1;
  };
  static size_t mix(uint64_t k) {  // keys of neighbouring edges differ in a few low bits
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    return static_cast<size_t>(k ^ (k >> 33));
  }
  /// The slot holding `key`, else the empty one where it would go.
  size_t slotOf(uint64_t key) const {
    const size_t mask = slots_.size() - 1;
    for (size_t i = mix(key) & mask;; i = (i + 1) & mask)
      if (slots_[i].key == key || slots_[i].key == kNone) return i;
  }
  void rehash(size_t count) {
    std::vector<Slot> old(count);
    old.swap(slots_);
    for (const Slot& s : old)
      if (s.key != kNone) slots_[slotOf(s.key)] = s;
  }

  std::vector<Slot> slots_;
  size_t size_ = 0;
};

}  // namespace rangefuse
