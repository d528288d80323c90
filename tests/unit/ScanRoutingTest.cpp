// Routing a scan's triangles to the ranks owning the bricks their prisms touch, against brute
// force over every triangle and every brick; reader assignment by file size.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "../common/GridScan.h"
#include "rangefuse/pipeline/StreamedField.h"
#include "rangefuse/route/RoutingPlan.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"
#include "rangefuse/surface/ScanSurface.h"

using namespace rangefuse;

namespace {

using test::wavyScan;

/// `planned` with only the bricks whose positions `keep` accepts, split over `ranks` by work:
/// triangles of the scan then reach bricks the layout lacks.
template <class Keep>
BrickLayout keptBricks(const BrickLayout& planned, int ranks, Keep keep) {
  BrickWork work;
  for (size_t i = 0; i < planned.codes.size(); ++i)
    if (keep(i)) work[planned.codes[i]] = planned.work[i];
  return layoutFromWork(work, planned.grid, ranks);
}

/// Brute force: the ranks owning some brick a prism's bounds touch.
std::set<int> ownersOf(const Prism& p, const BrickLayout& layout) {
  std::set<int> owners;
  VoxelIndex lo, hi;
  layout.grid.voxelRange(prismBounds(p), lo, hi);
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const int64_t at = layout.find(mortonEncode(brickOf({x, y, z}, layout.grid.brick)));
        if (at >= 0) owners.insert(layout.ownerOf(at));
      }
  return owners;
}

TEST(PrismIntegrator, ThreadsGiveTheSingleThreadSumsEvenWithNothingToAdd) {
  // Rank 1 of 3 owns a third of the bricks; three overlapping images (so that the order in
  // which a voxel's samples are added shows in its sums' bits), then a scan far from every
  // brick (no prism reaches the rank: every slab but one is empty). Added one at a time, then
  // as one batch (each thread goes through the batch on its own).
  const PrismScan scan = wavyScan();
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 3);
  PrismScan lifted = scan, tilted = scan, far = scan;
  for (auto& p : lifted.surface.points) p.z() += 0.3;
  for (auto& p : tilted.surface.points) p.z() += 0.05 * p.x() - 0.5;
  for (auto& p : far.surface.points) p.z() += 1000;
  const std::vector<const PrismScan*> images{&scan, &lifted, &tilted, &far};
  std::vector<VoxelSums> want;
  IntegrationStats wantStats;
  for (int threads : {1, 3, 8})
    for (bool batch : {false, true}) {
      BrickStore store(layout, 1);
      PrismIntegrator integrator(store, threads);
      IntegrationStats total;
      if (batch) {
        std::vector<PrismIntegrator::Image> all;
        for (const PrismScan* s : images) all.push_back({s});
        total = integrator.addImages(all);
      }
      for (const PrismScan* s : batch ? std::vector<const PrismScan*>{} : images) {
        const IntegrationStats st = integrator.addScan(*s);
        total.prisms += st.prisms;
        total.voxelUpdates += st.voxelUpdates;
      }
      const std::vector<VoxelSums> got(store.sums().begin(), store.sums().end());
      if (threads == 1 && !batch) {
        want = got, wantStats = total;
        continue;
      }
      ASSERT_EQ(got.size(), want.size());
      EXPECT_EQ(std::memcmp(got.data(), want.data(), got.size() * sizeof(VoxelSums)), 0)
          << threads << " " << batch;
      EXPECT_EQ(total.prisms, wantStats.prisms) << threads << " " << batch;
      EXPECT_EQ(total.voxelUpdates, wantStats.voxelUpdates) << threads << " " << batch;
    }
  EXPECT_GT(wantStats.voxelUpdates, 0u);
}

