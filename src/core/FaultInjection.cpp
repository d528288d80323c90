#include "rangefuse/core/FaultInjection.h"

#include <mpi.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

struct Fault {
  std::string point, action;
  int rank = -1;
  int nth = 0;  ///< only the n-th call of the point on that rank (0: every call)
};

/// RANGEFUSE_FAULT parsed once; an unset or malformed value injects nothing.
const Fault& requested() {
  static const Fault fault = [] {
    Fault f;
    const char* env = std::getenv("RANGEFUSE_FAULT");
    if (!env) return f;
    const std::string s = env;
    const size_t colon = s.find(':'), at = s.find('@');
    if (colon == std::string::npos || at == std::string::npos || at < colon) return f;
    f.point = s.substr(0, colon);
    f.action = s.substr(colon + 1, at - colon - 1);
    f.rank = std::atoi(s.c_str() + at + 1);
    const size_t hash = s.find('#', at);
    if (hash != std::string::npos) f.nth = std::atoi(s.c_str() + hash + 1);
    return f;
  }();
  return fault;
}

/// This process's rank in MPI_COMM_WORLD (0 before MPI starts).
int worldRank() {
  int started = 0, rank = 0;
  MPI_Initialized(&started);
  if (started) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

}  // namespace

void faultPoint(const char* point, const std::string& detail) {
  const Fault& f = requested();
  if (f.point != point || f.rank != worldRank()) return;
  static int calls = 0;  // of the requested point, on this rank
  if (f.nth > 0 && ++calls != f.nth) return;
  // The time stamp lets tests measure how long the other ranks take to stop.
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  std::fprintf(stderr, "rangefuse: injecting fault %s:%s on rank %d at %.3f\n", point,
               f.action.c_str(), f.rank, std::chrono::duration<double>(now).count());
  std::fflush(stderr);
  if (f.action == "kill") std::raise(SIGKILL);
  if (f.action == "throw")
    throw InputError((detail.empty() ? std::string(point) : detail) + ": injected fault on rank " +
                     std::to_string(f.rank));
}

}  // namespace rangefuse
