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
      kept_(scans_.size()),
      keptBytes_(scans_.size(), 0) {}

void HeldScans::append(const std::vector<io::ConfScan>& more, const std::vector<int>& readers) {
  scans_.insert(scans_.end(), more.begin(), more.end());
  readers_.insert(readers_.end(), readers.begin(), readers.end());
  kept_.resize(scans_.size());
  keptBytes_.resize(scans_.size(), 0);
}

std::shared_ptr<const PrismScan> HeldScans::get(size_t i) const {
  if (kept_[i]) return kept_[i];
  const ScanPreparation& p = preparation_;
  return std::make_shared<const PrismScan>(loadScan(scans_[i], p.surface, p.limits, p.eps));
}

std::shared_ptr<const PrismScan> HeldScans::readAndOffer(size_t i) {
  return offer(i, get(i));
}

std::vector<std::shared_ptr<const PrismScan>> HeldScans::readAndOffer(
    const std::vector<size_t>& which, int threads) {
  std::vector<const io::ConfScan*> unread;
  for (size_t i : which)
    if (!kept_[i]) unread.push_back(&scans_[i]);
  const ScanPreparation& p = preparation_;
  std::vector<PrismScan> read = loadScans(unread, p.surface, p.limits, p.eps, threads);
  std::vector<std::shared_ptr<const PrismScan>> out;
  size_t next = 0;
  for (size_t i : which)
    out.push_back(kept_[i] ? kept_[i]
                           : offer(i, std::make_shared<const PrismScan>(std::move(read[next++]))));
  return out;
}

std::shared_ptr<const PrismScan> HeldScans::offer(size_t i, std::shared_ptr<const PrismScan> scan) {
  const uint64_t bytes = scanBytes(*scan);
  if (!kept_[i] && bytes <= budgetLeft_) {
    budgetLeft_ -= bytes;
    kept_[i] = scan;
    keptBytes_[i] = bytes;
  }
  return scan;
}

void HeldScans::release(size_t i) {
  budgetLeft_ += keptBytes_[i];
  keptBytes_[i] = 0;
  kept_[i].reset();
}

size_t HeldScans::keptCount() const {
  return static_cast<size_t>(
      std::count_if(kept_.begin(), kept_.end(), [](const auto& s) { return s != nullptr; }));
}

std::shared_ptr<HeldScans> heldScans(std::vector<io::ConfScan> scans, std::vector<int> readers,
                                     int rank, const ReadSettings& read) {
  ScanPreparation preparation{read.surface, read.limits, read.eps};
  preparation.surface.sightMap = false;
  return std::make_shared<HeldScans>(std::move(scans), std::move(readers), rank, preparation,
                                     read.keepBytes);
}

}  // namespace rangefuse
