// The scan parts routed to a rank, held until its bricks take them.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

/// Scans (or parts of them) with the position of their entry in the scan list.
using IndexedScans = std::vector<std::pair<size_t, PrismScan>>;

/// Parts routed to this rank, in the bytes they arrived in: a compact scan's in about half the
/// memory of its doubles (decision 45). Each part is unpacked when it is taken, and a buffer
/// is freed once all its parts are.
class RoutedParts {
 public:
  /// Holds one of this rank's own parts as it is.
  void keep(uint64_t entry, PrismScan&& part);
  /// Holds one part of entry `entry` packed already, as packedScan or routing packs it.
  void keepBytes(uint64_t entry, std::vector<char>&& bytes);
  /// Holds the parts one rank sent (routeScan's bytes for this rank), packed.
  void receive(std::vector<char>&& bytes);
  /// Orders the parts by entry. Each entry has one reader, so it arrives once from each rank
  /// that sent a part of it: entry order is all a field needs (parts of one entry keep the
  /// order they came in).
  void sortByEntry();
  size_t size() const { return parts_.size(); }
  uint64_t entry(size_t k) const { return parts_[k].entry; }
  /// Bytes part k holds, packed or not.
  uint64_t bytesOf(size_t k) const { return parts_[k].bytes; }
  /// Part k as a scan (each part is taken once).
  PrismScan take(size_t k);
  /// Parts [first, end) as scans, unpacked on up to `threads` threads.
  IndexedScans take(size_t first, size_t end, int threads);
  /// Every part, in order.
  IndexedScans takeAll();
  /// Bytes held: packed parts' buffers and the parts kept as they are.
  uint64_t bytes() const { return bytes_; }

 private:
  struct Part {
    uint64_t entry;
    size_t buffer, offset;  ///< a packed part; buffer = npos for a part kept as it is
    uint64_t bytes;
  };
  /// Part k unpacked (or moved out), its buffer left as it is: safe on several threads.
  PrismScan unpack(size_t k);
  /// Holds the next buffer, whose `parts` parts are listed already.
  void hold(std::vector<char>&& bytes, size_t parts);
  /// Lets go of part k's share of the bytes held.
  void release(size_t k);
  static constexpr size_t npos = ~size_t(0);
  std::vector<Part> parts_;
  std::vector<std::vector<char>> buffers_;
  std::vector<size_t> untaken_;  ///< per buffer, its parts not yet taken
  std::vector<PrismScan> loose_;
  uint64_t bytes_ = 0;
};

}  // namespace rangefuse
