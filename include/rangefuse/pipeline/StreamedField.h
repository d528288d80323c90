// The prism field of many scans without any rank holding them all: each rank reads a share,
// plans bricks with the others from (brick, work) pairs only, then streams its scans, triangle
// by triangle, to the ranks owning the bricks their prisms touch.
#pragma once

#include <mpi.h>

#include <functional>
#include <optional>

#include "rangefuse/io/Conf.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/robust/SurfaceHypotheses.h"

namespace rangefuse {

/// What one streamed build needs besides the scans.
struct StreamOptions {
  double voxel = 0, eps = 0;  ///< voxel size and prism envelope, in the scans' units
  int brick = 8;
  SurfaceOptions surface;
  InputLimits limits;
  /// Prepared scans a rank keeps between passes (the rest are re-read); a quarter of it, a
  /// rank, bounds the scans of one routing window (route/RoutingPlan.h).
  uint64_t keepBytes = 0;
  int threads = 1;  ///< threads of this rank (reading scans, adding them to the field)
  /// PTX scans of more cells than this (0: none) are read in bands of columns, each by its own
  /// rank and added to the field as a scan of its own (ColumnBands.h).
  uint64_t bandCells = 0;
  /// 0: prism fields, parts integrated as they arrive. > 0: closest-surface methods, each
  /// scan's triangles within this reach of a local brick kept in FusedField::scans.
  double routeReach = 0;
  /// Set: robust fusion. Each reader also maps what its scans saw (SightMap), every rank gets
  /// every map, and images' samples become hypotheses resolved once all are in.
  std::optional<HypothesisParams> robust;
  /// Every scan's sight map shared with every rank and kept in FusedField::sights (closing
  /// holes carves with them).
  bool keepSights = false;
  /// The colour asked for (--colour; none: auto, see chooseColour). Prism fields only.
  std::optional<ColourKind> colour;
  /// Called on every rank once the bricks are planned, before the field pass (may be null).
  std::function<void(const BrickLayout&)> planned;
};

/// Collective: the prism field of the .conf's scans at the .conf's poses. Contributions reach
/// every voxel in scan order (a large scan's bands in turn), then triangle order, so the field
/// is the same on any rank count.
/// With routeReach > 0 the field is left empty and field.scans holds the routed triangles
/// instead. False when any rank failed (printed once).
bool buildStreamedField(const StreamOptions& options, const io::ConfFile& conf, MPI_Comm comm,
                        Progress& progress, FusedField& field, RankCounters& counters);

}  // namespace rangefuse
