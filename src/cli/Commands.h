// Subcommands of the rangefuse executable.
#pragma once

#include <mpi.h>

namespace rangefuse::cli {

/// `rangefuse fuse ...`: argv starts after the subcommand name.
int fuseCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli

namespace rangefuse::cli {

/// `rangefuse eval --mesh M.ply --reference R.ply --voxel V`: accuracy and completeness.
int evalCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli

namespace rangefuse::cli {

/// `rangefuse scan ...`: synthetic range scans with ground truth.
int scanCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli

namespace rangefuse::cli {

/// `rangefuse render ...`: pictures of the fused field.
int renderCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli

namespace rangefuse::cli {

/// `rangefuse perturb ...`: perturbed copies of real poses, for registration tests.
int perturbCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli
