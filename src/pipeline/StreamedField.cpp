#include "rangefuse/pipeline/StreamedField.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <map>
#include <optional>

#include "ColourChoice.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/io/DepthPng.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/parallel/WorkStealing.h"
#include "rangefuse/pipeline/HeldScans.h"
#include "rangefuse/pipeline/VoxelCheck.h"
#include "rangefuse/route/RoutingPlan.h"
#include "rangefuse/route/ScanLoader.h"
#include "rangefuse/route/ScanRouting.h"

namespace rangefuse {
namespace {

using mpi::collectively;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The bytes each scan reads: its file's, its share of a PTX or E57 file's scan, or for a depth
/// image its decoded pixels'. A PNG's size says how well it compressed, not what preparing it
/// costs: a room walk's PNG files range from 3 to 45 KB, and readers given equal PNG bytes got
/// 181 and 119 of its 300 frames (and planning took 1.4 s against 0.7).
std::vector<uint64_t> fileSizes(const io::ConfFile& conf) {
  std::vector<uint64_t> bytes;
  for (const auto& c : conf.scans) {
    if (c.ptx) {
      bytes.push_back((c.ptx->end - c.ptx->offset) / static_cast<uint64_t>(c.bands));
      continue;
    }
    if (c.e57) {
      uint64_t bits = 0;
      for (const io::E57Field& f : c.e57->fields) bits += static_cast<uint64_t>(f.bits());
      bytes.push_back(c.e57->records * bits / 8 / static_cast<uint64_t>(c.bands));
      continue;
    }
    if (c.memory) {
      bytes.push_back(c.memory->grid.points.size() * sizeof(Eigen::Vector3d) +
                      c.memory->depth.counts.size() * sizeof(uint16_t));
      continue;
    }
    if (c.depth) {
      bytes.push_back(io::pngPixels(c.path) * sizeof(uint16_t));
      continue;
    }
    std::error_code ec;
    const auto n = std::filesystem::file_size(c.path, ec);
    bytes.push_back(ec ? 0 : static_cast<uint64_t>(n));  // unreadable: the read says why
  }
  return bytes;
}

/// Warnings of this rank's scans, printed by rank 0 in scan order.
void printWarnings(const std::map<size_t, std::string>& mine, MPI_Comm comm) {
  for (const auto& [i, w] : mpi::gatherIndexed(mine, 0, comm))
    std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
}

/// The sight maps of robust fusion: this rank's, then those of every scan that may see this
/// rank's bricks once shared.
struct SightMaps {
  std::map<size_t, SightMap> mine;
  std::vector<SightMap> all;  ///< per scan; empty (NaN everywhere) where it cannot see them

  /// Collective: each of this rank's maps to every rank whose bricks it may see (`scanOf`: the
  /// scan of each entry; a scan read in bands gets their maps joined). Maps are asked about
  /// the surface a voxel's hypothesis puts within `reach` of its centre (the envelope; infinite:
  /// every map to every rank); a map
  /// left out would have answered NaN wherever that rank asks (SightMap::mayCover), so the
  /// field is the same bits, and a rank holds the maps of the scans that see its part only.
  void share(const std::vector<size_t>& scanOf, const BrickLayout& layout, double reach,
             MPI_Comm comm) {
    const int ranks = mpi::size(comm);
    std::vector<Eigen::AlignedBox3d> boxes = ownedBoxes(layout, comm);
    for (Eigen::AlignedBox3d& box : boxes) {
      box.min().array() -= reach;
      box.max().array() += reach;
    }
    std::vector<std::vector<char>> out(ranks);
    for (const auto& [i, m] : mine) {
      const uint64_t index = i;
      for (int r = 0; r < ranks; ++r) {
        if (std::isfinite(reach) && !m.mayCover(boxes[r])) continue;
        mpi::pack(out[r], &index, 1);
        m.pack(out[r]);
      }
    }
    mine.clear();
    all.assign(scanOf.empty() ? 0 : scanOf.back() + 1, SightMap{});
    for (const auto& part : mpi::exchangeBytes(std::move(out), comm))
      for (size_t pos = 0; pos < part.size();) {
        uint64_t index;
        mpi::unpack(part, pos, &index, 1);
        all[scanOf[index]].join(SightMap::unpack(part, pos));
      }
    uint64_t held = 0;
    for (const SightMap& m : all) held += m.bytes();
    memoryLedger().set(Held::sightMaps, held);
  }

