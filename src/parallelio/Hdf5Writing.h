// Parallel HDF5 writing shared by the checkpoint and the mesh writers (private to io/): every
// step that may fail on one rank is agreed on before the next collective, so that all ranks
// leave a writer at the same step and none waits in a collective another has left.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <functional>
#include <stdexcept>
#include <string>

namespace rangefuse::io::internal {

/// Owns an HDF5 handle; closes it with the matching function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }
  bool ok() const { return id_ >= 0; }
  /// Closes now, returning the status (a file's close writes what HDF5 still buffers).
  herr_t close() {
    const herr_t status = id_ >= 0 ? close_(id_) : 0;
    id_ = -1;
    return status;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// Throws InputError "path: what" unless ok (a step of one rank alone).
void check(bool ok, const std::string& path, const std::string& what);

/// Thrown on the ranks whose step succeeded when another rank's failed.
struct OtherRankFailed : std::runtime_error {
  OtherRankFailed() : std::runtime_error("a step failed on another rank") {}
};

/// Collective: a write step that every rank must pass before the next collective one.
void together(bool ok, const std::string& message, MPI_Comm comm);
void together(bool ok, const std::string& path, const std::string& what, MPI_Comm comm);

/// File access through MPI-IO on comm.
Handle accessList(MPI_Comm comm);

/// Collective: a 1-D (cols = 0) or 2-D dataset of `type`, rows x cols.
Handle createDataset(hid_t file, const char* name, hid_t type, hsize_t rows, hsize_t cols,
                     const std::string& path, MPI_Comm comm);

/// Collective: writes rows [first, first + count) of a dataset from this rank (count may be 0).
void writeRows(hid_t set, hid_t type, hsize_t first, hsize_t count, hsize_t cols, const void* data,
               const std::string& path, const char* name, MPI_Comm comm);

/// Collective: runs `write` (which makes `tmp`) on every rank. Returns "" when every rank
/// succeeded; otherwise removes tmp and returns, on every rank, the message of the lowest rank
/// that had one.
std::string agreeOnWrite(const std::string& tmp, MPI_Comm comm, const std::function<void()>& write);

/// Collective: rank 0 renames tmp to path; throws InputError on every rank if it could not.
void renameIntoPlace(const std::string& tmp, const std::string& path, MPI_Comm comm);

}  // namespace rangefuse::io::internal
