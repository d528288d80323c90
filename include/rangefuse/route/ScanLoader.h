// Reading a scan and preparing it for a field: triangulated, normals filtered, prism limits
// computed, in the scan's own frame; placing it at a pose. Which rank reads which scan, and
// where the prepared triangles go, is routing's (route/ScanRouting.h).
#pragma once

#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/prism/PrismField.h"

namespace rangefuse {

/// Reads one scan, triangulates it, filters its normals and computes its prism limits, in the
/// scan's own frame. Throws InputError naming the file on bad input.
PrismScan loadScan(const io::ConfScan& scan, const SurfaceOptions& options,
                   const InputLimits& limits, double eps);

/// loadScan for several scans at once, on up to `threads` threads; the same scans, in order.
std::vector<PrismScan> loadScans(const std::vector<const io::ConfScan*>& scans,
                                 const SurfaceOptions& options, const InputLimits& limits,
                                 double eps, int threads);

/// Bytes a prepared scan holds (points, normals, confidences, triangles, limits).
uint64_t scanBytes(const PrismScan& scan);

/// A scan-frame scan moved to the world by pose (prism limits are rigid-invariant).
PrismScan placeScan(PrismScan local, const Pose& pose);

/// The scan with its points rounded to a lattice of its own (PrismScan::quantum, a power of two
/// about 2^-23 of its extent where that is under 2^-14 of the prisms' envelope, so 24-bit
/// offsets from the lattice point nearest its centre, else about 2^-30 and 32 bits), its
/// normals to the directions of 32-bit octahedral codes (within 1e-4 radians), its confidences
/// to 16-bit fractions and its prism limits to the nearest float: routed in those forms they
/// lose nothing, so every rank count sees the same values (decisions 45, 58). A compact scan
/// comes back as it is.
PrismScan compactScan(PrismScan scan);

}  // namespace rangefuse
