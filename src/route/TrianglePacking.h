// How a routed part's triangles are laid out in bytes (private to route/): a part numbers its
// vertices in order of first use, so each corner lies a short step below the next new vertex,
// and one or two bytes hold the step (decisions 54, 58).
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/core/TriangleMesh.h"

namespace rangefuse::internal {

/// Appends the listed triangles with their corners renumbered by remap: the count, the bytes
/// that follow, then per corner the step below the next new vertex (one more than the largest
/// corner so far): below 240 in a byte, below 4080 in two, or where that does not fit, 0xff
/// and the corner in 32 bits. Any numbering comes back exactly; first-use order on a grid
/// takes 3 to 6 bytes a triangle, by how far back the row above was numbered.
void packTriangles(std::vector<char>& buf, const std::vector<Triangle>& triangles,
                   const std::vector<uint32_t>& pick, const std::vector<int32_t>& remap);
void unpackTriangles(const std::vector<char>& buf, size_t& pos, std::vector<Triangle>& v);
void skipTriangles(const std::vector<char>& buf, size_t& pos);

}  // namespace rangefuse::internal