TEST(PrismIntegrator, AnImageInPartsIsTheImageWhole) {
  // A station's bands reach a brick owner as parts of one image: each voxel must take the
  // nearest triangle of all of them, as if they were one scan, on any thread count.
  const PrismScan scan = wavyScan();
  const size_t n = scan.surface.triangles.size();
  std::vector<PrismScan> parts(3, scan);
  for (size_t k = 0; k < 3; ++k) {
    const auto from = n * k / 3, to = n * (k + 1) / 3;
    parts[k].surface.triangles.assign(scan.surface.triangles.begin() + from,
                                      scan.surface.triangles.begin() + to);
    parts[k].limits.assign(scan.limits.begin() + from, scan.limits.begin() + to);
  }
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 1);
  auto sums = [&](int threads, bool asOneImage) {
    BrickStore store(layout, 0);
    PrismIntegrator integrator(store, threads);
    if (asOneImage)
      integrator.addImages({{&parts[0], &parts[1], &parts[2]}, {&scan}});
    else
      for (const PrismScan* p :
           std::vector<const PrismScan*>{&parts[0], &parts[1], &parts[2], &scan})
        integrator.addScan(*p);
    return std::vector<VoxelSums>(store.sums().begin(), store.sums().end());
  };
  BrickStore whole(layout, 0);
  PrismIntegrator integrator(whole, 1);
  integrator.addScan(scan);
  integrator.addScan(scan);
  const std::vector<VoxelSums> want(whole.sums().begin(), whole.sums().end());
  const size_t bytes = want.size() * sizeof(VoxelSums);
  for (int threads : {1, 3}) {
    EXPECT_EQ(std::memcmp(sums(threads, true).data(), want.data(), bytes), 0) << threads;
    // Added as three images, voxels where two parts' prisms meet take two samples.
    EXPECT_NE(std::memcmp(sums(threads, false).data(), want.data(), bytes), 0) << threads;
  }
}

TEST(ScanRouting, EachRankGetsExactlyTheTrianglesTouchingItsBricks) {
  const PrismScan scan = wavyScan();
  const std::vector<PrismScan> one{scan};
  const VoxelGrid grid = fitGrid(one, 0.5, 4, 1.5);
  const int ranks = 3;
  // Drop every 5th brick: triangles touching only missing bricks must go nowhere.
  const BrickLayout layout =
      keptBricks(planBricks(one, grid, ranks), ranks, [](size_t i) { return i % 5 != 0; });

  std::vector<std::vector<char>> out(ranks);
  RoutingStats stats;
  stats.bytes.assign(ranks, 0);
  IndexedScans mine;
  routeScan(7, scan, layout, 0, 1, out, mine, stats);  // rank 1's part kept, not serialised
  EXPECT_TRUE(out[1].empty());
  std::vector<IndexedScans> got(ranks);
  for (int r = 0; r < ranks; ++r) got[r] = r == 1 ? mine : unpackRouted({out[r]});

  std::vector<size_t> expected(ranks, 0);
  std::vector<size_t> next(ranks, 0);  // position in rank r's part, in triangle order
  for (size_t t = 0; t < scan.surface.triangles.size(); ++t)
    for (int r : ownersOf(scanPrism(scan, t), layout)) {
      ++expected[r];
      ASSERT_EQ(got[r].size(), 1u);
      const PrismScan& part = got[r][0].second;
      ASSERT_LT(next[r], part.surface.triangles.size());
      const Prism a = scanPrism(scan, t), b = scanPrism(part, next[r]++);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(a.p[k], b.p[k]);
        EXPECT_EQ(a.n[k], b.n[k]);
        EXPECT_EQ(a.w[k], b.w[k]);
      }
      EXPECT_EQ(a.dMin, b.dMin);
      EXPECT_EQ(a.dMax, b.dMax);
    }
  size_t copies = 0;
  for (int r = 0; r < ranks; ++r) {
    const size_t n = got[r].empty() ? 0 : got[r][0].second.surface.triangles.size();
    EXPECT_EQ(n, expected[r]) << "rank " << r;
    if (!got[r].empty()) {
      EXPECT_EQ(got[r][0].first, 7u);
    }
    copies += n;
  }
  EXPECT_EQ(stats.copies, copies);
  EXPECT_EQ(stats.triangles, scan.surface.triangles.size());
  EXPECT_LT(copies, 2 * scan.surface.triangles.size());
  EXPECT_GT(expected[0] * expected[1] * expected[2], 0u) << "every rank should get some";
}

