#include "rangefuse/parallel/FixedPointSum.h"

#include <cmath>
#include <stdexcept>

namespace rangefuse {

FixedPointSum::FixedPointSum(size_t slots, double bound) : sums_(slots, 0) {
  if (!(bound >= 0) || !std::isfinite(bound))
    throw std::invalid_argument("FixedPointSum: the bound must be finite and >= 0");
  // A power of two keeps the scaling itself exact; 2^61 leaves room for the rounding of each
  // term (under a unit) on top of the bound.
  int exponent = 0;
  std::frexp(bound > 0 ? bound : 1.0, &exponent);  // bound < 2^exponent
  scale_ = std::ldexp(1.0, 61 - exponent);
  unit_ = 1 / scale_;
}

void FixedPointSum::add(size_t i, double v) {
  sums_[i] += static_cast<int64_t>(v * scale_);  // truncated: the same everywhere, and cheap
}

std::vector<double> FixedPointSum::reduce(MPI_Comm comm) const {
  std::vector<int64_t> all(sums_.size());
  MPI_Allreduce(sums_.data(), all.data(), static_cast<int>(all.size()), MPI_INT64_T, MPI_SUM, comm);
  std::vector<double> out(all.size());
  for (size_t i = 0; i < all.size(); ++i) out[i] = static_cast<double>(all[i]) * unit_;
  return out;
}

}  // namespace rangefuse
