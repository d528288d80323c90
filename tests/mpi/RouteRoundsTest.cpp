// route/ScanRouting.h's routeRounds: what each rank holds after routing, its own part packed
// as the others' arrive, is the part routeScan keeps unserialised, whichever way the scan
// came (packed bytes or a scan) and whether or not it all stays.
#include <gtest/gtest.h>

#include <algorithm>

#include "../common/GridScan.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"

namespace rangefuse {
namespace {

/// The routing tests' wavy patch, compact as a streamed field holds its scans.
PrismScan wavyPatch() {
  return compactScan(test::wavyScan());
}

bool sameParts(const PrismScan& a, const PrismScan& b) {
  const ScanSurface &x = a.surface, &y = b.surface;
  return x.points == y.points && x.normals == y.normals && x.confidence == y.confidence &&
         x.triangles == y.triangles && a.limits == b.limits && a.quantum == b.quantum &&
         a.origin == b.origin;
}

TEST(RouteRounds, EachRankHoldsThePartsRouteScanKeeps) {
  const int ranks = mpi::size(MPI_COMM_WORLD), me = mpi::rank(MPI_COMM_WORLD);
  if (ranks == 1) GTEST_SKIP() << "a lone rank keeps each scan as it was taken";
  // Scan 0 lies on every rank's bricks. Scans 1 and 2 are its first 20 triangles, which lie on
  // rank 0's bricks alone (a whole scan that stays), taken as bytes and as a scan.
  std::vector<PrismScan> scans(3, wavyPatch());
  const BrickLayout layout = planBricks({scans[0]}, fitGrid({scans[0]}, 0.5, 4, 1.5), ranks);
  for (size_t e = 1; e < 3; ++e) {
    std::vector<Triangle> kept;
    PrismLimits limits;
    for (size_t t = 0; t < 20; ++t)
      kept.push_back(scans[e].surface.triangles[t]), limits.push_back(scans[e].limits[t]);
    scans[e].surface.triangles = kept;
    scans[e].limits = limits;
  }
  RoutedParts parts;
  RoutingStats stats;
  const auto take = [&](size_t i) {
    const size_t e = i % 3;
    return e == 2 ? TakenScan{{}, scans[e]} : TakenScan{packedScan(scans[e]), {}};
  };
  // Reader r routes entries 3r, 3r+1, 3r+2 (scans 0, 1, 2).
  const std::vector<size_t> mine{size_t(3 * me), size_t(3 * me + 1), size_t(3 * me + 2)};
  ASSERT_TRUE(routeRounds({mine}, take, layout, 0, false, MPI_COMM_WORLD, parts, stats));
  parts.sortByEntry();
  const IndexedScans held = parts.takeAll();

  // What routeScan keeps for this rank of each entry, unserialised.
  IndexedScans expected;
  for (int r = 0; r < ranks; ++r)
    for (size_t e = 0; e < 3; ++e) {
      std::vector<std::vector<char>> out(ranks);
      RoutingStats ignored;
      ignored.bytes.assign(ranks, 0);
      routeScan(3 * r + e, unpackedScan(packedScan(scans[e])), layout, 0, me, out, expected,
                ignored);
    }
  ASSERT_EQ(held.size(), expected.size());
  for (size_t k = 0; k < held.size(); ++k) {
    EXPECT_EQ(held[k].first, expected[k].first);
    EXPECT_TRUE(sameParts(held[k].second, expected[k].second)) << "entry " << held[k].first;
  }
  // Every rank holds a part of entry 0 that is not all of it (the split is tested, not only
  // whole scans).
  const auto split = [&](const auto& e) {
    return e.first % 3 == 0 &&
           e.second.surface.triangles.size() < scans[0].surface.triangles.size();
  };
  EXPECT_TRUE(std::any_of(held.begin(), held.end(), split));
  const auto whole = [&](const auto& e) {
    return e.first % 3 != 0 && e.second.surface.triangles.size() == 20;
  };
  if (me == 0) {
    EXPECT_EQ(std::count_if(held.begin(), held.end(), whole), 2 * ranks);
  }
}

}  // namespace
}  // namespace rangefuse
