#include "rangefuse/fuse/FuseJob.h"

#include <sys/resource.h>

#include <cmath>
#include <sstream>

#include "rangefuse/consensus/ConsensusSampler.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/fuse/Checkpointing.h"
#include "rangefuse/fuse/FuseParameters.h"
#include "rangefuse/fuse/OutputChecks.h"
#include "rangefuse/fuse/RegisterStage.h"
#include "rangefuse/fuse/RunReport.h"
#include "rangefuse/fuse/ScanLoader.h"
#include "rangefuse/fuse/StreamedField.h"
#include "rangefuse/fuse/TrackStage.h"
#include "rangefuse/io/MeshPartPly.h"
#include "rangefuse/io/MeshPartXdmf.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/FaultInjection.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/register/Registration.h"
#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

using mpi::collectively;

/// Consensus and naive: fields from closest-surface queries over routed triangles.
bool closestSurface(const FuseOptions& o) {
  return methodInfo(o.method).closestSurface;
}

size_t countTriangles(const std::vector<PrismScan>& scans) {
  size_t n = 0;
  for (const auto& s : scans) n += s.surface.triangles.size();
  return n;
}

std::string perRank(MPI_Comm comm, uint64_t value) {
  std::vector<uint64_t> all(mpi::size(comm));
  MPI_Gather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, comm);
  std::ostringstream s;
  for (size_t r = 0; r < all.size(); ++r) s << (r ? " / " : "") << all[r];
  return s.str();
}

/// "a / b / c s": seconds per rank, on rank 0.
std::string secondsPerRank(MPI_Comm comm, double seconds) {
  std::vector<double> all(mpi::size(comm));
  MPI_Gather(&seconds, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm);
  std::string text;
  char one[32];
  for (size_t r = 0; r < all.size(); ++r) {
    std::snprintf(one, sizeof one, "%s%.2f", r ? " / " : "", all[r]);
    text += one;
  }
  return text + " s";
}

/// " (max/mean X)" of a value across ranks, when there are several.
std::string balance(MPI_Comm comm, uint64_t value) {
  if (mpi::size(comm) == 1) return "";
  uint64_t max = value, sum = value;
  MPI_Allreduce(MPI_IN_PLACE, &max, 1, MPI_UINT64_T, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm);
  char text[40];
  std::snprintf(text, sizeof text, " (max/mean %.3f)",
                sum == 0 ? 1.0 : static_cast<double>(max) * mpi::size(comm) / sum);
  return text;
}

/// Rank 0 warns when the checkpoint or the mesh may not fit where they go.
void warnStorage(const FuseOptions& o, const BrickLayout& layout, MPI_Comm comm) {
  if (mpi::rank(comm) != 0) return;
  for (const std::string& w : storageWarnings(o, layout))
    std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
}

}  // namespace

void validateFuseOptions(const FuseOptions& o) {
  for (const FuseParameter& p : fuseParameters()) {
    const std::string wrong = p.check ? p.check(o) : "";
    if (!wrong.empty()) throw InputError("--" + p.option + " " + wrong);
  }
}

namespace {

/// Past the largest distance a brick-sized cell is refined at, plus 2 delta_d: a consensus
/// closer than margin - 2 delta_d is settled by the triangles within the margin.
double closestSurfaceMargin(const FuseOptions& o) {
  return (std::sqrt(3.0) * (0.5 * o.brick + 1) + 1) * o.voxel + 2 * o.sameDistance * o.voxel;
}

}  // namespace

SurfaceOptions surfaceOptions(const FuseOptions& o) {
  SurfaceOptions s = o.surface;
  s.mergeTarget = o.mergeCells * o.voxel;
  s.sightMap = methodInfo(o.method).hypotheses;
  return s;
}

double routeReach(const FuseOptions& o) {
  // Every triangle within the margin of a brick's bounding ball, whose radius is half the
  // diagonal of its voxel centres; one voxel more as bricksOfBox goes by voxel centres.
  return closestSurfaceMargin(o) + (0.5 * std::sqrt(3.0) * (o.brick - 1) + 1) * o.voxel;
}

