// Stanford range-grid PLY reading (ascii, binary little and big endian).
#pragma once

#include <string>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::io {

/// Reads a range grid: size from `obj_info num_cols/num_rows`, optional pinhole
/// intrinsics from `obj_info pinhole_fx/fy/cx/cy`. Throws InputError naming the file and
/// the line or element on any malformed content.
RangeGrid readRangeGridPly(const std::string& path, const InputLimits& limits = {});

/// The same from bytes in memory; `name` heads every message (fuzzing, embedded data).
RangeGrid parseRangeGridPly(const std::string& name, const std::string& text,
                            const InputLimits& limits = {});

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Writes a range grid in the Stanford layout (float x y z; one range_grid list of 0 or 1
/// index per cell, row-major), pinhole intrinsics as obj_info lines. Atomic.
void writeRangeGridPly(const std::string& path, const RangeGrid& grid, PlyEncoding encoding);

}  // namespace rangefuse::io
