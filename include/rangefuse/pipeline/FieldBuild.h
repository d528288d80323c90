// Building a run's field from its scan list: the scans read (held for registration and
// tracking, or streamed to the brick owners), the field planned, filled and evaluated, with a
// progress line for each stage.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "rangefuse/consensus/NearSurface.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"

namespace rangefuse {

/// Collective: reads the scans (each rank a share, kept within read.keepBytes, the rest read
/// again when needed), at `poses` when given (one per scan of the list) and without those
/// marked `lost` when given. False when any rank failed (the failure printed once).
bool loadScans(const ReadSettings& read, MPI_Comm comm, Progress& progress, LoadedScans& scans,
               const std::vector<Pose>* poses = nullptr, const std::vector<char>* lost = nullptr);

/// Collective: the field of the list's scans streamed to the brick owners, at `poses` (the
/// list's when null) and without those marked `lost`; scans gets their names, paths and poses.
/// `planned`, when set, is called on every rank once the bricks are known. False when any rank
/// failed (printed once).
bool buildStreamed(const ReadSettings& read, const FieldSettings& settings, MPI_Comm comm,
                   Progress& progress, LoadedScans& scans, FusedField& field,
                   RankCounters& counters, const std::vector<Pose>* poses = nullptr,
                   const std::vector<char>* lost = nullptr,
                   const std::function<void(const BrickLayout&)>& planned = nullptr);

/// Collective: buildStreamed at the list's poses, for commands that need only the field.
bool buildField(const ReadSettings& read, const FieldSettings& settings, MPI_Comm comm,
                Progress& progress, FusedField& field, RankCounters& counters);

/// How far from a brick the triangles a consensus or naive field needs there may lie: the
/// consensus margin plus the ball around the brick's voxel centres.
double routeReach(const FieldSettings& settings);

/// Consensus or naive distances near the surface of every local brick, from field.scans (all
/// scans, or the triangles routed to this rank within routeReach of its bricks). Registration
/// fields pass minViews 1: a scan is registered against what any placed view saw.
EvaluationStats evaluateClosestSurfaceField(const FieldSettings& settings, FusedField& field,
                                            int minViews);

/// The default quorum: Wheeler et al.'s 2.25 for 48 views, in proportion to the view count
/// (the number of views that see a surface point grows with the number of views).
double autoQuorum(size_t views);

}  // namespace rangefuse
