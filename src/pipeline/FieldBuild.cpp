#include "rangefuse/pipeline/FieldBuild.h"

#include <cmath>

#include "rangefuse/consensus/ConsensusSampler.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/FaultInjection.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/pipeline/RunLines.h"
#include "rangefuse/pipeline/StreamedField.h"
#include "rangefuse/pipeline/VoxelCheck.h"

namespace rangefuse {
namespace {

using internal::balance;
using internal::perRank;
using internal::secondsPerRank;
using mpi::collectively;

/// Past the largest distance a brick-sized cell is refined at, plus 2 delta_d: a consensus
/// closer than margin - 2 delta_d is settled by the triangles within the margin.
double closestSurfaceMargin(const FieldSettings& f) {
  return (std::sqrt(3.0) * (0.5 * f.brick + 1) + 1) * f.voxel + 2 * f.sameDistance * f.voxel;
}

/// The list's scans at `poses` (when given, one per scan of the list: a longer list is cut to
/// them), without those marked `lost` (when given). `list` names it in errors.
void placeAndKeep(io::ConfFile& conf, const std::vector<Pose>* poses, const std::vector<char>* lost,
                  const std::string& list) {
  if (poses && conf.scans.size() < poses->size())
    throw InputError(list + ": the list now holds " + std::to_string(conf.scans.size()) +
                     " scans, fewer than the " + std::to_string(poses->size()) + " placed");
  // A followed folder may have gained frames after its stream ended: they are not part of it.
  if (poses) conf.scans.resize(poses->size());
  std::vector<io::ConfScan> kept;
  for (size_t i = 0; i < conf.scans.size(); ++i) {
    if (lost && (*lost)[i]) continue;
    if (poses) conf.scans[i].pose = (*poses)[i];
    kept.push_back(conf.scans[i]);
  }
  conf.scans = std::move(kept);
}

/// Collective: the scan list, placed and filtered (placeAndKeep); a depth stream without a
/// trajectory is refused unless poses are given. False on failure (printed once).
bool readList(const ReadSettings& read, MPI_Comm comm, const std::vector<Pose>* poses,
              const std::vector<char>* lost, bool needPoses, io::ConfFile& conf) {
  return collectively(comm, [&] {
    conf = read.list ? *read.list : io::readScanList(read.scans, read.limits, read.source);
    if (needPoses && !conf.posed && !poses)
      throw InputError(read.scans +
                       ": a depth stream without a trajectory has no poses to place its "
                       "frames: fuse tracks it (rangefuse fuse --scans ... --trajectory-out)");
    placeAndKeep(conf, poses, lost, read.scans);
  });
}

void printWarnings(const io::ConfFile& conf, const Progress& progress) {
  if (progress.isRoot())
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
}

std::string fieldLine(FieldMethod method, MPI_Comm comm, const FusedField& field,
                      const RankCounters& counters) {
  std::string line = std::string(toString(method)) + ": " +
                     std::to_string(field.layout.totalBricks()) + " bricks, per rank " +
                     perRank(comm, counters.bricks) + "; voxels updated per rank " +
                     perRank(comm, counters.voxelUpdates) + balance(comm, counters.voxelUpdates);
  if (!methodInfo(method).closestSurface && mpi::size(comm) > 1) {
    line += "; adding images per rank " + secondsPerRank(comm, counters.addSeconds);
    // routedCopies is a sum over the ranks: every rank takes this branch or none does.
    if (field.routedCopies > 0)
      line += "; planning per rank " + secondsPerRank(comm, counters.planSeconds) +
              "; routing per rank " + secondsPerRank(comm, counters.routeSeconds);
  }
  if (methodInfo(method).hypotheses) {
    uint64_t r[3] = {counters.robust.agreed, counters.robust.unopposed, counters.robust.removed};
    MPI_Allreduce(MPI_IN_PLACE, r, 3, MPI_UINT64_T, MPI_SUM, comm);
    line += "; voxels agreed " + std::to_string(r[0]) + ", seen by fewer views and unopposed " +
            std::to_string(r[1]) + ", removed " + std::to_string(r[2]);
  }
  if (field.routedCopies > 0) {
    char routed[160];
    std::snprintf(routed, sizeof routed,
                  "; routed %.3f copies and %.1f bytes to other ranks per input triangle",
                  static_cast<double>(field.routedCopies) / field.scanTriangles,
                  static_cast<double>(field.routedBytes) / field.scanTriangles);
    line += routed;
  }
  return line;
}

StreamOptions streamOptions(const ReadSettings& read, const FieldSettings& f) {
  StreamOptions s;
  s.voxel = f.voxel;
  s.eps = f.eps();
  s.brick = f.brick;
  s.surface = read.surface;
  s.limits = read.limits;
  s.keepBytes = read.keepBytes;
  s.threads = read.threads;
  s.bandCells = read.bandCells;
  const MethodInfo& method = methodInfo(f.method);
  if (method.closestSurface) s.routeReach = routeReach(f);
  // Prism and robust fields carry colour; the closest-surface methods fuse depth alone.
  if (f.colour != "auto" || method.closestSurface)
    s.colour = parseColourKind(method.closestSurface ? "none" : f.colour, ColourKind::none);
  if (method.hypotheses)
    s.robust = HypothesisParams{f.sameDistance * f.voxel, std::cos(f.sameAngle * M_PI / 180),
                                f.minViews, f.lookedThroughMargin()};
  s.keepSights = f.fillHoles;
  return s;
}

}  // namespace

bool loadScans(const ReadSettings& read, MPI_Comm comm, Progress& progress, LoadedScans& scans,
               const std::vector<Pose>* poses, const std::vector<char>* lost) {
  io::ConfFile conf;
  if (!readList(read, comm, poses, lost, false, conf)) return false;
  scans.rank = mpi::rank(comm);
  scans.posed = conf.posed;
  for (size_t i = 0; i < conf.scans.size(); ++i)
    scans.add(conf.scans[i], readerOf(i, mpi::size(comm)));
  scans.held = heldScans(conf.scans, scans.readers, scans.rank, read);
  // Each rank reads its scans and keeps those that fit the budget; the others are read again
  // whenever a registration field needs them.
  uint64_t triangles = 0;
  std::vector<std::string> empty;
  std::vector<size_t> mine;
  Eigen::AlignedBox3d box;
  for (size_t i = 0; i < conf.scans.size(); ++i)
    if (scans.holds(i)) mine.push_back(i);
  if (!collectively(comm, [&] {
        forEachBatch(mine, read.threads, [&](const std::vector<size_t>& which) {
          const auto got = scans.held->readAndOffer(which, read.threads);
          for (size_t k = 0; k < which.size(); ++k) {
            triangles += got[k]->surface.triangles.size();
            if (got[k]->surface.triangles.empty()) empty.push_back(conf.scans[which[k]].path);
            for (const Eigen::Vector3d& p : got[k]->surface.points)
              box.extend(scans.poses[which[k]].apply(p));
          }
        });
      }))
    return false;
  printWarnings(conf, progress);
  const std::string slip = voxelUnitWarning(read.voxel, mpi::unitedBox(box, comm));
  if (!slip.empty() && progress.isRoot())
    std::fprintf(stderr, "rangefuse: warning: %s\n", slip.c_str());
  for (const auto& path : empty)
    std::fprintf(stderr, "rangefuse: warning: %s: no triangles survive the filters\n",
                 path.c_str());
  MPI_Allreduce(MPI_IN_PLACE, &triangles, 1, MPI_UINT64_T, MPI_SUM, comm);
  progress.stage("read", std::to_string(conf.scans.size()) + " scans, " +
                             std::to_string(triangles) + " triangles; scans kept per rank " +
                             std::to_string(scans.held->keptCount()) + " (rank 0)");
  return true;
}

bool buildStreamed(const ReadSettings& read, const FieldSettings& f, MPI_Comm comm,
                   Progress& progress, LoadedScans& scans, FusedField& field,
                   RankCounters& counters, const std::vector<Pose>* poses,
                   const std::vector<char>* lost,
                   const std::function<void(const BrickLayout&)>& planned) {
  io::ConfFile conf;
  if (!readList(read, comm, poses, lost, true, conf)) return false;
  if (!poses) printWarnings(conf, progress);
  scans.names.clear(), scans.paths.clear(), scans.poses.clear(), scans.times.clear();
  for (const io::ConfScan& c : conf.scans) {
    scans.names.push_back(c.name);
    scans.paths.push_back(c.path);
    scans.poses.push_back(c.pose);
    scans.times.push_back(c.time);
  }
  StreamOptions options = streamOptions(read, f);
  options.planned = planned;
  if (!buildStreamedField(options, conf, comm, progress, field, counters)) return false;
  if (methodInfo(f.method).closestSurface && !collectively(comm, [&] {
        const EvaluationStats st = evaluateClosestSurfaceField(f, field, f.minViews);
        counters.evaluatedPoints = st.points;
        counters.voxelUpdates = st.voxels;
        field.scans = {};
      }))
    return false;
  progress.stage("field", fieldLine(f.method, comm, field, counters));
  return true;
}

bool buildField(const ReadSettings& read, const FieldSettings& settings, MPI_Comm comm,
                Progress& progress, FusedField& field, RankCounters& counters) {
  LoadedScans scans;
  return buildStreamed(read, settings, comm, progress, scans, field, counters);
}

double routeReach(const FieldSettings& f) {
  // Every triangle within the margin of a brick's bounding ball, whose radius is half the
  // diagonal of its voxel centres; one voxel more as bricksOfBox goes by voxel centres.
  return closestSurfaceMargin(f) + (0.5 * std::sqrt(3.0) * (f.brick - 1) + 1) * f.voxel;
}

EvaluationStats evaluateClosestSurfaceField(const FieldSettings& f, FusedField& field,
                                            int minViews) {
  std::vector<ViewIndex> views;
  for (const auto& s : field.scans) views.emplace_back(s.surface);
  ConsensusParams params;
  params.quorum = f.quorum >= 0 ? f.quorum : autoQuorum(field.scanCount);
  params.minViews = minViews;
  params.sameDistance = f.sameDistance * f.voxel;
  params.sameCosine = std::cos(f.sameAngle * M_PI / 180);
  params.edgeCosine = std::cos(f.edgeAngle * M_PI / 180);
  // Near the surface the offset's direction is noise: half a voxel of slack for the final
  // test; joining a consensus is judged tighter, as a rim point biases the average.
  params.edgeSlack = 0.5 * f.voxel;
  params.memberSlack = 0.05 * f.voxel;
  // Routed or not, a voxel's value depends only on the triangles within the margin of its
  // brick, so that it is the same on any number of ranks (docs/consensus.md).
  ConsensusSampler sampler(views, params, f.method == FieldMethod::Naive, closestSurfaceMargin(f),
                           false);
  faultPoint("field");
  return evaluateNearSurface(*field.store, sampler);
}

double autoQuorum(size_t views) {
  return 2.25 * static_cast<double>(views) / 48;
}

}  // namespace rangefuse