EvaluationStats evaluateClosestSurfaceField(const FuseOptions& o, FusedField& field, int minViews) {
  std::vector<ViewIndex> views;
  for (const auto& s : field.scans) views.emplace_back(s.surface);
  ConsensusParams params;
  params.quorum = o.quorum >= 0 ? o.quorum : autoQuorum(field.scanCount);
  params.minViews = minViews;
  params.sameDistance = o.sameDistance * o.voxel;
  params.sameCosine = std::cos(o.sameAngle * M_PI / 180);
  params.edgeCosine = std::cos(o.edgeAngle * M_PI / 180);
  // Near the surface the offset's direction is noise: half a voxel of slack for the final
  // test; joining a consensus is judged tighter, as a rim point biases the average.
  params.edgeSlack = 0.5 * o.voxel;
  params.memberSlack = 0.05 * o.voxel;
  // Routed or not, a voxel's value depends only on the triangles within the margin of its
  // brick, so that it is the same on any number of ranks (docs/consensus.md).
  ConsensusSampler sampler(views, params, o.method == FieldMethod::Naive, closestSurfaceMargin(o),
                           false);
  faultPoint("field");
  return evaluateNearSurface(*field.store, sampler);
}

namespace {

bool writeOutputs(const FuseOptions& o, MPI_Comm comm, const FusedField& field, MeshPart& mesh) {
  if (o.normals) addPartNormals(mesh, comm);
  const bool written = io::isXdmfPath(o.out) ? io::writeMeshPartXdmf(o.out, mesh, comm)
                                             : io::writeMeshPartPly(o.out, mesh, comm);
  if (!written) return false;
  if (o.preview.empty()) return true;
  const Image picture = renderDistributed(*field.store, o.minWeight, ViewSettings{}, 0, comm);
  return collectively(comm, [&] {
    if (mpi::rank(comm) == 0) io::writePng(o.preview, picture);
  });
}

bool writePoses(const FuseOptions& o, MPI_Comm comm, const LoadedScans& scans) {
  if (o.posesOut.empty()) return true;
  return collectively(comm, [&] {
    if (mpi::rank(comm) != 0) return;
    std::vector<io::ConfScan> out;
    for (size_t i = 0; i < scans.names.size(); ++i)
      out.push_back({scans.names[i], "", scans.poses[i]});
    io::writeConf(o.posesOut, out);
  });
}

}  // namespace

nlohmann::json resultParameters(const FuseOptions& o) {
  nlohmann::json out = nlohmann::json::object();
  for (const FuseParameter& p : fuseParameters())
    if (p.recorded == Recorded::Result) out[p.key] = parameterJson(p, o);
  return out;
}

double autoQuorum(size_t views) {
  return 2.25 * static_cast<double>(views) / 48;
}

uint64_t peakMemoryMiB() {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return static_cast<uint64_t>(u.ru_maxrss) / 1024;  // ru_maxrss is in KiB on Linux
}

namespace {

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

}  // namespace

bool loadScans(const FuseOptions& o, MPI_Comm comm, Progress& progress, LoadedScans& scans,
               const std::vector<Pose>* poses, const std::vector<char>* lost) {
  io::ConfFile conf;
  if (!collectively(comm, [&] {
        validateFuseOptions(o);
        conf = io::readScanList(o.scans, o.limits, o.source);
        placeAndKeep(conf, poses, lost, o.scans);
      }))
    return false;
  scans.rank = mpi::rank(comm);
  scans.posed = conf.posed;
  for (size_t i = 0; i < conf.scans.size(); ++i) scans.readers.push_back(i % mpi::size(comm));
  for (const auto& c : conf.scans) {
    scans.names.push_back(c.name);
    scans.paths.push_back(c.path);
    scans.poses.push_back(c.pose);
    scans.times.push_back(c.time);
  }
  // Held scans feed registration fields, which are prism or closest-surface fields: robust
  // fusion's sight maps are made when the final field streams the scans again.
  ScanPreparation preparation{surfaceOptions(o), o.limits, o.envelope * o.voxel};
  preparation.surface.sightMap = false;
  scans.held = std::make_shared<HeldScans>(conf.scans, scans.readers, scans.rank, preparation,
                                           static_cast<uint64_t>(o.scanMemory * 1024 * 1024));
  // Each rank reads its scans and keeps those that fit the budget; the others are read again
  // whenever a registration field needs them.
  uint64_t triangles = 0;
  std::vector<std::string> empty;
  std::vector<size_t> mine;
  for (size_t i = 0; i < conf.scans.size(); ++i)
    if (scans.holds(i)) mine.push_back(i);
  if (!collectively(comm, [&] {
        forEachBatch(mine, o.threads, [&](const std::vector<size_t>& which) {
          const auto read = scans.held->readAndOffer(which, o.threads);
          for (size_t k = 0; k < which.size(); ++k) {
            triangles += read[k]->surface.triangles.size();
            if (read[k]->surface.triangles.empty()) empty.push_back(conf.scans[which[k]].path);
          }
        });
      }))
    return false;
  if (progress.isRoot())
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
  for (const auto& path : empty)
    std::fprintf(stderr, "rangefuse: warning: %s: no triangles survive the filters\n",
                 path.c_str());
  MPI_Allreduce(MPI_IN_PLACE, &triangles, 1, MPI_UINT64_T, MPI_SUM, comm);
  progress.stage("read", std::to_string(conf.scans.size()) + " scans, " +
                             std::to_string(triangles) + " triangles; scans kept per rank " +
                             std::to_string(scans.held->keptCount()) + " (rank 0)");
  return true;
}

