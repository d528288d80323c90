// Figures per rank for the progress lines of a run (private to the fuse stage). Each is
// collective; the text is meaningful on rank 0.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

namespace rangefuse::internal {

/// "a / b / c": the value of every rank, in rank order.
std::string perRank(MPI_Comm comm, uint64_t value);

/// "a / b / c s": seconds per rank, two decimals.
std::string secondsPerRank(MPI_Comm comm, double seconds);

/// " (max/mean X)" of a value across ranks, when there are several (else empty).
std::string balance(MPI_Comm comm, uint64_t value);

}  // namespace rangefuse::internal