TEST(ScanRouting, ToRangesEachRankGetsTheTrianglesReachingItsRangeHeldOrNot) {
  const PrismScan scan = wavyScan();
  const std::vector<PrismScan> one{scan};
  const VoxelGrid grid = fitGrid(one, 0.5, 4, 1.5);
  const int ranks = 3;
  const BrickLayout planned = planBricks(one, grid, ranks);
  // A growing field lacks bricks the scan reaches: two in three here, in every rank's range.
  const std::vector<uint64_t> firstCodes = planned.firstCodes;
  BrickLayout layout = keptBricks(planned, ranks, [](size_t i) { return i % 3 == 0; });
  layout.firstCodes = firstCodes;
  layout.rankStart = runsOf(layout.codes, firstCodes);

  for (int me = 0; me < ranks; ++me) {
    std::vector<std::vector<char>> out(ranks);
    RoutingStats stats;
    stats.bytes.assign(ranks, 0);
    IndexedScans mine;
    routeScan(4, scan, layout, 0, me, out, mine, stats, RouteTo::ranges);
    const size_t got = mine.empty() ? 0 : mine[0].second.surface.triangles.size();
    // Brute force: the triangles with a brick of their prism's box in me's range of codes.
    size_t expected = 0;
    for (size_t t = 0; t < scan.surface.triangles.size(); ++t) {
      VoxelIndex lo, hi;
      grid.voxelRange(prismBounds(scanPrism(scan, t)), lo, hi);
      bool reaches = false;
      for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
          for (int x = lo.x(); x <= hi.x(); ++x) {
            const uint64_t code = mortonEncode(brickOf({x, y, z}, grid.brick));
            reaches |= code >= firstCodes[me] && code < firstCodes[me + 1];
          }
      expected += reaches;
    }
    EXPECT_EQ(got, expected) << "rank " << me;
    EXPECT_GT(expected, 0u);
    // Routed to the bricks alone, the triangles reaching only the missing bricks go nowhere.
    IndexedScans held;
    routeScan(4, scan, layout, 0, me, out, held, stats);
    const size_t toBricks = held.empty() ? 0 : held[0].second.surface.triangles.size();
    EXPECT_LT(toBricks, got) << "rank " << me;
  }
}

TEST(ScanRouting, PartsCarryOnlyTheVerticesTheirTrianglesUse) {
  const PrismScan scan = wavyScan();
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 4);
  std::vector<std::vector<char>> out(4);
  RoutingStats stats;
  stats.bytes.assign(4, 0);
  IndexedScans none;
  routeScan(0, scan, layout, 0, -1, out, none, stats);
  EXPECT_TRUE(none.empty());
  for (int r = 0; r < 4; ++r) {
    const IndexedScans got = unpackRouted({out[r]});
    if (got.empty()) continue;
    const ScanSurface& s = got[0].second.surface;
    std::vector<int> used(s.points.size(), 0);
    for (const auto& t : s.triangles)
      for (int k = 0; k < 3; ++k) used.at(t[k]) = 1;
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), static_cast<long>(s.points.size()));
    EXPECT_EQ(stats.bytes[r], out[r].size());
  }
}

TEST(AssignReaders, ScansTakenNearbyGoToOneRank) {
  // Three sites far apart, their scans listed interleaved: each site is read by one rank.
  std::vector<Eigen::Vector3d> at;
  std::vector<uint64_t> bytes;
  for (int k = 0; k < 12; ++k) {
    const int site = k % 3;
    at.emplace_back(100.0 * site + 0.1 * k, 0.05 * k, 1.0);
    bytes.push_back(1000 + k);
  }
  const std::vector<int> readers = assignReadersNearby(at, bytes, 3);
  for (int k = 3; k < 12; ++k) EXPECT_EQ(readers[k], readers[k % 3]) << "scan " << k;
  EXPECT_EQ(std::set<int>(readers.begin(), readers.end()).size(), 3u);
}

