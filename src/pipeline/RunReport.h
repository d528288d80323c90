// The run report: inputs, parameters, per-rank stage times and counters, mesh size.
#pragma once

#include <mpi.h>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/Progress.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Registration.h"

namespace rangefuse {

/// This process's peak resident memory, MiB.
uint64_t peakMemoryMiB();

/// Collective: gathers every rank's stage times and counters; rank 0 writes the JSON report
/// to the report path of `settings`. Throws InputError on a write failure (on rank 0).
void writeRunReport(const RunSettings& settings, MPI_Comm comm, const Progress& progress,
                    const RankCounters& counters, const FusedField& field, const MeshPart& mesh,
                    const std::vector<RegistrationStep>& steps);

}  // namespace rangefuse
