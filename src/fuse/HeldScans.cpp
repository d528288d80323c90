#include "rangefuse/fuse/HeldScans.h"

#include <algorithm>

#include "rangefuse/fuse/ScanLoader.h"

namespace rangefuse {

HeldScans::HeldScans(std::vector<io::ConfScan> scans, std::vector<int> readers, int rank,
                     ScanPreparation preparation, uint64_t budgetBytes)
    : scans_(std::move(scans)),
      readers_(std::move(readers)),
      rank_(rank),
      preparation_(preparation),
      budgetLeft_(budgetBytes),
      kept_(scans_.size()) {}

std::shared_ptr<const PrismScan> HeldScans::get(size_t i) const {
  if (kept_[i]) return kept_[i];
  const ScanPreparation& p = preparation_;
  return std::make_shared<const PrismScan>(loadScan(scans_[i], p.surface, p.limits, p.eps));
}

std::shared_ptr<const PrismScan> HeldScans::readAndOffer(size_t i) {
  std::shared_ptr<const PrismScan> scan = get(i);
  const uint64_t bytes = scanBytes(*scan);
  if (!kept_[i] && bytes <= budgetLeft_) {
    budgetLeft_ -= bytes;
    kept_[i] = scan;
  }
  return scan;
}

size_t HeldScans::keptCount() const {
  return static_cast<size_t>(
      std::count_if(kept_.begin(), kept_.end(), [](const auto& s) { return s != nullptr; }));
}

}  // namespace rangefuse
