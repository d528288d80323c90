// How much each pair of scans overlaps as the joint solve sees it, at its first step and at its
// last: poses that slide scans along each other keep every residual small but lose overlap,
// and only the overlap shows it.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// Two scans (a < b) and the control points of both in voxels both reached.
struct PairOverlap {
  uint32_t a = 0, b = 0;
  uint64_t first = 0;  ///< at the first joint step
  uint64_t last = 0;   ///< at the last joint step
};

/// Every pair that shared voxels at the first or the last joint step among `steps`, in (a, b)
/// order; empty when no step is a joint one.
std::vector<PairOverlap> pairOverlaps(const std::vector<RegistrationStep>& steps);

/// Fewer control points than this in a pair's overlap is too little to call it overlapping:
/// a few points at the fringe of two scans come and go as the poses move.
constexpr uint64_t kOverlapPoints = 50;

/// The pairs that overlapped at the first step (kOverlapPoints or more) and kept less than
/// `share` of it at the last (lost ones included).
size_t pairsLosing(const std::vector<PairOverlap>& pairs, double share);

/// The pairs overlapping (kOverlapPoints or more) at the first and at the last step.
std::pair<size_t, size_t> overlappingPairs(const std::vector<PairOverlap>& pairs);

}  // namespace rangefuse
