// The main job: scans + poses -> prism fields on distributed bricks -> stitched mesh. The
// options are the table's (FuseParameters.h); runFuse completes them into the run's settings
// (RunSettings.h) once, then runs one of four paths: a streamed field at the given poses,
// registration then a streamed field, a tracked depth stream, or a resumed checkpoint.
#pragma once

#include <mpi.h>

#include <string>

#include "rangefuse/options/FuseParameters.h"

namespace rangefuse {

/// Runs the whole job on every rank of comm. Returns the process exit code: 0 on success, 1
/// when any rank failed (the failure is printed once, by the lowest failing rank).
int runFuse(const FuseOptions& options, MPI_Comm comm);

}  // namespace rangefuse
