// Scan-parallel loading: each rank reads and prepares a share of the scans, then all
// ranks receive every prepared scan.
#pragma once

#include <mpi.h>

#include <utility>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

using IndexedScans = std::vector<std::pair<size_t, PrismScan>>;

/// Reads, triangulates and computes prism limits for the scans i with i % ranks == rank, in
/// each scan's own frame (poses are applied later, as registration moves them). Throws
/// InputError naming the file on bad input.
IndexedScans loadScanShare(const io::ConfFile& conf, const SurfaceOptions& options,
                           const InputLimits& limits, double eps, int rank, int ranks);

/// Collective: every rank's share on every rank, in .conf order.
std::vector<PrismScan> shareScans(const IndexedScans& mine, size_t total, MPI_Comm comm);

/// A scan-frame scan moved to the world by pose (prism limits are rigid-invariant).
PrismScan placeScan(const PrismScan& local, const Pose& pose);

}  // namespace rangefuse
