#include "rangefuse/parallel/Mpi.h"

#include <iostream>
#include <numeric>

namespace rangefuse::mpi {

int rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

bool agree(bool ok, const std::string& message, MPI_Comm comm) {
  int mine = ok ? size(comm) : rank(comm), first = 0;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size(comm)) return true;
  if (first == rank(comm)) std::cerr << "rangefuse: error: " << message << std::endl;
  return false;
}

std::vector<char> gatherBytes(const std::vector<char>& mine, int root, MPI_Comm comm) {
  const int n = size(comm);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(n), displs(n);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  std::vector<char> all;
  if (rank(comm) == root) {
    std::exclusive_scan(counts.begin(), counts.end(), displs.begin(), 0);
    all.resize(displs.back() + counts.back());
  }
  MPI_Gatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), displs.data(), MPI_CHAR,
              root, comm);
  return all;
}

std::vector<std::vector<char>> allgatherBytes(const std::vector<char>& mine, MPI_Comm comm) {
  const int n = size(comm);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(n), displs(n);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  std::exclusive_scan(counts.begin(), counts.end(), displs.begin(), 0);
  std::vector<char> all(displs.back() + counts.back());
  MPI_Allgatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), displs.data(), MPI_CHAR,
                 comm);
  std::vector<std::vector<char>> out(n);
  for (int r = 0; r < n; ++r)
    out[r].assign(all.begin() + displs[r], all.begin() + displs[r] + counts[r]);
  return out;
}

std::vector<std::vector<char>> exchangeBytes(const std::vector<std::vector<char>>& out,
                                             MPI_Comm comm) {
  const int n = size(comm);
  std::vector<int> sendCounts(n), recvCounts(n), sdispl(n), rdispl(n);
  std::vector<char> send;
  for (int r = 0; r < n; ++r) {
    sendCounts[r] = static_cast<int>(out[r].size());
    sdispl[r] = static_cast<int>(send.size());
    send.insert(send.end(), out[r].begin(), out[r].end());
  }
  MPI_Alltoall(sendCounts.data(), 1, MPI_INT, recvCounts.data(), 1, MPI_INT, comm);
  std::exclusive_scan(recvCounts.begin(), recvCounts.end(), rdispl.begin(), 0);
  std::vector<char> recv(rdispl.back() + recvCounts.back());
  MPI_Alltoallv(send.data(), sendCounts.data(), sdispl.data(), MPI_CHAR, recv.data(),
                recvCounts.data(), rdispl.data(), MPI_CHAR, comm);
  std::vector<std::vector<char>> in(n);
  for (int r = 0; r < n; ++r)
    in[r].assign(recv.begin() + rdispl[r], recv.begin() + rdispl[r] + recvCounts[r]);
  return in;
}

std::string broadcastString(const std::string& s, int root, MPI_Comm comm) {
  int n = static_cast<int>(s.size());
  MPI_Bcast(&n, 1, MPI_INT, root, comm);
  std::string out = s;
  out.resize(n);
  MPI_Bcast(out.data(), n, MPI_CHAR, root, comm);
  return out;
}

}  // namespace rangefuse::mpi
