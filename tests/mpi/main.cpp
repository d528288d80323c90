// GoogleTest main for tests that run on several MPI ranks; fails if any rank fails.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include "rangefuse/parallel/MpiStart.h"

int main(int argc, char** argv) {
  rangefuse::mpi::start(&argc, &argv);          // as the rangefuse executable does
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // as the executable: errors become messages
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) ::testing::GTEST_FLAG(brief) = true;  // other ranks print failures only
  int rc = RUN_ALL_TESTS(), worst = 0;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