TEST(AssignReaders, SharesTheBytesEvenlyAlongTheCurve) {
  // Random sizes at random places: every rank reads its share, give or take one file.
  std::vector<Eigen::Vector3d> at;
  std::vector<uint64_t> bytes;
  uint64_t total = 0, largest = 0;
  for (int k = 0; k < 200; ++k) {
    at.emplace_back((k * 7919) % 101, (k * 104729) % 37, (k * 31) % 53);
    bytes.push_back(1 + (k * 2654435761u) % 5000);
    total += bytes.back(), largest = std::max(largest, bytes.back());
  }
  for (int ranks : {1, 2, 5}) {
    const std::vector<int> readers = assignReadersNearby(at, bytes, ranks);
    std::vector<uint64_t> load(ranks, 0);
    for (size_t k = 0; k < bytes.size(); ++k) load[readers[k]] += bytes[k];
    for (int r = 0; r < ranks; ++r)
      EXPECT_NEAR(double(load[r]), double(total) / ranks, double(largest) + bytes.size())
          << ranks << " ranks, rank " << r;
  }
  // Scans at one place (a fixed camera) are read in list order: contiguous runs.
  const std::vector<int> still = assignReadersNearby(
      std::vector<Eigen::Vector3d>(9, Eigen::Vector3d(1, 2, 3)), std::vector<uint64_t>(9, 10), 3);
  EXPECT_EQ(still, (std::vector<int>{0, 0, 0, 1, 1, 1, 2, 2, 2}));
}

}  // namespace

TEST(ScanRouting, ASingleRankKeepsTheWholeScanUncopied) {
  const PrismScan scan = wavyScan();
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 1);
  std::vector<std::vector<char>> out(1);
  IndexedScans mine;
  RoutingStats stats;
  stats.bytes.assign(1, 0);
  routeScan(3, scan, layout, 0, 0, out, mine, stats);
  ASSERT_EQ(mine.size(), 1u);
  EXPECT_EQ(mine[0].first, 3u);
  EXPECT_EQ(mine[0].second.surface.points, scan.surface.points);
  EXPECT_EQ(mine[0].second.surface.triangles, scan.surface.triangles);
  EXPECT_TRUE(out[0].empty());
  EXPECT_EQ(stats.copies, scan.surface.triangles.size());
}

TEST(RoutingRounds, EachReaderGivesItsBytesAwayAtTheSameRate) {
  // Entry j goes in the round where the bytes before it reach round/rounds of the rank's bytes.
  const std::vector<uint64_t> bytes{30, 10, 10, 10, 5, 5};
  using Rounds = std::vector<std::vector<size_t>>;
  EXPECT_EQ(roundsOf({0, 1, 2, 3}, 2, bytes), (Rounds{{0}, {1, 2, 3}}));
  EXPECT_EQ(roundsOf({1, 2, 3}, 3, bytes), (Rounds{{1}, {2}, {3}}));
  // Fewer entries than rounds: the later rounds are empty, and every rank runs them all.
  EXPECT_EQ(roundsOf({4, 5}, 4, bytes), (Rounds{{4}, {}, {5}, {}}));
  EXPECT_EQ(roundsOf({}, 2, bytes), (Rounds{{}, {}}));
  // Empty scans: one a round, in order.
  EXPECT_EQ(roundsOf({0, 1}, 3, {0, 0}), (Rounds{{0}, {1}, {}}));
}

