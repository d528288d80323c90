#include "rangefuse/parallel/Threads.h"

#include <sched.h>

#include <algorithm>

namespace rangefuse {

int threadsPerRank(MPI_Comm comm) {
  // The affinity mask, not the machine's core count: mpirun may bind a rank to one core.
  cpu_set_t set;
  CPU_ZERO(&set);
  int cpus = sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : 1;
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int local = 1, sharing = 1;
  MPI_Comm_size(node, &local);
  MPI_Comm_free(&node);
  // Ranks bound to disjoint cores each see their own mask; unbound ranks all see every core.
  if (cpus >= static_cast<int>(std::thread::hardware_concurrency())) sharing = local;
  return std::max(1, cpus / sharing);
}

}  // namespace rangefuse
