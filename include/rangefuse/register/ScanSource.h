// The scans a registration works on, in their own frames. A rank holds only the scans it read,
// and of those keeps in memory what fits its budget; the others are read again when needed.
#pragma once

#include <memory>
#include <numeric>
#include <vector>

#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

class ScanSource {
 public:
  virtual ~ScanSource() = default;

  /// How many scans the job has (held here or not).
  virtual size_t size() const = 0;

  /// True when this rank read scan i.
  virtual bool holds(size_t i) const = 0;

  /// True when scan i is held and kept in memory: get(i) then costs nothing and returns the
  /// same scan every time.
  virtual bool kept(size_t i) const = 0;

  /// Scan i, held here: the kept one, or one read again (released when the caller drops it).
  virtual std::shared_ptr<const PrismScan> get(size_t i) const = 0;
};

/// Scans given in memory (tests, one-rank tools); an empty scan counts as not held.
class ScansInMemory : public ScanSource {
 public:
  explicit ScansInMemory(std::vector<PrismScan> scans);

  size_t size() const override { return scans_.size(); }
  bool holds(size_t i) const override { return scans_[i] != nullptr; }
  bool kept(size_t i) const override { return holds(i); }
  std::shared_ptr<const PrismScan> get(size_t i) const override { return scans_[i]; }

 private:
  std::vector<std::shared_ptr<const PrismScan>> scans_;
};

/// 0, 1, ..., n - 1: every entry of a list of n scans.
inline std::vector<size_t> everyScan(size_t n) {
  std::vector<size_t> all(n);
  std::iota(all.begin(), all.end(), size_t{0});
  return all;
}

}  // namespace rangefuse
