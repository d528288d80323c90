#include "rangefuse/core/MemoryLedger.h"

#include <unistd.h>

#include <fstream>

namespace rangefuse {

const char* heldName(Held part) {
  switch (part) {
    case Held::keptScans:
      return "kept_scans";
    case Held::routedScans:
      return "routed_scans";
    case Held::field:
      return "field";
    case Held::integrator:
      return "integrator";
    case Held::brickList:
      return "brick_list";
    case Held::sightMaps:
      return "sight_maps";
    case Held::count:
      break;
  }
  return "?";
}

void MemoryLedger::set(Held part, uint64_t bytes) {
  uint64_t& held = now_[static_cast<size_t>(part)];
  total_ = total_ - held + bytes;
  held = bytes;
  if (total_ > peakTotal_) peakTotal_ = total_, atPeak_ = now_;
}

void MemoryLedger::start() {
  *this = MemoryLedger{};
  processBytes_ = residentBytes();
}

MemoryLedger& memoryLedger() {
  static MemoryLedger ledger;
  return ledger;
}

uint64_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  uint64_t pages = 0, resident = 0;
  if (!(statm >> pages >> resident)) return 0;
  return resident * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace rangefuse
