// Subcommands of the rangefuse executable; each takes argv after the subcommand name.
#pragma once

#include <mpi.h>

namespace rangefuse::cli {

/// `rangefuse fuse ...`: scans to one mesh (fields, registration, outputs).
int fuseCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse eval ...`: a mesh against a reference mesh, or poses against reference poses.
int evalCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse scan ...`: synthetic range scans with ground truth.
int scanCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse render ...`: pictures of the fused field.
int renderCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse perturb ...`: perturbed copies of real poses, for registration tests.
int perturbCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse mesh FILE.h5 --out M.ply`: the mesh of a checkpoint's field, on any ranks.
int meshCommand(int argc, char** argv, MPI_Comm comm);

/// `rangefuse info FILE.h5`: what a checkpoint holds.
int infoCommand(int argc, char** argv, MPI_Comm comm);

}  // namespace rangefuse::cli