TEST(RoutingRounds, TheBusiestReaderSetsTheRoundsAtAboutTheBytesOfARound) {
  const std::vector<uint64_t> bytes{30, 10, 10, 10, 5, 5, 0, 0, 0};
  // 60 bytes at 25 a round: 3 rounds, whatever the lighter reader (10 bytes) needs.
  EXPECT_EQ(roundCount({{0, 1, 2, 3}, {4, 5}}, bytes, 25), 3u);
  // Never more rounds than a reader has entries: 30 bytes in one entry, one round.
  EXPECT_EQ(roundCount({{0}, {4}}, bytes, 1), 1u);
  EXPECT_EQ(roundCount({{0, 1, 2, 3}, {4, 5}}, bytes, 1), 4u);
  // Entries without bytes: one a round (roundsOf places them so).
  EXPECT_EQ(roundCount({{6, 7, 8}, {0}}, bytes, 100), 3u);
  EXPECT_EQ(roundCount({{}, {}}, bytes, 100), 0u);
  // Each rank's entries fit the count: roundsOf puts each one in a round below it.
  const size_t rounds = roundCount({{0, 1, 2, 3}, {4, 5}}, bytes, 25);
  using Rounds = std::vector<std::vector<size_t>>;
  EXPECT_EQ(roundsOf({0, 1, 2, 3}, rounds, bytes), (Rounds{{0}, {1}, {2, 3}}));
  EXPECT_EQ(roundsOf({4, 5}, rounds, bytes), (Rounds{{4}, {5}, {}}));
}

TEST(RoutingRounds, SortByEntryKeepsTheOrderOfEqualEntries) {
  IndexedScans parts(4);
  const size_t entries[] = {3, 1, 3, 0};
  for (size_t k = 0; k < 4; ++k) {
    parts[k].first = entries[k];
    parts[k].second.surface.points.assign(k + 1, Eigen::Vector3d::Zero());
  }
  sortByEntry(parts);
  std::vector<std::pair<size_t, size_t>> got;
  for (const auto& [i, s] : parts) got.emplace_back(i, s.surface.points.size());
  EXPECT_EQ(got, (std::vector<std::pair<size_t, size_t>>{{0, 4}, {1, 2}, {3, 1}, {3, 3}}));
}

TEST(RoutingWindows, GrowByWholeRoundsOfScansWithinTheBudget) {
  const std::vector<uint64_t> bytes(7, 10);
  const std::vector<uint8_t> none(7, 0);
  // Budget 30 in all: one round (2 scans, 20 bytes) fits, two rounds (40) do not; the short
  // last round (10) joins the one before.
  EXPECT_EQ(routingWindows(bytes, none, 2, 30), (std::vector<size_t>{2, 4, 7}));
  EXPECT_EQ(routingWindows(bytes, none, 2, 40), (std::vector<size_t>{4, 7}));
  EXPECT_EQ(routingWindows(bytes, none, 2, 1000), (std::vector<size_t>{7}));
  // No budget: a round of one scan per rank at a time, as --scan-memory 0 reads them.
  EXPECT_EQ(routingWindows(bytes, none, 2, 0), (std::vector<size_t>{2, 4, 6, 7}));
  EXPECT_EQ(routingWindows(bytes, none, 1, 0), (std::vector<size_t>{1, 2, 3, 4, 5, 6, 7}));
  // A large scan closes its window early; the last round may be short.
  EXPECT_EQ(routingWindows({10, 10, 100, 10, 10}, {0, 0, 0, 0, 0}, 2, 40),
            (std::vector<size_t>{2, 4, 5}));
  EXPECT_TRUE(routingWindows({}, {}, 3, 100).empty());
}

TEST(RoutingWindows, ScansKeptByTheirReaderNeverCloseAWindow) {
  const std::vector<uint64_t> bytes(7, 10);
  // All kept: one window, whatever the budget.
  EXPECT_EQ(routingWindows(bytes, std::vector<uint8_t>(7, 1), 2, 0), (std::vector<size_t>{7}));
  // Scans 2 and 3 read again (20 bytes) fill a budget of 20; scans 4 and 5 close it.
  EXPECT_EQ(routingWindows(bytes, {1, 1, 0, 0, 0, 1, 1}, 2, 20), (std::vector<size_t>{4, 7}));
  EXPECT_EQ(routingWindows(bytes, {1, 1, 0, 0, 0, 0, 1}, 2, 20), (std::vector<size_t>{4, 7}));
  EXPECT_EQ(routingWindows(bytes, {1, 1, 0, 0, 0, 0, 0}, 2, 20), (std::vector<size_t>{4, 6, 7}));
}

