// The registration stage of a fuse run: options, progress lines and checkpoints around
// registerScans.
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// Collective: refines scans.poses as --register asks, continuing from `state`, writing
/// checkpoints at boundaries when --checkpoint is set; rank 0 prints a line per fit. False
/// when any rank failed (reported once).
bool registerPoses(const FuseOptions& options, MPI_Comm comm, Progress& progress,
                   LoadedScans& scans, RegistrationProgress& state,
                   std::vector<RegistrationStep>& steps);

}  // namespace rangefuse
