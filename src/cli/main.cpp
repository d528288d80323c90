// rangefuse: fuse range images into one mesh on MPI ranks.
#include <hdf5.h>
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>

#include "Commands.h"
#include "InterruptHint.h"
#include "rangefuse/parallel/MpiStart.h"

namespace {

const char* kUsage =
    "usage: rangefuse COMMAND [options]\n"
    "commands:\n"
    "  fuse    fuse range scans into one mesh: a Stanford .conf of range-grid PLY files, a\n"
    "          Leica .ptx, an ASTM .e57, or a TUM RGB-D, Redwood or Open3D-recorder depth folder\n"
    "  eval    compare a mesh with a reference mesh, or poses with reference poses\n"
    "  mesh    the stitched mesh of a checkpoint's field\n"
    "  info    what a checkpoint holds\n"
    "  perturb the scanner's pose perturbation applied to a .conf\n"
    "  render  a PNG of the fused field: ray-cast surface or distance slice\n"
    "  scan    synthetic range scans of a mesh or built-in shape, with ground truth\n"
    "run 'rangefuse COMMAND --help' for the options of a command;\n"
    "run under mpirun to spread the volume over ranks; 'rangefuse --version' says which build.\n";

/// "rangefuse 0.1.0 (HDF5 1.10.8, Open MPI v4.1.4 ...)": what a bug report needs.
std::string versionLine() {
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  char mpi[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(mpi, &length);
  std::string library(mpi, static_cast<size_t>(length));
  library = library.substr(0, library.find_first_of(",\n"));
  return std::string("rangefuse ") + RANGEFUSE_VERSION + " (HDF5 " + std::to_string(major) + "." +
         std::to_string(minor) + "." + std::to_string(release) + ", " + library + ")";
}

/// True when any argument asks for the version (rangefuse --version, rangefuse fuse --version).
bool asksVersion(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--version") == 0) return true;
  return false;
}

int runCommand(int argc, char** argv, int rank) {
  using namespace rangefuse::cli;
  const std::string command = argc > 1 ? argv[1] : "";
  const MPI_Comm world = MPI_COMM_WORLD;
  if (asksVersion(argc, argv)) {
    if (rank == 0) std::cout << versionLine() << "\n";
    return 0;
  }
  if (command == "fuse") return fuseCommand(argc - 1, argv + 1, world);
  if (command == "mesh") return meshCommand(argc - 1, argv + 1, world);
  if (command == "info") return infoCommand(argc - 1, argv + 1, world);
  if (command == "perturb") return perturbCommand(argc - 1, argv + 1, world);
  if (command == "render") return renderCommand(argc - 1, argv + 1, world);
  if (command == "scan") return scanCommand(argc - 1, argv + 1, world);
  if (command == "eval") return evalCommand(argc - 1, argv + 1, world);
  if (command == "--help" || command == "-h") {
    if (rank == 0) std::cout << kUsage;
    return 0;
  }
  if (rank == 0)
    std::cerr << "rangefuse: error: "
              << (command.empty() ? "no command given" : "unknown command '" + command + "'")
              << "\n"
              << kUsage;
  return 2;
}

/// Runs the subcommand. Errors at stage boundaries are agreed on by every rank and come back
/// as exit codes; an exception that escapes here was thrown by one rank mid-stage, while the
/// others wait in a collective it will never join, so it ends the whole job at once.
int dispatch(int argc, char** argv, int rank) {
  try {
    return runCommand(argc, argv, rank);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rangefuse: error on rank %d: %s\n", rank, e.what());
  } catch (...) {
    std::fprintf(stderr, "rangefuse: error on rank %d: unknown exception\n", rank);
  }
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  rangefuse::mpi::start(&argc, &argv);  // worker threads read and compute; this one calls MPI
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors become our own messages
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  rangefuse::cli::installInterruptHint(rank == 0);
  const int code = dispatch(argc, argv, rank);
  MPI_Finalize();
  return code;
}
