// Thin MPI helpers: collective error agreement and vector gathers/exchanges.
#pragma once

#include <mpi.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace rangefuse::mpi {

int rank(MPI_Comm comm = MPI_COMM_WORLD);
int size(MPI_Comm comm = MPI_COMM_WORLD);

/// Collective: true when every rank passed ok. Otherwise the lowest failing rank prints
/// its message to stderr (once for the whole job; none when it is empty) and every rank gets
/// false.
bool agree(bool ok, const std::string& message, MPI_Comm comm = MPI_COMM_WORLD);

/// While one lives on this thread of every rank, agree() gives every rank the lowest failing
/// rank's message (the first failure's, kept) instead of printing it: the library throws it.
class CapturedFailure {
 public:
  CapturedFailure();
  ~CapturedFailure();
  CapturedFailure(const CapturedFailure&) = delete;
  CapturedFailure& operator=(const CapturedFailure&) = delete;

  /// Keeps `message` unless an earlier failure left one.
  void keep(const std::string& message);
  /// The first failure's message; empty when none.
  const std::string& message() const { return message_; }
  /// The capture of this thread, or null.
  static CapturedFailure* current();

 private:
  std::string message_;
  CapturedFailure* outer_;
};

/// Thrown on every rank after a failure all ranks agreed on and one rank already printed:
/// unwinds a collective stage without another message.
struct Reported : std::exception {
  const char* what() const noexcept override { return "failure reported above"; }
};

/// Collective: runs fn on every rank; if it throws anywhere, every rank returns false and the
/// lowest failing rank's message is printed once.
template <class Fn>
bool collectively(MPI_Comm comm, Fn&& fn) {
  std::string error;
  bool ok = true;
  try {
    fn();
  } catch (const Reported&) {
    ok = false;  // a nested stage failed on every rank and printed why
  } catch (const std::exception& e) {
    ok = false;
    error = e.what();
  }
  return agree(ok, error, comm);
}

/// Collective: as collectively, but a failure throws Reported on every rank, so that a stage in
/// the middle of a sequence of collectives unwinds on all ranks at the same step.
template <class Fn>
void collectivelyOrThrow(MPI_Comm comm, Fn&& fn) {
  if (!collectively(comm, fn)) throw Reported();
}

/// Largest message the byte helpers below send at once (1 GiB), so that no MPI count passes
/// INT_MAX however much they carry. Tests lower it with RANGEFUSE_MPI_CHUNK_BYTES to run the
/// chunked paths on small data.
uint64_t chunkBytes();

/// Gathers every rank's bytes to `root`, concatenated in rank order (empty elsewhere).
std::vector<char> gatherBytes(const std::vector<char>& mine, int root, MPI_Comm comm);

/// Collective: the box holding every rank's `mine` (empty boxes add nothing).
Eigen::AlignedBox3d unitedBox(const Eigen::AlignedBox3d& mine, MPI_Comm comm);

/// Collective: every rank's (index, text) entries joined, on `root` (empty elsewhere), or on
/// every rank when root is -1. An index given by several ranks keeps the highest rank's text.
std::map<size_t, std::string> gatherIndexed(const std::map<size_t, std::string>& mine, int root,
                                            MPI_Comm comm);

/// Collective: a value of `bytes` bytes at `value` passed along the ranks in rank order. Rank 0
/// starts from its own value; each later rank receives its predecessor's; each calls fold() on
/// it before passing it on; every rank returns holding the last rank's value. For totals whose
/// terms must be added in one order on any rank count (floating point is not associative).
void passAlong(void* value, size_t bytes, const std::function<void()>& fold, MPI_Comm comm);

/// Every rank's bytes, on every rank, indexed by rank.
std::vector<std::vector<char>> allgatherBytes(const std::vector<char>& mine, MPI_Comm comm);

/// Sends bytes out[r] to each rank r; returns what each rank sent to this one. Taken by value:
/// move it in, and this rank's own part is handed back without a copy.
std::vector<std::vector<char>> exchangeBytes(std::vector<std::vector<char>> out, MPI_Comm comm);

/// As exchangeBytes, but hands each rank's bytes to received(from, bytes) as soon as they
/// arrive (this rank's own first), so that only one incoming part is held at a time.
void exchangeBytes(std::vector<std::vector<char>> out, MPI_Comm comm,
                   const std::function<void(int, std::vector<char>&&)>& received);

/// Broadcasts a string from root.
std::string broadcastString(const std::string& s, int root, MPI_Comm comm);

/// Appends the raw bytes of trivially copyable values.
template <class T>
void pack(std::vector<char>& buf, const T* data, size_t n) {
  const char* p = reinterpret_cast<const char*>(data);
  buf.insert(buf.end(), p, p + n * sizeof(T));
}

/// Reads n values from buf at pos, advancing pos.
template <class T>
void unpack(const std::vector<char>& buf, size_t& pos, T* data, size_t n) {
  std::copy(buf.begin() + pos, buf.begin() + pos + n * sizeof(T), reinterpret_cast<char*>(data));
  pos += n * sizeof(T);
}

}  // namespace rangefuse::mpi
