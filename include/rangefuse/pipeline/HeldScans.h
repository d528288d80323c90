// The scans a rank read for registration, in their own frames: kept in memory while they fit a
// budget (--scan-memory), the rest read again from their files whenever a field needs them.
#pragma once

#include <memory>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/register/ScanSource.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// How a scan is prepared when read (again).
struct ScanPreparation {
  SurfaceOptions surface;
  InputLimits limits;
  double eps = 0;  ///< prism envelope, in the scans' units
  /// Made compact once placed (compactScan), and kept packed as routing sends them, a third of
  /// the memory: a streamed field's scans. A kept scan then holds what a field needs only; its
  /// reader takes the sight map, noise and colour kind before offering it.
  bool compact = false;
};

/// A rank's share of a scan list, kept in memory within a budget: the scans it reads (its
/// readers say which), prepared as `preparation` says, each kept while it fits what is left of
/// the budget and read again from its file whenever it is needed otherwise. Registration and
/// tracking hold scans in their own frames (their poses change); a streamed field holds them
/// placed at the list's poses (`placed`).
class HeldScans : public ScanSource {
 public:
  /// `readers`: the rank reading each scan; this rank is `rank`. Nothing is read yet.
  HeldScans(std::vector<io::ConfScan> scans, std::vector<int> readers, int rank,
            ScanPreparation preparation, uint64_t budgetBytes, bool placed = false);

  size_t size() const override { return scans_.size(); }
  bool holds(size_t i) const override { return readers_[i] == rank_; }
  bool kept(size_t i) const override { return kept_[i] != nullptr || !packed_[i].empty(); }
  /// Scan i: the kept one (unpacked: a copy), or one read again (not kept). Safe on several
  /// threads at once.
  std::shared_ptr<const PrismScan> get(size_t i) const override;

  /// The rank that reads scan i.
  int reader(size_t i) const { return readers_[i]; }
  /// Hands each scan to the rank that read it (reading shared out as it went, the same list
  /// on every rank): that rank keeps it or reads it again from here on.
  void setReaders(std::vector<int> readers) { readers_ = std::move(readers); }

  /// The listed scans read from their files on up to `threads` threads, in order, whether kept
  /// or not; none is kept (offer them).
  std::vector<PrismScan> read(const std::vector<size_t>& which, int threads) const;

  /// Reads scan i (held here) and keeps it if it fits what is left of the budget.
  std::shared_ptr<const PrismScan> readAndOffer(size_t i);
  /// readAndOffer for the listed scans, read on up to `threads` threads and offered in order.
  std::vector<std::shared_ptr<const PrismScan>> readAndOffer(const std::vector<size_t>& which,
                                                             int threads);

  /// Keeps scan i, read elsewhere (another thread), if it fits what is left of the budget.
  std::shared_ptr<const PrismScan> offer(size_t i, std::shared_ptr<const PrismScan> scan);
  std::shared_ptr<const PrismScan> offer(size_t i, PrismScan&& scan);
  /// Keeps scan i, compact and packed already (packedScan), if it fits what is left.
  void offerPacked(size_t i, std::vector<char>&& bytes);

  /// Scan i for its last use: the kept one handed over (moved out when no one else holds it)
  /// and forgotten, or one read again.
  PrismScan take(size_t i);

  /// Scan i's packed bytes for its last use, forgotten here, when it is kept packed; else
  /// nothing (take it).
  std::vector<char> takePacked(size_t i);

  /// Forgets scan i (a tracked frame once fused), returning its bytes to the budget.
  void release(size_t i);

  /// Lets go of scan i's images handed over in memory (ConfScan::memory), for good: a tracked
  /// frame no longer needed. Reading it again is then an error.
  void dropMemory(size_t i) { scans_[i].memory.reset(); }

  size_t keptCount() const;

  /// Scans that joined the list since (a stream that is still being recorded), with their
  /// readers; nothing is read yet.
  void append(const std::vector<io::ConfScan>& more, const std::vector<int>& readers);

 private:
  PrismScan load(size_t i) const;
  void keep(size_t i, std::shared_ptr<const PrismScan> scan, uint64_t bytes);
  /// Counts scan i's `bytes`, kept now, against the budget and in the memory ledger.
  void hold(size_t i, uint64_t bytes);

  std::vector<io::ConfScan> scans_;
  std::vector<int> readers_;
  int rank_;
  ScanPreparation preparation_;
  bool placed_;
  uint64_t budgetLeft_;
  uint64_t keptTotal_ = 0;  ///< bytes kept now, for the memory ledger
  std::vector<std::shared_ptr<const PrismScan>> kept_;
  std::vector<std::vector<char>> packed_;  ///< kept compact scans, packed
  std::vector<uint64_t> keptBytes_;
  std::vector<char> movable_;  ///< kept scans made here (offered by value), not const
};

/// The scans this rank reads for registration or tracking, prepared as `read` says without
/// sight maps (registration fields are prism or closest-surface fields; robust fusion's maps
/// are made when the final field streams the scans again), kept within read.keepBytes. Depth
/// frames take --normal-passes, not --depth-normal-passes.
std::shared_ptr<HeldScans> heldScans(std::vector<io::ConfScan> scans, std::vector<int> readers,
                                     int rank, const ReadSettings& read);

}  // namespace rangefuse
