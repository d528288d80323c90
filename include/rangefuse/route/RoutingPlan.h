// Which rank reads which scan, and where the field pass's routing windows end: plans made
// before any scan is read, from the scans' sensor positions and file sizes, the same on every
// rank.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace rangefuse {

/// Where the field pass's windows end: each window is routed round by round (one scan a rank)
/// and added before the next. A window takes `ranks` consecutive scans, and `ranks` more while
/// the scans it reads again stay within `budget` bytes in all (each rank holds about its
/// share). Scans their reader `kept` count nothing: the parts routed from them take their
/// place. Ranks wait for one another once a window, and consecutive views fall mostly on one
/// rank's bricks: the fewer the windows, the more of that is evened out (decision 16).
std::vector<size_t> routingWindows(const std::vector<uint64_t>& scanBytes,
                                   const std::vector<uint8_t>& kept, int ranks, uint64_t budget);

/// The windows moved on so that none ends between two bands of one scan (`scanOf`: the scan of
/// each entry), whose parts a brick owner joins into one image before adding it.
std::vector<size_t> wholeScanWindows(std::vector<size_t> ends, const std::vector<size_t>& scanOf);

/// The reader rank of each scan, by where it was taken: the scans sorted along the Morton curve
/// of their sensors' positions (ties in list order) and cut into `ranks` runs of near-equal
/// file bytes. Bricks are owned along the same curve, so a scan is mostly read by a rank that
/// owns the surface near its sensor: its parts stay on that rank instead of crossing to it.
std::vector<int> assignReadersNearby(const std::vector<Eigen::Vector3d>& positions,
                                     const std::vector<uint64_t>& fileBytes, int ranks);

}  // namespace rangefuse
