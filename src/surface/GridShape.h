// What a grid's shape says about its triangles (private to the surface stage): whether a
// station's columns close a full turn, and which way its cells face the sensor.
#pragma once

#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::internal {

/// True when a spherical grid's columns close a full turn about the station's z axis.
/// `turnColumns` (default: the grid's) is the column count of the whole turn, for a sample of
/// a grid's columns whose empty columns separate runs of consecutive ones.
bool wrapsAround(const RangeGrid& grid, int turnColumns = -1);

/// True when most cells' triangles (r,c),(r,c+1),(r+1,c) face the sensor as wound.
bool facesSensor(const RangeGrid& grid);

}  // namespace rangefuse::internal
