// Stanford range-grid PLY reading (ascii, binary little and big endian).
#pragma once

#include <string>

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::io {

/// Reads a range grid: size from `obj_info num_cols/num_rows`, optional pinhole
/// intrinsics from `obj_info pinhole_fx/fy/cx/cy`. Throws InputError naming the file and
/// the line or element on any malformed content.
RangeGrid readRangeGridPly(const std::string& path);

}  // namespace rangefuse::io
