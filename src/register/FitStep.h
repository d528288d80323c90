// One rigid fit of one scan against the field (private to the registration code): Algorithm 1's
// step, shared by incremental registration and frame tracking.
#pragma once

#include <mpi.h>

#include "rangefuse/register/ControlRouting.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse::internal {

/// Collective: correspondences of scan i's control points (every `every`-th, for a coarse
/// level) at `pose`, summed across ranks, and the rigid update applied to `pose` (extrapolated
/// from `history` when steady). The step reports the sums before the fit.
RegistrationStep fitOnce(size_t i, Pose& pose, const BrickStore& field, ControlRouting& control,
                         const RegistrationOptions& o, MPI_Comm comm, FitHistory& history,
                         int every = 1);

}  // namespace rangefuse::internal
