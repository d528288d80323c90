// Stage-by-stage progress lines printed by rank 0, and each rank's stage times.
#pragma once

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace rangefuse {

class Progress {
 public:
  explicit Progress(MPI_Comm comm);
  /// Prints "[elapsed] stage: message (stage seconds)" on rank 0, records this rank's time
  /// for the stage and restarts the stage clock.
  void stage(const std::string& name, const std::string& message);
  /// Prints "[elapsed] stage message" on rank 0 when `every` seconds have passed since its last
  /// line (a long stage's progress); records nothing.
  void update(const std::string& name, const std::string& message, double every = 10);
  bool isRoot() const { return root_; }
  double elapsed() const;
  /// This rank's (stage, seconds) in order.
  const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }

 private:
  bool root_;
  double start_, stageStart_, lastLine_;
  std::vector<std::pair<std::string, double>> stages_;
};

}  // namespace rangefuse