bool buildFieldOf(const FuseOptions& o, std::vector<PrismScan> world, MPI_Comm comm,
                  FusedField& field, RankCounters& counters) {
  const double eps = o.envelope * o.voxel;
  field.scans = std::move(world);
  field.scanCount = field.scans.size();
  field.scanTriangles = countTriangles(field.scans);
  if (!collectively(comm, [&] {
        // Every rank holds every scan here, so each plans the whole list and keeps its part.
        field.layout =
            directoryOf(planBricks(field.scans, fitGrid(field.scans, o.voxel, o.brick, eps),
                                   mpi::size(comm), o.limits.maxVoxels),
                        mpi::rank(comm));
      }))
    return false;
  warnStorage(o, field.layout, comm);
  field.store = std::make_unique<BrickStore>(field.layout, mpi::rank(comm));
  counters = RankCounters{};
  counters.bricks = field.store->brickCount();
  if (!closestSurface(o)) {
    PrismIntegrator integrator(*field.store);
    for (const auto& s : field.scans) {
      faultPoint("field");
      const IntegrationStats st = integrator.addScan(s);
      counters.prisms += st.prisms;
      counters.voxelUpdates += st.voxelUpdates;
    }
    return true;
  }
  const EvaluationStats st = evaluateClosestSurfaceField(o, field, o.minViews);
  counters.evaluatedPoints = st.points;
  counters.voxelUpdates = st.voxels;
  return true;
}

bool streams(const FuseOptions& o) {
  return o.registration == RegistrationMode::None;
}

