#include "rangefuse/pipeline/HeldScans.h"

#include <algorithm>

#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"

namespace rangefuse {

HeldScans::HeldScans(std::vector<io::ConfScan> scans, std::vector<int> readers, int rank,
                     ScanPreparation preparation, uint64_t budgetBytes, bool placed)
    : scans_(std::move(scans)),
      readers_(std::move(readers)),
      rank_(rank),
      preparation_(preparation),
      placed_(placed),
      budgetLeft_(budgetBytes),
      kept_(scans_.size()),
      packed_(scans_.size()),
      keptBytes_(scans_.size(), 0),
      movable_(scans_.size(), 0) {}

void HeldScans::append(const std::vector<io::ConfScan>& more, const std::vector<int>& readers) {
  scans_.insert(scans_.end(), more.begin(), more.end());
  readers_.insert(readers_.end(), readers.begin(), readers.end());
  kept_.resize(scans_.size());
  packed_.resize(scans_.size());
  keptBytes_.resize(scans_.size(), 0);
  movable_.resize(scans_.size(), 0);
}

PrismScan HeldScans::load(size_t i) const {
  const ScanPreparation& p = preparation_;
  PrismScan s = loadScan(scans_[i], p.surface, p.limits, p.eps);
  if (placed_) s = placeScan(std::move(s), scans_[i].pose);
  return p.compact ? compactScan(std::move(s)) : s;
}

std::shared_ptr<const PrismScan> HeldScans::get(size_t i) const {
  if (kept_[i]) return kept_[i];
  if (!packed_[i].empty()) return std::make_shared<const PrismScan>(unpackedScan(packed_[i]));
  return std::make_shared<const PrismScan>(load(i));
}

std::vector<PrismScan> HeldScans::read(const std::vector<size_t>& which, int threads) const {
  std::vector<const io::ConfScan*> list;
  for (size_t i : which) list.push_back(&scans_[i]);
  const ScanPreparation& p = preparation_;
  std::vector<PrismScan> out = loadScans(list, p.surface, p.limits, p.eps, threads);
  if (placed_ || p.compact)
    parallelFor(out.size(), threads, [&](size_t k) {
      if (placed_) out[k] = placeScan(std::move(out[k]), scans_[which[k]].pose);
      if (p.compact) out[k] = compactScan(std::move(out[k]));
    });
  return out;
}

std::shared_ptr<const PrismScan> HeldScans::readAndOffer(size_t i) {
  return offer(i, get(i));
}

std::vector<std::shared_ptr<const PrismScan>> HeldScans::readAndOffer(
    const std::vector<size_t>& which, int threads) {
  std::vector<size_t> unread;
  for (size_t i : which)
    if (!kept_[i]) unread.push_back(i);
  std::vector<PrismScan> fresh = read(unread, threads);
  std::vector<std::shared_ptr<const PrismScan>> out;
  size_t next = 0;
  for (size_t i : which) out.push_back(kept(i) ? get(i) : offer(i, std::move(fresh[next++])));
  return out;
}

void HeldScans::keep(size_t i, std::shared_ptr<const PrismScan> scan, uint64_t bytes) {
  kept_[i] = std::move(scan);
  hold(i, bytes);
}

void HeldScans::hold(size_t i, uint64_t bytes) {
  budgetLeft_ -= bytes;
  keptTotal_ += bytes;
  keptBytes_[i] = bytes;
  memoryLedger().set(Held::keptScans, keptTotal_);
}

std::shared_ptr<const PrismScan> HeldScans::offer(size_t i, std::shared_ptr<const PrismScan> scan) {
  if (kept(i)) return scan;
  if (preparation_.compact) {
    offerPacked(i, packedScan(*scan));
    return scan;
  }
  const uint64_t bytes = scanBytes(*scan);
  if (bytes <= budgetLeft_) keep(i, scan, bytes);
  return scan;
}

std::shared_ptr<const PrismScan> HeldScans::offer(size_t i, PrismScan&& scan) {
  // Made here, not const: take() may move it out again.
  std::shared_ptr<const PrismScan> made = std::make_shared<PrismScan>(std::move(scan));
  offer(i, made);
  if (kept_[i] == made) movable_[i] = 1;
  return made;
}

void HeldScans::offerPacked(size_t i, std::vector<char>&& bytes) {
  if (kept(i) || bytes.size() > budgetLeft_) return;
  const uint64_t size = bytes.size();
  packed_[i] = std::move(bytes);
  hold(i, size);
}

PrismScan HeldScans::take(size_t i) {
  if (!packed_[i].empty()) {
    PrismScan scan = unpackedScan(packed_[i]);
    release(i);
    return scan;
  }
  if (!kept_[i]) return load(i);
  std::shared_ptr<const PrismScan> scan = kept_[i];
  const bool movable = movable_[i];
  release(i);
  // A scan made here (offered by value) was made non-const and is handed out only as a const
  // view: when no view is left, it is moved out instead of copied.
  if (movable && scan.use_count() == 1) return std::move(const_cast<PrismScan&>(*scan));
  return *scan;
}

std::vector<char> HeldScans::takePacked(size_t i) {
  std::vector<char> bytes = std::move(packed_[i]);
  packed_[i].clear();
  if (!bytes.empty()) release(i);
  return bytes;
}

void HeldScans::release(size_t i) {
  budgetLeft_ += keptBytes_[i];
  keptTotal_ -= keptBytes_[i];
  keptBytes_[i] = 0;
  movable_[i] = 0;
  kept_[i].reset();
  std::vector<char>().swap(packed_[i]);
  memoryLedger().set(Held::keptScans, keptTotal_);
}

size_t HeldScans::keptCount() const {
  return static_cast<size_t>(
      std::count_if(kept_.begin(), kept_.end(), [](const auto& s) { return s != nullptr; }) +
      std::count_if(packed_.begin(), packed_.end(), [](const auto& b) { return !b.empty(); }));
}

std::shared_ptr<HeldScans> heldScans(std::vector<io::ConfScan> scans, std::vector<int> readers,
                                     int rank, const ReadSettings& read) {
  ScanPreparation preparation{read.surface, read.limits, read.eps};
  preparation.surface.sightMap = false;
  // Held for registration or tracking, whose fits follow the field's gradients: a depth frame's
  // normals filtered further smooth them, and fits lose what they pinned (decision 51).
  preparation.surface.depthNormalPasses = -1;
  return std::make_shared<HeldScans>(std::move(scans), std::move(readers), rank, preparation,
                                     read.keepBytes);
}

}  // namespace rangefuse
