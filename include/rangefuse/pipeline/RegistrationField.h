// The field registration fits against in a fuse run: prism fields that grow scan by scan on
// one lattice, or (other methods) fields rebuilt from the listed scans.
#pragma once

#include <mpi.h>

#include <memory>
#include <string>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// The field for --register over `scans` (kept by reference): a growing prism field for
/// prism methods in `mode` grow, else rebuilt. `resumed` names the checkpoint a lattice
/// origin may come from. Its calls throw mpi::Reported on every rank when any rank failed (the
/// message printed once).
std::unique_ptr<RegistrationField> makeRegistrationField(const FieldSettings& field,
                                                         RegistrationFieldMode mode,
                                                         const std::string& resumed,
                                                         const LoadedScans& scans, MPI_Comm comm);

}  // namespace rangefuse
