#include "LimitPacking.h"

#include <algorithm>
#include <cstring>

#include "BitMask.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse::internal {
namespace {

/// Bit-for-bit equality: -0 is not 0, and a NaN equals itself.
template <class Real>
bool sameBits(Real a, Real b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// One end (0: dMin, 1: dMax) of the listed limits, as Real.
template <class Real>
void packEnd(std::vector<char>& buf, const std::vector<std::array<double, 2>>& limits,
             const std::vector<uint32_t>& pick, int end) {
  Real outer = static_cast<Real>(limits[pick[0]][end]);
  for (uint32_t t : pick) {
    const auto v = static_cast<Real>(limits[t][end]);
    outer = end == 0 ? std::min(outer, v) : std::max(outer, v);
  }
  mpi::pack(buf, &outer, 1);
  const size_t at = buf.size();
  buf.resize(at + maskBytes(pick.size()));
  for (size_t k = 0; k < pick.size(); ++k) {
    const auto v = static_cast<Real>(limits[pick[k]][end]);
    if (sameBits(v, outer))
      setBit(buf.data() + at, k);
    else
      mpi::pack(buf, &v, 1);  // after the mask: the mask's bytes are in place already
  }
}

template <class Real>
void unpackEnd(const std::vector<char>& buf, size_t& pos,
               std::vector<std::array<double, 2>>& limits, int end) {
  Real outer;
  mpi::unpack(buf, pos, &outer, 1);
  const char* mask = buf.data() + pos;
  pos += maskBytes(limits.size());
  for (size_t k = 0; k < limits.size(); ++k) {
    Real v = outer;
    if (!bitAt(mask, k)) mpi::unpack(buf, pos, &v, 1);
    limits[k][end] = v;
  }
}

/// Bytes of one end of n limits packed at pos.
template <class Real>
size_t endBytes(const std::vector<char>& buf, size_t pos, uint64_t n) {
  const size_t outer = setBits(buf.data() + pos + sizeof(Real), n);
  return sizeof(Real) + maskBytes(n) + (n - outer) * sizeof(Real);
}

template <class Real>
void packAll(std::vector<char>& buf, const std::vector<std::array<double, 2>>& limits,
             const std::vector<uint32_t>& pick) {
  for (int end : {0, 1}) packEnd<Real>(buf, limits, pick, end);
}

template <class Real>
void unpackAll(const std::vector<char>& buf, size_t& pos,
               std::vector<std::array<double, 2>>& limits) {
  for (int end : {0, 1}) unpackEnd<Real>(buf, pos, limits, end);
}

template <class Real>
void skipAll(const std::vector<char>& buf, size_t& pos, uint64_t n) {
  for (int end = 0; end < 2; ++end) pos += endBytes<Real>(buf, pos, n);
}

}  // namespace

void packLimits(std::vector<char>& buf, const std::vector<std::array<double, 2>>& limits,
                const std::vector<uint32_t>& pick, bool single) {
  const uint64_t n = limits.empty() ? 0 : pick.size();
  mpi::pack(buf, &n, 1);
  if (n == 0) return;
  single ? packAll<float>(buf, limits, pick) : packAll<double>(buf, limits, pick);
}

void unpackLimits(const std::vector<char>& buf, size_t& pos,
                  std::vector<std::array<double, 2>>& limits, bool single) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  limits.resize(n);
  if (n == 0) return;
  single ? unpackAll<float>(buf, pos, limits) : unpackAll<double>(buf, pos, limits);
}

void skipLimits(const std::vector<char>& buf, size_t& pos, bool single) {
  uint64_t n;
  mpi::unpack(buf, pos, &n, 1);
  if (n == 0) return;
  single ? skipAll<float>(buf, pos, n) : skipAll<double>(buf, pos, n);
}

}  // namespace rangefuse::internal