TEST(ScanRouting, AWindowNeverEndsBetweenTwoBandsOfAScan) {
  // Entries 1-3 are the bands of scan 1, entries 5-6 those of scan 3.
  const std::vector<size_t> scanOf = {0, 1, 1, 1, 2, 3, 3};
  EXPECT_EQ(wholeScanWindows({2, 4, 6, 7}, scanOf), (std::vector<size_t>{4, 7}));
  EXPECT_EQ(wholeScanWindows({1, 5, 7}, scanOf), (std::vector<size_t>{1, 5, 7}));
  EXPECT_EQ(wholeScanWindows({3, 7}, scanOf), (std::vector<size_t>{4, 7}));
  EXPECT_EQ(wholeScanWindows({1, 2, 3, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6}),
            (std::vector<size_t>{1, 2, 3, 4, 5, 6, 7}));
}

TEST(ScanRouting, JoinedPartsAreTheirVerticesAndTrianglesInTurn) {
  PrismScan a, b;
  a.surface.points = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
  a.surface.triangles = {{0, 1, 2}};
  a.limits = {{-1, 1}};
  b.surface.points = {Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(6, 0, 0), Eigen::Vector3d(5, 1, 0),
                      Eigen::Vector3d(6, 1, 0)};
  b.surface.triangles = {{0, 1, 2}, {1, 3, 2}};
  b.limits = {{-2, 2}, {-3, 3}};
  for (PrismScan* s : {&a, &b}) {
    s->surface.normals.assign(s->surface.points.size(), Eigen::Vector3d::UnitZ());
    s->surface.confidence.assign(s->surface.points.size(), 0.5);
  }
  std::vector<PrismScan> parts;
  parts.push_back(a), parts.push_back(b);
  const PrismScan j = joinScans(std::move(parts));
  ASSERT_EQ(j.surface.points.size(), 7u);
  ASSERT_EQ(j.surface.triangles.size(), 3u);
  EXPECT_EQ(j.surface.triangles[2], (Triangle{4, 6, 5}));
  for (size_t t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const PrismScan& from = t == 0 ? a : b;
      const size_t tf = t == 0 ? 0 : t - 1;
      EXPECT_EQ(j.surface.points[j.surface.triangles[t][k]],
                from.surface.points[from.surface.triangles[tf][k]]);
    }
  EXPECT_EQ(j.limits[2], b.limits[1]);
  EXPECT_EQ(j.surface.normals.size(), 7u);
  EXPECT_EQ(j.surface.confidence.size(), 7u);
}

TEST(ScanRouting, ASentPartIsThePartKeptUnserialised) {
  // Colours and texels too: every vector of a part travels.
  PrismScan scan = wavyScan();
  ScanSurface& s = scan.surface;
  s.texelSide = 2;
  for (size_t v = 0; v < s.points.size(); ++v) {
    const float c = static_cast<float>(v % 251) / 251;
    s.colours.emplace_back(c, 1 - c, 0.5f);
    s.blocks.push_back({static_cast<int32_t>(v / 10), static_cast<int32_t>(v % 10)});
  }
  s.texels = TexelImage::blank(0, 0, 2 * s.blocks.back()[0] + 2, 20);
  for (size_t i = 0; i < s.texels.cells.size(); ++i)
    s.texels.cells[i] = {static_cast<uint8_t>(i), static_cast<uint8_t>(i / 256), 7, 255};
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 3);
  for (int r = 0; r < 3; ++r) {
    std::vector<std::vector<char>> out(3);
    RoutingStats stats;
    stats.bytes.assign(3, 0);
    IndexedScans kept, none;
    routeScan(5, scan, layout, 0, r, out, kept, stats);   // rank r's part, unserialised
    routeScan(5, scan, layout, 0, -1, out, none, stats);  // and everyone's, sent
    const IndexedScans sent = unpackRouted(std::move(out));
    ASSERT_EQ(kept.size(), 1u);
    const auto same = [&](const IndexedScans& got) {
      return std::find_if(got.begin(), got.end(), [&](const auto& e) {
        const ScanSurface &a = e.second.surface, &b = kept[0].second.surface;
        return e.first == 5 && a.points == b.points && a.normals == b.normals &&
               a.confidence == b.confidence && a.triangles == b.triangles &&
               a.colours == b.colours && a.texels == b.texels && a.blocks == b.blocks &&
               a.texelSide == b.texelSide && e.second.limits == kept[0].second.limits;
      });
    };
    EXPECT_NE(same(sent), sent.end()) << "rank " << r;
  }
}

