// The usual binary range-grid layout decoded straight into a RangeGrid (private to io/).
#pragma once

#include <string_view>

#include "PlyFile.h"
#include "rangefuse/core/RangeGrid.h"

namespace rangefuse::io::internal {

/// Fills g.points and g.cell from `text`, whose header is `h`, when the body is little endian
/// (on a little-endian host) and holds just a vertex element of scalars with float or double
/// x, y, z (and no colour or intensity) and a range_grid element of g.cols x g.rows lists of 0 or 1
/// int or uint index, all valid. Otherwise false, leaving g's points and cells empty: the general
/// reader then reads the file and says what is wrong with it, so both readers refuse a file with
/// one message.
bool decodePlainRangeGrid(const PlyHeader& h, std::string_view text, RangeGrid& g);

}  // namespace rangefuse::io::internal
