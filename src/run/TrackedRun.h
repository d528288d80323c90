// The run of a depth stream without poses (private to the fuse stage): tracked frame by frame
// into its field, then meshed, or refined by Algorithm 2 and fused again.
#pragma once

#include <mpi.h>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/Progress.h"

namespace rangefuse::internal {

/// Collective: whether the run tracks a depth stream (reads the scan list). False on failure
/// (printed once).
bool decideTracking(const ReadSettings& read, const StreamSettings& track, MPI_Comm comm,
                    bool& tracking);

/// Collective: the whole tracked run, from the stream's first frame or from `resumed`, a
/// checkpoint at stage "tracking". Returns the run's exit code.
int runTracking(const RunSettings& settings, MPI_Comm comm, Progress& progress,
                const io::CheckpointMeta* resumed = nullptr);

}  // namespace rangefuse::internal
