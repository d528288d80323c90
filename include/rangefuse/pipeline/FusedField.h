// The fused field of a run: this rank's bricks, and what the stages after the field need.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "rangefuse/pipeline/TrackingSummary.h"
#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

/// The fused field of one job: every rank holds its own bricks, and all scans only when the
/// field was built from replicated scans (registration, closest-surface methods).
struct FusedField {
  /// Every scan, placed; when streamed, empty (prism) or, while the closest-surface field is
  /// evaluated, the triangles routed to this rank.
  std::vector<PrismScan> scans;
  size_t scanCount = 0;
  uint64_t scanTriangles = 0;
  uint64_t routedBytes = 0, routedCopies = 0;  ///< streamed: all ranks, to other ranks
  BrickLayout layout;
  std::unique_ptr<BrickStore> store;
  /// --fill-holes: every scan's sight map (the same on every rank), for carving.
  std::vector<SightMap> sights;
  /// A tracked stream: its frames' outcomes (rank 0's, for the report).
  std::optional<TrackingSummary> tracking;
};

}  // namespace rangefuse
