// Where a rank's memory goes: the stages set the bytes of the parts they hold, and the ledger
// keeps each part's bytes at the moment their sum peaked, so that a run can say what its peak
// was made of (the run report's memory breakdown).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rangefuse {

/// The parts of a rank's memory the stages account for.
enum class Held {
  keptScans,    ///< prepared scans kept between reading and fusing (--scan-memory)
  routedScans,  ///< scan parts routed to this rank's bricks for the routing window in hand
  field,        ///< the bricks' sums (and colours)
  integrator,   ///< the integrator's per-voxel index and per-thread sample lists
  brickList,    ///< the brick layout, and the (brick, work) pairs while planning it
  sightMaps,    ///< robust fusion: every scan's sight map
  count
};

/// The name of a part in reports ("kept_scans", ...).
const char* heldName(Held part);

/// Bytes per part now, and per part when their sum was largest.
class MemoryLedger {
 public:
  static constexpr size_t kParts = static_cast<size_t>(Held::count);
  using Bytes = std::array<uint64_t, kParts>;

  /// Part `part` now holds `bytes`.
  void set(Held part, uint64_t bytes);
  /// Every part's bytes when their sum peaked.
  const Bytes& atPeak() const { return atPeak_; }
  uint64_t peakTotal() const { return peakTotal_; }
  /// Forgets everything and notes what the process holds before the run: its code,
  /// libraries and MPI (a new run in the same process starts again here).
  void start();
  uint64_t processBytes() const { return processBytes_; }

 private:
  Bytes now_{}, atPeak_{};
  uint64_t total_ = 0, peakTotal_ = 0, processBytes_ = 0;
};

/// The process's ledger. Stages write it from the main thread only.
MemoryLedger& memoryLedger();

/// Resident bytes of this process now (0 where /proc is not there).
uint64_t residentBytes();

}  // namespace rangefuse
