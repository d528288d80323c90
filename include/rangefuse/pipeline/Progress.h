// Stage-by-stage progress lines printed by rank 0, and each rank's stage times.
#pragma once

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace rangefuse {

/// How much a run prints on its standard output: nothing (warnings and errors still go to
/// standard error), a line a stage and a little progress, or every fit and frame.
enum class Verbosity { quiet, normal, verbose };

class Progress {
 public:
  explicit Progress(MPI_Comm comm, Verbosity verbosity = Verbosity::normal);
  /// Prints "[elapsed] stage: message (stage seconds)" on rank 0 unless quiet, records this
  /// rank's time for the stage and restarts the stage clock.
  void stage(const std::string& name, const std::string& message);
  /// Prints "[elapsed] stage message" on rank 0 when `every` seconds have passed since its last
  /// line (a long stage's progress); records nothing.
  void update(const std::string& name, const std::string& message, double every = 10);
  bool isRoot() const { return root_; }
  /// Whether this rank prints lines of `level`: rank 0 at that verbosity or above.
  bool shows(Verbosity level) const { return root_ && verbosity_ >= level; }
  double elapsed() const;
  /// This rank's (stage, seconds) in order.
  const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }

 private:
  bool root_;
  Verbosity verbosity_;
  double start_, stageStart_, lastLine_;
  std::vector<std::pair<std::string, double>> stages_;
};

}  // namespace rangefuse
