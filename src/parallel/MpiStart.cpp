#include "rangefuse/parallel/MpiStart.h"

#include <mpi.h>

#include <cstdlib>
#include <cstring>

namespace rangefuse::mpi {

bool jobOnOneMachine() {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (size) return local && std::strcmp(size, local) == 0;
  // Launchers that set none of Open MPI's variables still leave their own.
  for (const char* launcher : {"PMIX_RANK", "PMI_RANK", "PMI_FD", "SLURM_PROCID"})
    if (std::getenv(launcher)) return false;
  return true;
}

void start(int* argc, char*** argv) {
  setenv("OMPI_MCA_sharedfp", "^sm", 0);
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
  if (jobOnOneMachine()) setenv("OMPI_MCA_pml", "ob1", 0);
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
}

}  // namespace rangefuse::mpi
