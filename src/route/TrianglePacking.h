// How a routed part's triangles are laid out in bytes (private to route/): a part numbers its
// vertices in order of first use, so each corner lies a short step below the next new vertex,
// and 16 bits hold the step (decision 54).
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse::internal {

/// Appends the listed triangles with their corners renumbered by remap: the count, the bytes
/// that follow, then per corner the step below the next new vertex (one more than the largest
/// corner so far) in 16 bits, or where that does not fit, 0xffff and the corner in 32 bits.
/// Any numbering comes back exactly; first-use order takes 6 bytes a triangle.
void packTriangles(std::vector<char>& buf, const std::vector<Triangle>& triangles,
                   const std::vector<uint32_t>& pick, const std::vector<int32_t>& remap);
void unpackTriangles(const std::vector<char>& buf, size_t& pos, std::vector<Triangle>& v);
void skipTriangles(const std::vector<char>& buf, size_t& pos);

}  // namespace rangefuse::internal
