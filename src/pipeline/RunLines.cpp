#include "rangefuse/pipeline/RunLines.h"

#include <cstdio>
#include <sstream>
#include <vector>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {

std::string perRank(MPI_Comm comm, uint64_t value) {
  std::vector<uint64_t> all(mpi::size(comm));
  MPI_Gather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, comm);
  std::ostringstream s;
  for (size_t r = 0; r < all.size(); ++r) s << (r ? " / " : "") << all[r];
  return s.str();
}

std::string secondsPerRank(MPI_Comm comm, double seconds) {
  std::vector<double> all(mpi::size(comm));
  MPI_Gather(&seconds, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm);
  std::string text;
  char one[32];
  for (size_t r = 0; r < all.size(); ++r) {
    std::snprintf(one, sizeof one, "%s%.2f", r ? " / " : "", all[r]);
    text += one;
  }
  return text + " s";
}

std::string balance(MPI_Comm comm, uint64_t value) {
  if (mpi::size(comm) == 1) return "";
  uint64_t max = value, sum = value;
  MPI_Allreduce(MPI_IN_PLACE, &max, 1, MPI_UINT64_T, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  char text[40];
  std::snprintf(text, sizeof text, " (max/mean %.3f)",
                sum == 0 ? 1.0 : static_cast<double>(max) * mpi::size(comm) / sum);
  return text;
}

}  // namespace rangefuse::internal
