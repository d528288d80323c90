// rangefuse: fuse range images into one mesh on MPI ranks.
#include <hdf5.h>
#include <mpi.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include "Commands.h"

namespace {

const char* kUsage =
    "usage: rangefuse COMMAND [options]\n"
    "commands:\n"
    "  fuse    fuse range scans (.conf + range-grid PLY) into one mesh\n"
    "  eval    compare a mesh with a reference mesh, or poses with reference poses\n"
    "  mesh    the stitched mesh of a checkpoint's field\n"
    "  info    what a checkpoint holds\n"
    "  perturb the scanner's pose perturbation applied to a .conf\n"
    "  render  a PNG of the fused field: ray-cast surface or distance slice\n"
    "  scan    synthetic range scans of a mesh or built-in shape, with ground truth\n"
    "run 'rangefuse COMMAND --help' for the options of a command;\n"
    "run under mpirun to spread the volume over ranks.\n";

}  // namespace

int main(int argc, char** argv) {
  // Open MPI's shared-memory shared-file-pointer component keeps a semaphore per file name; a
  // writer killed mid-checkpoint leaves it locked and the next open of that name hangs. We
  // never use shared file pointers, so leave that component out (unless the user chose).
  setenv("OMPI_MCA_sharedfp", "^sm", 0);
  MPI_Init(&argc, &argv);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become our own messages
  int rank = 0, code = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "fuse") {
    code = rangefuse::cli::fuseCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "mesh") {
    code = rangefuse::cli::meshCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "info") {
    code = rangefuse::cli::infoCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "perturb") {
    code = rangefuse::cli::perturbCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "render") {
    code = rangefuse::cli::renderCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "scan") {
    code = rangefuse::cli::scanCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "eval") {
    code = rangefuse::cli::evalCommand(argc - 1, argv + 1, MPI_COMM_WORLD);
  } else if (command == "--help" || command == "-h") {
    if (rank == 0) std::cout << kUsage;
  } else {
    if (rank == 0)
      std::cerr << "rangefuse: error: "
                << (command.empty() ? "no command given" : "unknown command '" + command + "'")
                << "\n"
                << kUsage;
    code = 2;
  }
  MPI_Finalize();
  return code;
}
