// The end of every kind of fuse run (private to the fuse stage): the field checkpointed, then
// meshed and written with the poses and the report.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse::internal {

/// Called once bricks are planned (buildStreamed's `planned`): rank 0 warns when the
/// checkpoint or the mesh may not fit where they go.
std::function<void(const BrickLayout&)> storageWarner(const RunSettings& settings, MPI_Comm comm);

/// Collective: writes the finished field to the run's checkpoint, when it has one. False on
/// failure (printed once).
bool writeFieldCheckpoint(const CheckpointWriting& checkpoints, MPI_Comm comm, Progress& progress,
                          const LoadedScans& scans, const FusedField& field);

/// Collective: this rank's part of a finished field's mesh, closed across holes when `mesh`
/// asks (carving with the field's sight maps). Throws mpi::Reported on every rank when the
/// field has no sight maps to carve with (printed once).
MeshPart meshField(const MeshSettings& mesh, MPI_Comm comm, const FusedField& field,
                   MeshStats& stats);
/// Collective: the mesh of a finished field, its outputs, the poses and the report. Returns
/// the run's exit code.
int finish(const RunSettings& settings, MPI_Comm comm, Progress& progress, const LoadedScans& scans,
           FusedField& field, RankCounters& counters, const std::vector<RegistrationStep>& steps);

}  // namespace rangefuse::internal
