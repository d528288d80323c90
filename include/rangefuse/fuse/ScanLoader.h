// Scan-parallel loading: each rank reads and prepares a share of the scans; then either all
// ranks receive every prepared scan (registration, closest-surface methods) or each triangle
// is routed to the ranks owning the bricks its prism touches (streamed prism fields).
#pragma once

#include <mpi.h>

#include <utility>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

using IndexedScans = std::vector<std::pair<size_t, PrismScan>>;

/// Reads one scan, triangulates it, filters its normals and computes its prism limits, in the
/// scan's own frame. Throws InputError naming the file on bad input.
PrismScan loadScan(const io::ConfScan& scan, const SurfaceOptions& options,
                   const InputLimits& limits, double eps);

/// loadScan for several scans at once, on up to `threads` threads; the same scans, in order.
std::vector<PrismScan> loadScans(const std::vector<const io::ConfScan*>& scans,
                                 const SurfaceOptions& options, const InputLimits& limits,
                                 double eps, int threads);

/// Reads, triangulates and computes prism limits for the scans i with i % ranks == rank, in
/// each scan's own frame (poses are applied later, as registration moves them). Throws
/// InputError naming the file on bad input.
IndexedScans loadScanShare(const io::ConfFile& conf, const SurfaceOptions& options,
                           const InputLimits& limits, double eps, int rank, int ranks);

/// Bytes a prepared scan holds (points, normals, confidences, triangles, limits).
uint64_t scanBytes(const PrismScan& scan);

/// What routing sent: input triangles, triangle copies made, bytes per destination rank.
struct RoutingStats {
  uint64_t triangles = 0, copies = 0;
  std::vector<uint64_t> bytes;
};

/// Appends to out[r], for every rank r owning a brick some triangle of the placed scan must
/// reach, the part of the scan made of those triangles (in order) and their vertices. With
/// reach 0 a triangle reaches the bricks its prism touches (prism fields); with reach > 0, the
/// bricks with a voxel centre within reach of its bounding box (closest-surface methods). A
/// triangle that reaches no existing brick goes nowhere. The part for rank `me` (none when -1)
/// is appended to `mine` instead, unserialised (the whole scan when it all goes there).
void routeScan(uint64_t index, PrismScan world, const BrickLayout& layout, double reach, int me,
               std::vector<std::vector<char>>& out, IndexedScans& mine, RoutingStats& stats);

/// The scan parts received from every rank, in scan order.
IndexedScans unpackRouted(std::vector<std::vector<char>>&& in);

/// Appends the scans packed in one rank's `bytes` to `into`, unsorted, and frees the bytes.
void unpackRoutedInto(std::vector<char>&& bytes, IndexedScans& into);

/// Parts of one scan as one: their vertices and triangles in turn (the first one's sensor).
PrismScan joinScans(std::vector<PrismScan>&& parts);

/// A scan-frame scan moved to the world by pose (prism limits are rigid-invariant).
PrismScan placeScan(PrismScan local, const Pose& pose);

}  // namespace rangefuse
