// How rangefuse starts MPI: Open MPI's components chosen for the job, unless the user chose.
#pragma once

namespace rangefuse::mpi {

/// Starts MPI with funnelled threads (worker threads compute; only the calling thread calls
/// MPI), first setting rangefuse's defaults for Open MPI where the environment names none:
/// - no shared-memory shared file pointers (`sharedfp ^sm`): a writer killed mid-checkpoint
///   leaves that component's semaphore locked, and the next open of the file name hangs;
/// - a waiting rank yields its core (`mpi_yield_when_idle`), so that a tracked rank's idle
///   thread prepares its next frame then (decision 50);
/// - a job whose processes all run on this machine uses the `ob1` messaging layer (shared
///   memory), without probing the network interfaces that the `cm` layer would try first
///   (Omni-Path, PSM, libfabric): 0.2 s of every start on a machine without them.
/// An `OMPI_MCA_...` variable the user set always wins; other MPIs ignore these.
void start(int* argc, char*** argv);

/// True when every process of the job runs on this machine: launched by Open MPI's mpirun
/// onto one node, or started alone, with no launcher's variables at all. A job launched by
/// another launcher (srun, hydra) is not known to be, and is left as it is.
bool jobOnOneMachine();

}  // namespace rangefuse::mpi
