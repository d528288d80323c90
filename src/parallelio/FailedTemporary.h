// Clean-up after a parallel write that failed (private to parallelio/).
#pragma once

#include <string>

namespace rangefuse::io::internal {

/// Removes the temporary file `tmp` of a write that failed, with the lock files Open MPI's
/// shared-file-pointer component (sharedfp/lockedfile) makes beside it, named
/// `tmp-<job>-<pid>.lock`. A rank whose MPI_File_open fails after making its lock (on a full
/// file system, writing the lock's first bytes fails) never closes the file, and Open MPI
/// leaves the lock behind. Call on one rank, after every rank has left the write.
void removeFailedTemporary(const std::string& tmp);

}  // namespace rangefuse::io::internal
