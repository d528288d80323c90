// The scans a rank read for registration, in their own frames: kept in memory while they fit a
// budget (--scan-memory), the rest read again from their files whenever a field needs them.
#pragma once

#include <memory>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/fuse/RunSettings.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/register/ScanSource.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// How a scan is prepared when read (again).
struct ScanPreparation {
  SurfaceOptions surface;
  InputLimits limits;
  double eps = 0;  ///< prism envelope, in the scans' units
};

class HeldScans : public ScanSource {
 public:
  /// `readers`: the rank reading each scan; this rank is `rank`. Nothing is read yet.
  HeldScans(std::vector<io::ConfScan> scans, std::vector<int> readers, int rank,
            ScanPreparation preparation, uint64_t budgetBytes);

  size_t size() const override { return scans_.size(); }
  bool holds(size_t i) const override { return readers_[i] == rank_; }
  bool kept(size_t i) const override { return kept_[i] != nullptr; }
  std::shared_ptr<const PrismScan> get(size_t i) const override;

  /// Reads scan i (held here) and keeps it if it fits what is left of the budget.
  std::shared_ptr<const PrismScan> readAndOffer(size_t i);
  /// readAndOffer for the listed scans, read on up to `threads` threads and offered in order.
  std::vector<std::shared_ptr<const PrismScan>> readAndOffer(const std::vector<size_t>& which,
                                                             int threads);

  /// Keeps scan i, read elsewhere (another thread), if it fits what is left of the budget.
  std::shared_ptr<const PrismScan> offer(size_t i, std::shared_ptr<const PrismScan> scan);

  /// Forgets scan i (a tracked frame once fused), returning its bytes to the budget.
  void release(size_t i);

  size_t keptCount() const;

  /// Scans that joined the list since (a stream that is still being recorded), with their
  /// readers; nothing is read yet.
  void append(const std::vector<io::ConfScan>& more, const std::vector<int>& readers);

 private:
  std::vector<io::ConfScan> scans_;
  std::vector<int> readers_;
  int rank_;
  ScanPreparation preparation_;
  uint64_t budgetLeft_;
  std::vector<std::shared_ptr<const PrismScan>> kept_;
  std::vector<uint64_t> keptBytes_;
};

/// The scans this rank reads for registration or tracking, prepared as `read` says without
/// sight maps (registration fields are prism or closest-surface fields; robust fusion's maps
/// are made when the final field streams the scans again), kept within read.keepBytes.
std::shared_ptr<HeldScans> heldScans(std::vector<io::ConfScan> scans, std::vector<int> readers,
                                     int rank, const ReadSettings& read);

}  // namespace rangefuse
