// Sums that come out the same to the bit whatever the order of their terms and however many
// ranks share them: each term is rounded once to a fixed-point scale every rank knows, then
// added as an integer, and integer addition is exact.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

namespace rangefuse {

/// A vector of sums. `bound` must not be smaller than the sum of the magnitudes of all terms any
/// slot receives on all ranks together, and must be the same number on every rank and for every
/// rank count (a count of points times the largest term, say): the scale comes from it alone.
/// A term keeps about 61 bits below `bound`.
class FixedPointSum {
 public:
  FixedPointSum(size_t slots, double bound);

  /// Adds v to slot i (this rank's part).
  void add(size_t i, double v);

  /// Collective: the sums over every rank's terms, identical on every rank.
  std::vector<double> reduce(MPI_Comm comm) const;

  /// The value of one fixed-point unit.
  double unit() const { return unit_; }

 private:
  std::vector<int64_t> sums_;
  double scale_, unit_;
};

}  // namespace rangefuse