TEST(ScanRouting, APackedScanHoldsItsUsedPointsOnlyAndAddsTheSameSums) {
  // Triangles of the last two thirds dropped and a point left alone: most points unused, as
  // joined flat blocks leave some. The packed scan keeps each triangle's corners, their
  // normals, confidences and colours, and its limits, and the field takes the same bits; a
  // compact scan's (compactScan) too.
  PrismScan scan = wavyScan();
  auto& s = scan.surface;
  for (size_t v = 0; v < s.points.size(); ++v)
    s.colours.push_back(Colour(float(v % 251) / 251, float(v % 7) / 7, 0.5f));
  s.colourKind = ColourKind::rgb;
  std::vector<Triangle> kept;
  PrismLimits limits;
  for (size_t t = 0; t < s.triangles.size() / 3; ++t)
    kept.push_back(s.triangles[t]), limits.push_back(scan.limits[t]);
  s.triangles = kept;
  scan.limits = limits;
  s.points.push_back({1, 2, 3}), s.normals.push_back({0, 0, 1}), s.confidence.push_back(1);
  s.colours.push_back(Colour(0.1f, 0.2f, 0.3f));

  const PrismScan compact = unpackedScan(packedScan(scan));
  const ScanSurface& c = compact.surface;
  std::vector<int> used(c.points.size(), 0);
  for (const auto& t : c.triangles)
    for (int k = 0; k < 3; ++k) used.at(t[k]) = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), static_cast<long>(c.points.size()));
  EXPECT_LT(c.points.size(), s.points.size() / 2);
  ASSERT_EQ(c.triangles.size(), s.triangles.size());
  for (size_t t = 0; t < c.triangles.size(); ++t) {
    EXPECT_EQ(compact.limits[t], scan.limits[t]);
    for (int k = 0; k < 3; ++k) {
      const int32_t a = c.triangles[t][k], b = s.triangles[t][k];
      EXPECT_EQ(c.points[a], s.points[b]);
      EXPECT_EQ(c.normals[a], s.normals[b]);
      EXPECT_EQ(c.confidence[a], s.confidence[b]);
      EXPECT_EQ(c.colours[a], s.colours[b]);
    }
  }
  const std::vector<PrismScan> one{scan};
  const BrickLayout layout = planBricks(one, fitGrid(one, 0.5, 4, 1.5), 1);
  auto sums = [&](const PrismScan& added) {
    BrickStore store(layout, 0);
    PrismIntegrator(store, 2).addScan(added);
    return std::vector<VoxelSums>(store.sums().begin(), store.sums().end());
  };
  const std::vector<VoxelSums> want = sums(scan), got = sums(compact);
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(std::memcmp(got.data(), want.data(), got.size() * sizeof(VoxelSums)), 0);
  const PrismScan lattice = compactScan(scan);
  const std::vector<VoxelSums> wantCompact = sums(lattice),
                               gotCompact = sums(unpackedScan(packedScan(lattice)));
  EXPECT_EQ(std::memcmp(gotCompact.data(), wantCompact.data(), got.size() * sizeof(VoxelSums)), 0);
}
