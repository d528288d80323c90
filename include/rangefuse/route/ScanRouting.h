// Routing prepared scans to the ranks that own the bricks their prisms reach: each triangle is
// copied to every rank that may own one of its bricks, packed with the vertices it uses, and
// unpacked there as a part of its scan. Streamed fields, registration and tracking route
// through these functions; which rank reads which scan is in route/RoutingPlan.h.
#pragma once

#include <mpi.h>

#include <functional>
#include <utility>
#include <vector>

#include "rangefuse/prism/PrismField.h"
#include "rangefuse/route/RoutedParts.h"
#include "rangefuse/volume/BrickLayout.h"

namespace rangefuse {

/// What routing sent: input triangles, triangle copies made, bytes per destination rank.
struct RoutingStats {
  uint64_t triangles = 0, copies = 0;
  std::vector<uint64_t> bytes;
};

/// Where a triangle goes: to the ranks that own or may own the bricks it reaches
/// (BrickLayout::mayOwn: a brick of this rank's own range that its directory lacks does not
/// exist), or to the owners of the ranges of codes that hold those bricks, existing or not (a
/// growing field, whose owners join the bricks they are sent).
enum class RouteTo { bricks, ranges };

/// Per rank, the codes of the bricks its range holds that routed triangles reach (sorted, each
/// once): what routing learns of a growing field's new bricks while it finds the triangles'
/// owners, so that the owners need not find them again.
using ReachedBricks = std::vector<std::vector<uint64_t>>;

/// Appends to out[r], for every rank r owning a brick some triangle of the placed scan must
/// reach (`to`), the part of the scan made of those triangles (in order) and their vertices. With
/// reach 0 a triangle reaches the bricks its prism touches (prism fields); with reach > 0, the
/// bricks with a voxel centre within reach of its bounding box (closest-surface methods). A
/// triangle that reaches no existing brick goes nowhere. The part for rank `me` (none when -1)
/// is appended to `mine` instead, unserialised (the whole scan when it all goes there).
void routeScan(uint64_t index, PrismScan world, const BrickLayout& layout, double reach, int me,
               std::vector<std::vector<char>>& out, IndexedScans& mine, RoutingStats& stats,
               RouteTo to = RouteTo::bricks);

/// A whole scan in the bytes routing sends, and the scan again from them: how a streamed field
/// keeps a scan until it is routed. Only what a field needs goes: the points its triangles use
/// (in order of first use; joined flat blocks leave up to three in four unused), not its sight
/// map, noise or colour kind. A compact scan (compactScan) packs in about a third of the bytes.
std::vector<char> packedScan(const PrismScan& scan);
PrismScan unpackedScan(const std::vector<char>& bytes);

/// The scan parts received from every rank, in entry order.
IndexedScans unpackRouted(std::vector<std::vector<char>>&& in);

/// Appends the scans packed in one rank's `bytes` to `into`, unsorted, and frees the bytes.
void unpackRoutedInto(std::vector<char>&& bytes, IndexedScans& into);

/// Sorts parts by entry. Each entry has one reader, so it arrives once from each rank that
/// sent a part of it: entry order is all a field needs (parts of one entry keep rank order).
void sortByEntry(IndexedScans& parts);

/// Parts of one scan as one: their vertices and triangles in turn (the first one's sensor).
PrismScan joinScans(std::vector<PrismScan>&& parts);

/// The rounds in which every reader's entries (`byReader`, of sizes `bytes`) go at about
/// `roundBytes` a round: the most any reader needs, one an entry at most (and one an entry for
/// a reader whose entries have no bytes, as roundsOf places them).
size_t roundCount(const std::vector<std::vector<size_t>>& byReader,
                  const std::vector<uint64_t>& bytes, uint64_t roundBytes);

/// This rank's entries `mine` by round, `rounds` of them: each entry goes in the round where
/// the bytes before it reach the same fraction of the rank's bytes as the round of all
/// rounds, so that every reader gives its scans away at the same rate in bytes. A reader of
/// many small scans then does not still hold half of them while the others' parts arrive.
std::vector<std::vector<size_t>> roundsOf(const std::vector<size_t>& mine, size_t rounds,
                                          const std::vector<uint64_t>& bytes);

/// A scan as routing takes it from its reader: its packed bytes (packedScan; a compact scan
/// kept so) when there are any, else `scan`.
struct TakenScan {
  std::vector<char> packed;
  PrismScan scan;
};

/// Collective: routes this rank's entries, round by round (`byRound`, the same number of
/// rounds on every rank), each taken placed in the world by `take`, and adds what this rank is
/// sent, and its own part, to `parts` (unsorted; a compact scan's own part packed as the others
/// are, and its bytes as they came when the whole scan stays). Without `colour`, no part
/// carries colours. A lone rank owns every brick, so with reach 0 each scan is its own part, as
/// it was taken, without finding the bricks of its triangles (one that reaches none adds
/// nothing to a field); it then counts no copies. Freed scans' pages are given back to the
/// system as they add up. False when `take` threw on some rank (printed once).
/// With `reached` (and more than one rank, or reach > 0), it also gets, for every rank, the
/// bricks of its range (`to`) that this rank's triangles reach.
bool routeRounds(const std::vector<std::vector<size_t>>& byRound,
                 const std::function<TakenScan(size_t)>& take, const BrickLayout& layout,
                 double reach, bool colour, MPI_Comm comm, RoutedParts& parts, RoutingStats& stats,
                 RouteTo to = RouteTo::bricks, ReachedBricks* reached = nullptr);

}  // namespace rangefuse
