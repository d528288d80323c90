// Stage-by-stage progress lines printed by rank 0.
#pragma once

#include <mpi.h>

#include <string>

namespace rangefuse {

class Progress {
 public:
  explicit Progress(MPI_Comm comm);
  /// Prints "[elapsed] stage: message" on rank 0 and restarts the stage clock.
  void stage(const std::string& name, const std::string& message);
  /// Seconds since the last stage() call.
  double stageSeconds() const;
  bool isRoot() const { return root_; }

 private:
  bool root_;
  double start_, stageStart_;
};

}  // namespace rangefuse
