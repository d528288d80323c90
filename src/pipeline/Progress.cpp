#include "rangefuse/pipeline/Progress.h"

#include <cstdio>

#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {

Progress::Progress(MPI_Comm comm, Verbosity verbosity)
    : root_(mpi::rank(comm) == 0),
      verbosity_(verbosity),
      start_(MPI_Wtime()),
      stageStart_(start_),
      lastLine_(start_) {}

void Progress::stage(const std::string& name, const std::string& message) {
  const double now = MPI_Wtime();
  stages_.emplace_back(name, now - stageStart_);
  if (shows(Verbosity::normal)) {
    std::printf("[%7.2fs] %-10s %s (%.2fs)\n", now - start_, name.c_str(), message.c_str(),
                now - stageStart_);
    std::fflush(stdout);
  }
  stageStart_ = lastLine_ = now;
}

void Progress::update(const std::string& name, const std::string& message, double every) {
  const double now = MPI_Wtime();
  if (!shows(Verbosity::normal) || now - lastLine_ < every) return;
  std::printf("[%7.2fs] %-10s %s\n", now - start_, name.c_str(), message.c_str());
  std::fflush(stdout);
  lastLine_ = now;
}

double Progress::elapsed() const {
  return MPI_Wtime() - start_;
}

}  // namespace rangefuse
