// How a routed part's prism limits are laid out in bytes (private to route/): nearly every
// prism keeps the envelope whole, [-eps, eps], so each end is a bit saying "the part's own"
// and only the ends that edge surfaces truncated follow (decision 54).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rangefuse::internal {

/// Appends the listed triangles' limits (dMin, dMax), as floats when `single` (a compact scan's
/// are floats' values already), else as doubles: the count, then for each end the part's
/// outermost value, a bit a triangle (1: the outermost) and the other triangles' values. Any
/// values come back bit for bit; a part whose prisms keep the envelope takes 2 bits a triangle.
void packLimits(std::vector<char>& buf, const std::vector<std::array<double, 2>>& limits,
                const std::vector<uint32_t>& pick, bool single);
void unpackLimits(const std::vector<char>& buf, size_t& pos,
                  std::vector<std::array<double, 2>>& limits, bool single);
void skipLimits(const std::vector<char>& buf, size_t& pos, bool single);

}  // namespace rangefuse::internal
