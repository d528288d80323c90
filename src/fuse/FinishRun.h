// The end of every kind of fuse run (private to the fuse stage): the field checkpointed, then
// meshed and written with the poses and the report.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/fuse/RunSettings.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse::internal {

/// Called once bricks are planned (buildStreamed's `planned`): rank 0 warns when the
/// checkpoint or the mesh may not fit where they go.
std::function<void(const BrickLayout&)> storageWarner(const RunSettings& settings, MPI_Comm comm);

/// Collective: writes the finished field to the run's checkpoint, when it has one. False on
/// failure (printed once).
bool writeFieldCheckpoint(const CheckpointWriting& checkpoints, MPI_Comm comm, Progress& progress,
                          const LoadedScans& scans, const FusedField& field);

/// Collective: the mesh of a finished field, its outputs, the poses and the report. Returns
/// the run's exit code.
int finish(const RunSettings& settings, MPI_Comm comm, Progress& progress, const LoadedScans& scans,
           FusedField& field, RankCounters& counters, const std::vector<RegistrationStep>& steps);

}  // namespace rangefuse::internal