namespace {

std::string fieldLine(const FuseOptions& o, MPI_Comm comm, const FusedField& field,
                      const RankCounters& counters) {
  std::string line = std::string(toString(o.method)) + ": " +
                     std::to_string(field.layout.totalBricks()) + " bricks, per rank " +
                     perRank(comm, counters.bricks) + "; voxels updated per rank " +
                     perRank(comm, counters.voxelUpdates) + balance(comm, counters.voxelUpdates);
  if (!methodInfo(o.method).closestSurface && mpi::size(comm) > 1)
    line += "; adding images per rank " + secondsPerRank(comm, counters.addSeconds);
  if (methodInfo(o.method).hypotheses) {
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

StreamOptions streamOptions(const FuseOptions& o, MPI_Comm comm) {
  StreamOptions s;
  s.planned = [&o, comm](const BrickLayout& layout) { warnStorage(o, layout, comm); };
  s.voxel = o.voxel;
  s.eps = o.envelope * o.voxel;
  s.brick = o.brick;
  s.surface = surfaceOptions(o);
  s.limits = o.limits;
  s.keepBytes = static_cast<uint64_t>(o.scanMemory * 1024 * 1024);
  s.threads = o.threads;
  s.bandCells = static_cast<uint64_t>(o.bandCells);
  if (closestSurface(o)) s.routeReach = routeReach(o);
  // Prism and robust fields carry colour; the closest-surface methods fuse depth alone.
  const bool colours = !methodInfo(o.method).closestSurface;
  if (o.colour != "auto" || !colours)
    s.colour = parseColourKind(colours ? o.colour : "none", ColourKind::none);
  if (methodInfo(o.method).hypotheses)
    s.robust =
        HypothesisParams{o.sameDistance * o.voxel, std::cos(o.sameAngle * M_PI / 180), o.minViews,
                         (o.freeMargin == -1 ? o.envelope : o.freeMargin) * o.voxel};
  return s;
}

/// Streamed field of the .conf's scans at `poses` (the .conf's when null); scans gets the
/// names, paths and poses only.
bool buildStreamed(const FuseOptions& o, MPI_Comm comm, Progress& progress, LoadedScans& scans,
                   FusedField& field, RankCounters& counters,
                   const std::vector<Pose>* poses = nullptr,
                   const std::vector<char>* lost = nullptr) {
  io::ConfFile conf;
  if (!collectively(comm, [&] {
        validateFuseOptions(o);
        conf = io::readScanList(o.scans, o.limits, o.source);
        if (!conf.posed && !poses)
          throw InputError(o.scans +
                           ": a depth stream without a trajectory has no poses to place its "
                           "frames: fuse tracks it (rangefuse fuse --scans ... --trajectory-out)");
        placeAndKeep(conf, poses, lost, o.scans);
      }))
    return false;
  if (progress.isRoot() && !poses)
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
  scans.names.clear(), scans.paths.clear(), scans.poses.clear();
  for (const io::ConfScan& c : conf.scans) {
    scans.names.push_back(c.name);
    scans.paths.push_back(c.path);
    scans.poses.push_back(c.pose);
  }
  if (!buildStreamedField(streamOptions(o, comm), conf, comm, progress, field, counters))
    return false;
  if (closestSurface(o) && !collectively(comm, [&] {
        const EvaluationStats st = evaluateClosestSurfaceField(o, field, o.minViews);
        counters.evaluatedPoints = st.points;
        counters.voxelUpdates = st.voxels;
        field.scans = {};
      }))
    return false;
  progress.stage("field", fieldLine(o, comm, field, counters));
  return true;
}

}  // namespace

bool buildField(const FuseOptions& o, MPI_Comm comm, Progress& progress, FusedField& field,
                RankCounters& counters) {
  LoadedScans scans;
  return buildStreamed(o, comm, progress, scans, field, counters);
}

namespace {

/// Mesh, outputs, poses and report of a finished field.
int finish(const FuseOptions& o, MPI_Comm comm, Progress& progress, const LoadedScans& scans,
           FusedField& field, RankCounters& counters, const std::vector<RegistrationStep>& steps) {
  MeshStats ms;
  MeshPart mesh = extractDistributedMesh(*field.store, o.minWeight, comm, &ms, o.threads);
  counters.haloBricks = ms.haloBricksReceived;
  counters.triangles = ms.localTriangles;
  progress.stage("mesh", std::to_string(mesh.totalFaces) + " triangles, " +
                             std::to_string(mesh.totalVertices) +
                             " vertices, halo bricks per rank " +
                             perRank(comm, ms.haloBricksReceived));
  if (!writeOutputs(o, comm, field, mesh) || !writePoses(o, comm, scans)) return 1;
  progress.stage("write", o.out + (o.preview.empty() ? "" : ", " + o.preview) +
                              (o.posesOut.empty() ? "" : ", " + o.posesOut));
  progress.stage("done", "peak memory per rank (MiB) " + perRank(comm, peakMemoryMiB()));
  if (o.report.empty()) return 0;
  return collectively(comm,
                      [&] { writeRunReport(o, comm, progress, counters, field, mesh, steps); })
             ? 0
             : 1;
}

/// Scan names, paths and hashes of the .conf, for checking a resume and writing checkpoints.
bool identifyScans(const FuseOptions& o, MPI_Comm comm, LoadedScans& scans,
                   std::vector<std::string>& hashes) {
  return collectively(comm, [&] {
    const io::ConfFile conf = io::readScanList(o.scans, o.limits, o.source);
    for (const auto& c : conf.scans) scans.names.push_back(c.name), scans.paths.push_back(c.path);
    hashes = hashScans(scans.paths, comm);
  });
}

/// Continues from a checkpoint that holds the finished field.
int resumeFromField(const FuseOptions& o, const io::CheckpointMeta& meta, MPI_Comm comm,
                    Progress& progress) {
  LoadedScans scans;
  std::vector<std::string> hashes;
  if (!identifyScans(o, comm, scans, hashes)) return 1;
  if (!collectively(comm, [&] { checkScanHashes(meta, scans, hashes); })) return 1;
  scans.poses = meta.poses;
  FusedField field;
  if (!collectively(
          comm, [&] { field.store = io::readCheckpointField(o.resume, meta, field.layout, comm); }))
    return 1;
  RankCounters counters;
  counters.bricks = field.store->brickCount();
  progress.stage("resume", o.resume + ": field of " + std::to_string(field.layout.totalBricks()) +
                               " bricks, per rank " + perRank(comm, counters.bricks));
  return finish(o, comm, progress, scans, field, counters, {});
}

bool writeFieldCheckpoint(const FuseOptions& o, MPI_Comm comm, Progress& progress,
                          const LoadedScans& scans, const FusedField& field) {
  if (o.checkpoint.empty()) return true;
  if (!collectively(comm, [&] {
        const std::vector<std::string> hashes = hashScans(scans.paths, comm);
        io::writeCheckpoint(o.checkpoint,
                            checkpointMeta(o, scans, hashes, {{"stage", "field"}}, &field),
                            field.store.get(), comm);
      }))
    return false;
  progress.stage("checkpoint", o.checkpoint);
  return true;
}

/// A depth stream tracked frame by frame into the field that is meshed. Other methods than
/// prism fuse the tracked frames again, lost ones left out.
/// Algorithm 2 after the stream: the tracked frames (lost ones left out) registered together
/// against the field of all of them, then fused again at the refined poses.
int refineTracked(const FuseOptions& o, MPI_Comm comm, Progress& progress,
                  const std::vector<Pose>& tracked, const std::vector<char>& lost) {
  LoadedScans scans;
  if (!loadScans(o, comm, progress, scans, &tracked, &lost)) return 1;
  RegistrationProgress state;
  std::vector<RegistrationStep> steps;
  if (!registerPoses(o, comm, progress, scans, state, steps) ||
      !writeTrajectoryFile(o.trajectoryOut, scans, {}, comm))
    return 1;
  // Back to one pose per frame of the list, for the final field that reads the list again.
  std::vector<Pose> refined = tracked;
  for (size_t i = 0, k = 0; i < refined.size(); ++i)
    if (!lost[i]) refined[i] = scans.poses[k++];
  scans.held.reset();
  FusedField field;
  RankCounters counters;
  if (!buildStreamed(o, comm, progress, scans, field, counters, &refined, &lost) ||
      !writeFieldCheckpoint(o, comm, progress, scans, field))
    return 1;
  return finish(o, comm, progress, scans, field, counters, steps);
}

int runTracking(const FuseOptions& o, MPI_Comm comm, Progress& progress,
                const io::CheckpointMeta* resumed = nullptr) {
  if (!collectively(comm, [&] {
        if (o.registration != RegistrationMode::None &&
            o.registration != RegistrationMode::Simultaneous)
          throw InputError("--register " + std::string(toString(o.registration)) +
                           ": tracked frames are registered as they arrive (Algorithm 1); after "
                           "the stream only --register simultaneous refines them");
        if (o.registration == RegistrationMode::Simultaneous && !o.checkpoint.empty())
          throw InputError(
              "--checkpoint: a tracked stream refined by --register simultaneous "
              "cannot be checkpointed yet");
      }))
    return 1;
  LoadedScans scans;
  std::vector<char> lost;
  FusedField field;
  RankCounters counters;
  if (!openStream(o, comm, progress, scans) ||
      !trackStream(o, comm, progress, scans, lost, field, counters, resumed))
    return 1;
  if (o.registration == RegistrationMode::Simultaneous) {
    const std::vector<Pose> tracked = scans.poses;
    scans.held.reset();
    field = FusedField{};
    return refineTracked(o, comm, progress, tracked, lost);
  }
  if (!writeTrajectoryFile(o.trajectoryOut, scans, lost, comm)) return 1;
  if (o.method != FieldMethod::Prism) {
    const std::vector<Pose> tracked = scans.poses;
    scans.held.reset();
    field = FusedField{};
    if (!buildStreamed(o, comm, progress, scans, field, counters, &tracked, &lost)) return 1;
  }
  if (!writeFieldCheckpoint(o, comm, progress, scans, field)) return 1;
  return finish(o, comm, progress, scans, field, counters, {});
}

/// Collective: whether the run tracks a depth stream (reads the scan list).
bool decideTracking(const FuseOptions& o, MPI_Comm comm, bool& tracking) {
  return collectively(comm, [&] {
    if (o.follow) {  // the folder may hold no frames yet
      if (o.track == "off")
        throw InputError("--follow tracks a stream while it is recorded: leave out --track off");
      tracking = true;
      return;
    }
    const io::ConfFile conf = io::readScanList(o.scans, o.limits, o.source);
    tracking = tracksFrames(o.track, conf.posed, o.scans);
  });
}

}  // namespace

int runFuse(const FuseOptions& given, MPI_Comm comm) {
  memoryLedger().start();
  Progress progress(comm);
  FuseOptions o = given;
  io::CheckpointMeta resumed;
  if (!o.resume.empty() && !collectively(comm, [&] {
        resumed = io::readCheckpointMeta(o.resume, comm, o.limits);
        adoptCheckpointParameters(resumed, o);
      }))
    return 1;
  if (!collectively(comm, [&] {
        if (o.out.empty()) throw InputError("--out is required (the mesh .ply to write)");
        validateFuseOptions(o);
        checkOutputs(o, mpi::rank(comm));
      }))
    return 1;
  if (o.threads == 0) o.threads = threadsPerRank(comm);
  if (!o.resume.empty()) {
    const std::string stage = resumed.progress.value("stage", "");
    if (stage == "field") return resumeFromField(o, resumed, comm, progress);
    if (stage == "tracking") return runTracking(o, comm, progress, &resumed);
    if (stage != "registration" && !collectively(comm, [&] {
          throw InputError(o.resume + ": unknown stage '" + stage + "'");
        }))
      return 1;
  }
  bool tracking = false;
  if (o.resume.empty() && !decideTracking(o, comm, tracking)) return 1;
  if (tracking) return runTracking(o, comm, progress);
  if (o.resume.empty() && streams(o)) {
    LoadedScans scans;
    FusedField field;
    RankCounters counters;
    if (!buildStreamed(o, comm, progress, scans, field, counters) ||
        !writeFieldCheckpoint(o, comm, progress, scans, field))
      return 1;
    return finish(o, comm, progress, scans, field, counters, {});
  }
  LoadedScans scans;
  if (!loadScans(o, comm, progress, scans)) return 1;
  RegistrationProgress state;
  if (!o.resume.empty() && !collectively(comm, [&] {
        checkScanHashes(resumed, scans, hashScans(scans.paths, comm));
        scans.poses = resumed.poses;
        state = RegistrationProgress::fromJson(resumed.progress.at("registration"));
      }))
    return 1;
  if (!o.resume.empty())
    progress.stage("resume", o.resume + ": registration " + state.phase + ", scan " +
                                 std::to_string(state.nextScan) + ", round " +
                                 std::to_string(state.round) + " iteration " +
                                 std::to_string(state.iteration));
  std::vector<RegistrationStep> steps;
  if (!registerPoses(o, comm, progress, scans, state, steps)) return 1;
  // The final field streams the scans again at the registered poses: registration keeps only
  // each rank's own share, and the field is the same bits as one built from held scans.
  const std::vector<Pose> registered = scans.poses;
  scans.held.reset();
  FusedField field;
  RankCounters counters;
  if (!buildStreamed(o, comm, progress, scans, field, counters, &registered)) return 1;
  if (!writeFieldCheckpoint(o, comm, progress, scans, field)) return 1;
  return finish(o, comm, progress, scans, field, counters, steps);
}

}  // namespace rangefuse
