#include "rangefuse/parallel/MpiTraffic.h"

#include <mpi.h>

#include <atomic>

namespace {

std::atomic<uint64_t> sent{0}, received{0}, calls{0};

uint64_t bytes(int count, MPI_Datatype type) {
  int size = 0;
  PMPI_Type_size(type, &size);
  return static_cast<uint64_t>(count) * static_cast<uint64_t>(size);
}

int ranks(MPI_Comm comm) {
  int n = 1;
  PMPI_Comm_size(comm, &n);
  return n;
}

bool isRoot(int root, MPI_Comm comm) {
  int me = 0;
  PMPI_Comm_rank(comm, &me);
  return me == root;
}

void tally(uint64_t out, uint64_t in) {
  sent.fetch_add(out, std::memory_order_relaxed);
  received.fetch_add(in, std::memory_order_relaxed);
  calls.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

namespace rangefuse::mpi {

Traffic traffic() {
  return {sent.load(), received.load(), calls.load()};
}

}  // namespace rangefuse::mpi

// The wrappers: MPI's profiling interface lets a program define the MPI_ names and call the
// library's PMPI_ ones.
extern "C" {

int MPI_Isend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm,
              MPI_Request* request) {
  tally(bytes(count, type), 0);
  return PMPI_Isend(buf, count, type, dest, tag, comm, request);
}

int MPI_Irecv(void* buf, int count, MPI_Datatype type, int source, int tag, MPI_Comm comm,
              MPI_Request* request) {
  tally(0, bytes(count, type));
  return PMPI_Irecv(buf, count, type, source, tag, comm, request);
}

int MPI_Allreduce(const void* sendbuf, void* recvbuf, int count, MPI_Datatype type, MPI_Op op,
                  MPI_Comm comm) {
  tally(bytes(count, type), bytes(count, type));
  return PMPI_Allreduce(sendbuf, recvbuf, count, type, op, comm);
}

int MPI_Reduce(const void* sendbuf, void* recvbuf, int count, MPI_Datatype type, MPI_Op op,
               int root, MPI_Comm comm) {
  tally(bytes(count, type), isRoot(root, comm) ? bytes(count, type) : 0);
  return PMPI_Reduce(sendbuf, recvbuf, count, type, op, root, comm);
}

int MPI_Exscan(const void* sendbuf, void* recvbuf, int count, MPI_Datatype type, MPI_Op op,
               MPI_Comm comm) {
  tally(bytes(count, type), bytes(count, type));
  return PMPI_Exscan(sendbuf, recvbuf, count, type, op, comm);
}

int MPI_Bcast(void* buffer, int count, MPI_Datatype type, int root, MPI_Comm comm) {
  const bool mine = isRoot(root, comm);
  tally(mine ? bytes(count, type) : 0, mine ? 0 : bytes(count, type));
  return PMPI_Bcast(buffer, count, type, root, comm);
}

int MPI_Gather(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
               int recvcount, MPI_Datatype recvtype, int root, MPI_Comm comm) {
  tally(bytes(sendcount, sendtype),
        isRoot(root, comm) ? bytes(recvcount, recvtype) * ranks(comm) : 0);
  return PMPI_Gather(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, root, comm);
}

int MPI_Allgather(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                  int recvcount, MPI_Datatype recvtype, MPI_Comm comm) {
  tally(bytes(sendcount, sendtype), bytes(recvcount, recvtype) * ranks(comm));
  return PMPI_Allgather(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, comm);
}

int MPI_Alltoall(const void* sendbuf, int sendcount, MPI_Datatype sendtype, void* recvbuf,
                 int recvcount, MPI_Datatype recvtype, MPI_Comm comm) {
  tally(bytes(sendcount, sendtype) * ranks(comm), bytes(recvcount, recvtype) * ranks(comm));
  return PMPI_Alltoall(sendbuf, sendcount, sendtype, recvbuf, recvcount, recvtype, comm);
}

}  // extern "C"
