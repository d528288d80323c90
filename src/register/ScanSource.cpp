#include "rangefuse/register/ScanSource.h"

namespace rangefuse {

ScansInMemory::ScansInMemory(std::vector<PrismScan> scans) {
  for (PrismScan& s : scans)
    scans_.push_back(s.surface.points.empty() ? nullptr
                                              : std::make_shared<const PrismScan>(std::move(s)));
}

}  // namespace rangefuse
