// How a routed scan part is laid out in bytes (private to route/).
#pragma once

#include <cstdint>
#include <vector>

#include "rangefuse/prism/PrismField.h"

namespace rangefuse::internal {

/// Appends the part of `scan` made of the listed triangles (in order) and the vertices they
/// use, in order of first use, to buf: its entry `index`, then each vector with its length. A
/// compact scan's points go as 24- or 32-bit lattice offsets, its normals and confidences as
/// their codes (CompactAttributes.h): a third of the bytes, and the same values. Triangles,
/// limits, colours, texels and blocks go as TrianglePacking.h, LimitPacking.h and
/// ColourPacking.h lay them out. remap must be -1 for every point; it is left so.
void packPart(std::vector<char>& buf, uint64_t index, const PrismScan& scan,
              const std::vector<uint32_t>& triangles, std::vector<int32_t>& remap);

/// packPart of every triangle: the whole scan, only the points its triangles use.
void packWhole(std::vector<char>& buf, uint64_t index, const PrismScan& scan);

/// Reads the part packPart wrote at pos into `part`, advancing pos; returns its entry.
uint64_t unpackPart(const std::vector<char>& buf, size_t& pos, PrismScan& part);

/// Moves pos past the part packPart wrote there; returns its entry.
uint64_t skipPart(const std::vector<char>& buf, size_t& pos);

/// The vertices the listed triangles use, in order of first use; remap[v] is set to v's place
/// among them (the caller puts -1 back).
std::vector<uint32_t> usedVertices(const ScanSurface& s, const std::vector<uint32_t>& triangles,
                                   std::vector<int32_t>& remap);

}  // namespace rangefuse::internal
