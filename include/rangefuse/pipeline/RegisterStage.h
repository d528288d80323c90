// The registration stage of a fuse run: options, progress lines and checkpoints around
// registerScans.
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// Collective: refines scans.poses as `registration` asks, on fields of `field`'s lattice and
/// method, continuing from `state` (a lattice origin in it came from `resumed`), writing
/// checkpoints at boundaries when `checkpoints` has a path; rank 0 prints a line per fit.
/// False when any rank failed (reported once).
bool registerPoses(const RegistrationSettings& registration, const FieldSettings& field,
                   const CheckpointWriting& checkpoints, const std::string& resumed, MPI_Comm comm,
                   Progress& progress, LoadedScans& scans, RegistrationProgress& state,
                   std::vector<RegistrationStep>& steps);

}  // namespace rangefuse
