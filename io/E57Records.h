// Decoding an E57 scan's compressed vector (private to io/): data packets, one byte stream per
// prototype field, each field's values bit-packed least significant bit first in just enough
// bits for its range; a stream runs on from packet to packet, so a value may span two.
#pragma once

#include <functional>
#include <vector>

#include "E57Pages.h"
#include "rangefuse/io/E57.h"

namespace rangefuse::io::internal {

/// Consecutive records of a scan: for each field asked for, its values (integers as they are,
/// scaled integers scaled, floats widened); the other fields' vectors stay empty.
struct E57Records {
  size_t count = 0;
  std::vector<std::vector<double>> values;  ///< by field, in prototype order
};

/// Decodes every record of the scan, in order, handing them to `use` a packet's worth at a time;
/// only the fields `wanted` marks are stored. Throws InputError naming the file, the scan and
/// the byte offset for a section or packet that is malformed or cut short.
void decodeE57Records(E57Pages& pages, const E57Scan& scan, const std::vector<bool>& wanted,
                      const std::function<void(const E57Records&)>& use);

}  // namespace rangefuse::io::internal