  /// Collective: the world box of each rank's bricks (empty when it has none).
  static std::vector<Eigen::AlignedBox3d> ownedBoxes(const BrickLayout& layout, MPI_Comm comm) {
    Eigen::AlignedBox3d box;
    const VoxelGrid& g = layout.grid;
    const int me = mpi::rank(comm);
    for (size_t b = layout.rankStart[me]; b < layout.rankStart[me + 1]; ++b) {
      const VoxelIndex first = mortonDecode(layout.codes[b]) * g.brick;
      box.extend(g.centre(first));
      box.extend(g.centre(first + VoxelIndex::Constant(g.brick - 1)));
    }
    std::vector<char> bytes;
    mpi::pack(bytes, &box, 1);
    std::vector<Eigen::AlignedBox3d> boxes;
    for (const auto& part : mpi::allgatherBytes(bytes, comm)) {
      size_t pos = 0;
      mpi::unpack(part, pos, &box, 1);
      boxes.push_back(box);
    }
    return boxes;
  }
};

/// Pass 1: reads this rank's scans, keeps what fits, and returns the bounds of all points.
bool readShare(const io::ConfFile& conf, HeldScans& share, int threads, MPI_Comm comm,
               Progress& progress, Eigen::AlignedBox3d& box, uint64_t& triangles,
               std::vector<uint64_t>& bytes, std::vector<std::optional<ColourKind>>& kinds,
               SightMaps* sights) {
  std::map<size_t, std::string> warnings;
  triangles = 0;
  bytes.assign(conf.scans.size(), 0);
  // 1 + the kind a scan carries, on its reader; 0 elsewhere, and for a scan (or a band of one)
  // with no points, which says nothing about the colour of its file.
  std::vector<uint8_t> kindOf(conf.scans.size(), 0);
  std::vector<size_t> worked;
  if (!collectively(comm, [&] {
        std::vector<size_t> mine;
        for (size_t i = 0; i < conf.scans.size(); ++i)
          if (share.holds(i)) mine.push_back(i);
        const size_t own = mine.size();
        size_t done = 0;
        // As many scans at a time as the rank has threads: one each. Frames of one size cost
        // what they show (real kitchen, 200 frames a rank: 9.5 M triangles against 13.6 M,
        // reading done at 4.8 s against 6.8 s), so a rank done early reads others' scans.
        const auto readBatch = [&](const std::vector<size_t>& batch) {
          std::vector<PrismScan> scans = share.read(batch, threads);
          // Kept until routed as routing packs them: compact, only the points prisms use.
          std::vector<std::vector<char>> packed(batch.size());
          parallelFor(batch.size(), threads, [&](size_t k) { packed[k] = packedScan(scans[k]); });
          for (size_t k = 0; k < batch.size(); ++k) {
            const size_t i = batch[k];
            PrismScan& s = scans[k];
            if (s.surface.triangles.empty())
              warnings[i] = conf.scans[i].path + ": no triangles survive the filters";
            box.extend(pointBounds(s));
            triangles += s.surface.triangles.size();
            if (!s.surface.points.empty())
              kindOf[i] = 1 + static_cast<uint8_t>(s.surface.colourKind);
            if (sights && s.sight) sights->mine.emplace(i, *s.sight);
            bytes[i] = packed[k].size();
            share.offerPacked(i, std::move(packed[k]));
          }
          done += batch.size();
          // A large station's bands count as scans here.
          progress.update("read", "rank 0 has prepared " + std::to_string(done) + " scans (" +
                                      std::to_string(own) + " were its own)");
        };
        worked =
            mpi::forEachStealing(std::move(mine), static_cast<size_t>(threads), readBatch, comm);
      }))
    return false;
  std::vector<int> readers(conf.scans.size(), -1);
  for (size_t i : worked) readers[i] = mpi::rank(comm);
  MPI_Allreduce(MPI_IN_PLACE, readers.data(), static_cast<int>(readers.size()), MPI_INT, MPI_MAX,
                comm);
  share.setReaders(std::move(readers));
  printWarnings(warnings, comm);
  box = mpi::unitedBox(box, comm);
  MPI_Allreduce(MPI_IN_PLACE, &triangles, 1, MPI_UINT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, bytes.data(), static_cast<int>(bytes.size()), MPI_UINT64_T, MPI_SUM,
                comm);
  MPI_Allreduce(MPI_IN_PLACE, kindOf.data(), static_cast<int>(kindOf.size()), MPI_UINT8_T, MPI_MAX,
                comm);
  kinds.clear();
  for (const uint8_t k : kindOf)
    kinds.push_back(k == 0 ? std::nullopt : std::optional(static_cast<ColourKind>(k - 1)));
  return true;
}

/// Pass 2: the bricks every prism touches, planned from this rank's scans and reduced.
bool planShare(const StreamOptions& o, const io::ConfFile& conf, const HeldScans& share,
               const VoxelGrid& grid, MPI_Comm comm, BrickLayout& layout, double& seconds) {
  BrickWork work;
  const auto start = std::chrono::steady_clock::now();
  if (!collectively(comm, [&] {
        // Kept scans whole, a share on each thread (one parallel section, not one a scan),
        // each unpacked by its thread as it comes; the others are read again one at a time,
        // each on all threads.
        std::vector<size_t> kept, unkept;
        for (size_t i = 0; i < conf.scans.size(); ++i) {
          if (!share.holds(i)) continue;
          (share.kept(i) ? kept : unkept).push_back(i);
        }
        const size_t parts = static_cast<size_t>(std::max(1, o.threads));
        std::vector<BrickWork> part(parts);
        parallelFor(parts, o.threads, [&](size_t k) {
          for (size_t j = k; j < kept.size(); j += parts)
            addPrismWork(*share.get(kept[j]), grid, o.limits.maxVoxels, part[k], 1);
        });
        for (const BrickWork& p : part) addWork(p, grid, o.limits.maxVoxels, work);
        for (size_t i : unkept)
          addPrismWork(*share.get(i), grid, o.limits.maxVoxels, work, o.threads);
        seconds = secondsSince(start);
      }))
    return false;
  return collectively(comm,
                      [&] { layout = reduceBrickWork(work, grid, o.limits.maxVoxels, comm); });
}

/// The parts (sorted by entry) of each scan, in scan order: a station's bands together, one
/// image, so that a voxel takes its nearest triangle of them all.
std::vector<std::pair<size_t, std::vector<PrismScan*>>> partsByScan(
    IndexedScans& parts, const std::vector<size_t>& scanOf) {
  std::vector<std::pair<size_t, std::vector<PrismScan*>>> images;
  for (auto& [i, part] : parts) {
    if (images.empty() || images.back().first != scanOf[i])
      images.emplace_back(scanOf[i], std::vector<PrismScan*>{});
    images.back().second.push_back(&part);
  }
  return images;
}

/// The voxel updates the cost model predicts for rank `me`'s bricks.
uint64_t predictedUpdates(const BrickLayout& layout, int me) {
  uint64_t work = 0;
  for (size_t b = layout.rankStart[me]; b < layout.rankStart[me + 1]; ++b) work += layout.work[b];
  return static_cast<uint64_t>(static_cast<double>(work) / kWorkPerUpdate);
}

/// Collective: whether each scan's reader kept it.
std::vector<uint8_t> keptByReader(const HeldScans& share, MPI_Comm comm) {
  std::vector<uint8_t> kept(share.size(), 0);
  for (size_t i = 0; i < kept.size(); ++i) kept[i] = share.holds(i) && share.kept(i);
  MPI_Allreduce(MPI_IN_PLACE, kept.data(), static_cast<int>(kept.size()), MPI_UINT8_T, MPI_MAX,
                comm);
  return kept;
}

/// Prepared bytes a reader routes in a round, about. A round ends in a collective where every
/// rank waits for the slowest: with a scan a round, the real kitchen's ranks each waited 0.6 s
/// of their 1.8 s routing for frames larger than theirs. A few scans a round average that out,
/// and a round's copies in flight stay a few MiB.
constexpr uint64_t kRoundBytes = 4 << 20;

/// Collective: routes this rank's scans of entries [first, end) to the brick owners and
/// appends what this rank is sent, and its own part, to `parts`. There are as many rounds as
/// the busiest reader needs at kRoundBytes a round (roundCount), and every reader sends its
/// entries spread over them by bytes (roundsOf): what is in flight is about a round's copies,
/// not a window's, and each rank gives away about what it receives (the window is added in
/// scan order whatever the order it arrived in).
bool routeEntries(size_t first, size_t end, HeldScans& share,
                  const std::vector<uint64_t>& preparedBytes, bool colour, double reach,
                  const BrickLayout& layout, MPI_Comm comm, RoutedParts& parts,
                  RoutingStats& routing) {
  const int ranks = mpi::size(comm), me = mpi::rank(comm);
  std::vector<std::vector<size_t>> byReader(ranks);
  for (size_t i = first; i < end; ++i) byReader[share.reader(i)].push_back(i);
  const size_t rounds = roundCount(byReader, preparedBytes, kRoundBytes);
  // A kept scan is taken in its packed bytes, unpacked only if it has parts to send.
  const auto take = [&](size_t i) {
    TakenScan s{share.takePacked(i), {}};
    if (s.packed.empty()) s.scan = share.take(i);
    return s;
  };
  return routeRounds(roundsOf(byReader[me], rounds, preparedBytes), take, layout, reach, colour,
                     comm, parts, routing);
}

/// Unpacked parts a batch of images holds at most (and a whole image more): a window's parts
/// are held packed (decision 45), and only a batch's at a time as doubles.
constexpr uint64_t kBatchBytes = 32 << 20;

/// The next parts from `k` on (sorted by entry), whole images of about kBatchBytes held (a
/// compact part unpacks to about four times its bytes), unpacked on `threads` threads.
IndexedScans nextBatch(RoutedParts& parts, const std::vector<size_t>& scanOf, int threads,
                       size_t& k) {
  const size_t first = k;
  uint64_t held = 0;
  while (k < parts.size() &&
         (held < kBatchBytes / 4 || scanOf[parts.entry(k)] == scanOf[parts.entry(k - 1)]))
    held += parts.bytesOf(k++);
  IndexedScans batch = parts.take(first, k, threads);
  uint64_t bytes = 0;
  for (const auto& [i, part] : batch) bytes += scanBytes(part);
  memoryLedger().set(Held::routedScans, parts.bytes() + bytes);
  return batch;
}

/// Adds a window's parts (sorted by entry) to the integrator in scan order, a batch at a time.
/// A part routed here carries no sight map: the rank's copy of its scan's map (`sights`, robust
/// fusion) gives its samples' noise.
void addParts(RoutedParts& parts, const std::vector<size_t>& scanOf, std::vector<SightMap>* sights,
              int threads, PrismIntegrator& integrator, RankCounters& counters) {
  for (size_t k = 0; k < parts.size();) {
    IndexedScans batch = nextBatch(parts, scanOf, threads, k);
    // The batch's images go to the integrator together: its threads need not wait for each
    // other between images.
    std::vector<PrismIntegrator::Image> images;
    for (const auto& [i, image] : partsByScan(batch, scanOf)) {
      faultPoint("field");
      if (sights)
        for (PrismScan* part : image)
          part->sight = std::shared_ptr<SightMap>(std::shared_ptr<SightMap>(), &(*sights)[i]);
      images.emplace_back(image.begin(), image.end());
    }
    const auto start = std::chrono::steady_clock::now();
    const IntegrationStats st = integrator.addImages(images);
    counters.addSeconds += secondsSince(start);
    counters.prisms += st.prisms;
    counters.voxelUpdates += st.voxelUpdates;
    memoryLedger().set(Held::integrator, integrator.bytes());
  }
}

/// The closest-surface methods keep each scan's parts, joined, as the field's scans.
void keepParts(RoutedParts& parts, const std::vector<size_t>& scanOf, FusedField& field) {
  IndexedScans all = parts.takeAll();
  for (const auto& [i, image] : partsByScan(all, scanOf)) {
    faultPoint("field");
    std::vector<PrismScan> bands;
    for (PrismScan* part : image) bands.push_back(std::move(*part));
    field.scans[i] = joinScans(std::move(bands));
  }
}

/// Pass 3: window by window, routes this rank's scans to the brick owners, which add what
/// they receive in scan order (or keep it, for the closest-surface methods).
bool integrateShare(const io::ConfFile& conf, const std::vector<size_t>& scanOf, HeldScans& share,
                    const std::vector<size_t>& windows, const std::vector<uint64_t>& preparedBytes,
                    double reach, int threads, SurfaceHypotheses* hypotheses,
                    std::vector<SightMap>* sights, MPI_Comm comm, Progress& progress,
                    FusedField& field, RankCounters& counters, RoutingStats& routing) {
  BrickStore& store = *field.store;
  if (reach > 0) field.scans.resize(field.scanCount);
  const int ranks = mpi::size(comm);
  // The closest-surface methods keep the scans instead (no per-voxel entries for them).
  std::optional<PrismIntegrator> integrator;
  if (reach == 0) integrator.emplace(store, threads, hypotheses);
  routing.bytes.assign(ranks, 0);
  // A lone rank's scans are its parts whole, and the copies it would have routed are the
  // prisms the integrator finds reaching a brick.
  const bool alone = ranks == 1 && reach == 0;
  for (size_t w = 0, first = 0; w < windows.size(); first = windows[w++]) {
    const size_t end = windows[w];
    RoutedParts parts;
    const auto start = std::chrono::steady_clock::now();
    if (!routeEntries(first, end, share, preparedBytes, store.hasColour(), reach, store.layout(),
                      comm, parts, routing))
      return false;
    counters.routeSeconds += secondsSince(start);
    parts.sortByEntry();
    if (integrator) {
      const uint64_t prisms = counters.prisms;
      addParts(parts, scanOf, sights, threads, *integrator, counters);
      if (alone) routing.copies += counters.prisms - prisms;
    } else {
      keepParts(parts, scanOf, field);
    }
    memoryLedger().set(Held::routedScans, 0);
    if (end < conf.scans.size())
      progress.update("field", std::to_string(end) + " of " + std::to_string(conf.scans.size()) +
                                   " scans added");
  }
  return true;
}

}  // namespace

bool buildStreamedField(const StreamOptions& o, const io::ConfFile& scans, MPI_Comm comm,
                        Progress& progress, FusedField& field, RankCounters& counters) {
  const int me = mpi::rank(comm), ranks = mpi::size(comm);
  // From here on a band of a large scan is an entry of its own, read by any rank; brick owners
  // join a scan's bands again before adding them.
  io::ConfFile conf = io::splitIntoBands(scans, o.bandCells);
  if (o.colour == ColourKind::intensity) io::preferIntensity(conf);
  // A field without colour reads none: decoding a frame's colour costs time and peak memory.
  if (o.colour == ColourKind::none) io::dropColourImages(conf);
  std::vector<size_t> scanOf;
  for (const io::ConfScan& c : conf.scans)
    scanOf.push_back(scanOf.empty() ? 0 : scanOf.back() + (c.band == 0));
  std::vector<Eigen::Vector3d> sensors;
  for (const io::ConfScan& c : conf.scans) sensors.push_back(c.pose.apply(Eigen::Vector3d::Zero()));
  // A field's scans are not registered: only depth images and sight maps need their noise.
  SurfaceOptions surface = o.surface;
  surface.measureNoise = false;
  HeldScans share(conf.scans, assignReadersNearby(sensors, fileSizes(conf), ranks), me,
                  ScanPreparation{surface, o.limits, o.eps, true}, o.keepBytes, true);
  Eigen::AlignedBox3d box;
  uint64_t triangles = 0;
  std::vector<uint64_t> bytes;
  std::vector<std::optional<ColourKind>> kinds;
  std::optional<SightMaps> sights;
  if (o.robust || o.keepSights) sights.emplace();
  if (!readShare(conf, share, std::max(1, o.threads), comm, progress, box, triangles, bytes, kinds,
                 sights ? &*sights : nullptr))
    return false;
  const std::string slip = voxelUnitWarning(o.voxel, box);
  if (!slip.empty() && me == 0) std::fprintf(stderr, "rangefuse: warning: %s\n", slip.c_str());
  ColourKind colour = ColourKind::none;
  std::string note;
  // Every rank holds the same kinds: the same choice, or the same error, everywhere.
  if (!collectively(comm, [&] { colour = chooseColour(o.colour, kinds, conf, note); }))
    return false;
  if (!note.empty() && me == 0) std::fprintf(stderr, "note: %s\n", note.c_str());
  malloc_trim(0);  // what reading freed goes back to the system before the field is allocated
  std::string read = std::to_string(scans.scans.size()) + " scans";
  if (conf.scans.size() > scans.scans.size())
    read += " (" + std::to_string(conf.scans.size()) + " with large ones in bands)";
  progress.stage("read", read + ", " + std::to_string(triangles) +
                             " triangles; scans kept per rank " +
                             std::to_string(share.keptCount()) + " (rank 0)");
  field.scanCount = scans.scans.size();
  field.scanTriangles = triangles;
  VoxelGrid grid;
  double planSeconds = 0;
  if (!collectively(comm, [&] { grid = gridAround(box, o.voxel, o.brick, o.eps); }) ||
      !planShare(o, conf, share, grid, comm, field.layout, planSeconds))
    return false;
  if (o.planned) o.planned(field.layout);
  // A hypothesis's surface lies within the envelope of its voxel: a voxel more for rounding.
  // Carving asks about any voxel of the field's box: then every map goes everywhere.
  if (sights) sights->share(scanOf, field.layout, o.keepSights ? INFINITY : o.eps + o.voxel, comm);
  field.store = std::make_unique<BrickStore>(field.layout, me);
  if (colour != ColourKind::none) field.store->enableColour(colour);
  memoryLedger().set(Held::field, field.store->bytes());
  // The field's layout and the store's copy.
  memoryLedger().set(Held::brickList, 2 * field.layout.bytes());
  counters = RankCounters{};
  counters.planSeconds = planSeconds;
  counters.bricks = field.store->brickCount();
  counters.predictedUpdates = predictedUpdates(field.layout, me);
  RoutingStats routing;
  std::optional<SurfaceHypotheses> hypotheses;
  if (o.robust) hypotheses.emplace(*field.store, *o.robust);
  // A quarter of --scan-memory a rank for the scans read again (the parts of a kept scan take
  // its place).
  const std::vector<size_t> windows = wholeScanWindows(
      routingWindows(bytes, keptByReader(share, comm), ranks, o.keepBytes / 4 * ranks), scanOf);
  if (!integrateShare(conf, scanOf, share, windows, bytes, o.routeReach, o.threads,
                      hypotheses ? &*hypotheses : nullptr, hypotheses ? &sights->all : nullptr,
                      comm, progress, field, counters, routing))
    return false;
  if (hypotheses &&
      !collectively(comm, [&] { counters.robust = hypotheses->resolve(sights->all, o.threads); }))
    return false;
  if (o.keepSights) field.sights = std::move(sights->all);
  uint64_t sent = 0;
  for (int r = 0; r < ranks; ++r) sent += r == me ? 0 : routing.bytes[r];
  uint64_t totals[2] = {sent, routing.copies};
  MPI_Allreduce(MPI_IN_PLACE, totals, 2, MPI_UINT64_T, MPI_SUM, comm);
  counters.routedBytes = sent;
  field.routedBytes = totals[0];
  field.routedCopies = totals[1];
  return true;
}

}  // namespace rangefuse
