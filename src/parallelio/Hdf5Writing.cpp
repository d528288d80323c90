#include "Hdf5Writing.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "FailedTemporary.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::io::internal {

void check(bool ok, const std::string& path, const std::string& what) {
  if (!ok) throw InputError(path + ": " + what);
}

/// Collective: a write step that every rank must pass before the next collective one.
void together(bool ok, const std::string& message, MPI_Comm comm) {
  const int cause = ok ? 0 : errno;
  int mine = ok, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm);
  if (all) return;
  if (ok) throw OtherRankFailed();
  throw InputError(message + (cause ? std::string(" (") + std::strerror(cause) + ")" : ""));
}

void together(bool ok, const std::string& path, const std::string& what, MPI_Comm comm) {
  together(ok, path + ": " + what, comm);
}

Handle accessList(MPI_Comm comm) {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  return fapl;
}

/// A 1-D or 2-D dataset of `type`, rows x cols.
Handle createDataset(hid_t file, const char* name, hid_t type, hsize_t rows, hsize_t cols,
                     const std::string& path, MPI_Comm comm) {
  const hsize_t dims[2] = {rows, cols};
  Handle space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose);
  // No modification times: the same data gives the same bytes, run after run.
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl, 0);
  Handle set(H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose);
  together(set.ok(), path, std::string("cannot create dataset ") + name, comm);
  return set;
}

/// Writes rows [first, first + count) of a dataset from this rank (independent I/O).
void writeRows(hid_t set, hid_t type, hsize_t first, hsize_t count, hsize_t cols, const void* data,
               const std::string& path, const char* name, MPI_Comm comm) {
  Handle space(H5Dget_space(set), H5Sclose);
  const hsize_t start[2] = {first, 0}, size[2] = {count, cols};
  if (count == 0) {
    H5Sselect_none(space);
  } else {
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, size, nullptr);
  }
  Handle mem(H5Screate_simple(cols ? 2 : 1, size, nullptr), H5Sclose);
  if (count == 0) H5Sselect_none(mem);
  std::string injected;  // a test's fault (RANGEFUSE_FAULT=write:throw@RANK#N)
  try {
    faultPoint("write", path + " (" + name + ")");
  } catch (const std::exception& e) {
    injected = e.what();
  }
  errno = 0;
  const bool ok = injected.empty() && H5Dwrite(set, type, mem, space, H5P_DEFAULT, data) >= 0;
  together(ok, injected.empty() ? path + ": cannot write " + name : injected, comm);
}

std::string agreeOnWrite(const std::string& tmp, MPI_Comm comm,
                         const std::function<void()>& write) {
  std::string error;
  bool failed = false;
  try {
    write();  // on failure every rank unwinds from the same step
  } catch (const OtherRankFailed&) {
    failed = true;
  } catch (const std::exception& e) {
    error = e.what();
    failed = true;
  }
  int any = failed;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  if (!any) return "";
  const int size = mpi::size(comm);
  int from = error.empty() ? size : mpi::rank(comm);
  MPI_Allreduce(MPI_IN_PLACE, &from, 1, MPI_INT, MPI_MIN, comm);
  const std::string cause = from < size ? mpi::broadcastString(error, from, comm) : "";
  if (mpi::rank(comm) == 0) removeFailedTemporary(tmp);
  return cause.empty() ? "failed on another rank" : cause;
}

void renameIntoPlace(const std::string& tmp, const std::string& path, MPI_Comm comm) {
  int renamed = 0;
  if (mpi::rank(comm) == 0) renamed = std::rename(tmp.c_str(), path.c_str()) == 0;
  MPI_Bcast(&renamed, 1, MPI_INT, 0, comm);
  if (!renamed) throw InputError(path + ": cannot rename the temporary file into place");
}

}  // namespace rangefuse::io::internal
