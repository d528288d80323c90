#include "rangefuse/run/FuseJob.h"

#include "TrackedRun.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/core/MemoryLedger.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/pipeline/Checkpointing.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/FinishRun.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/OutputChecks.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/pipeline/RegisterStage.h"
#include "rangefuse/pipeline/RunLines.h"
#include "rangefuse/track/TrackStage.h"

namespace rangefuse {
namespace {

using internal::finish;
using internal::storageWarner;
using internal::writeFieldCheckpoint;
using mpi::collectively;

/// The options of the run, with the result-deciding ones a checkpoint holds adopted when
/// resuming, checked; the checkpoint's meta in `resumed`. False on failure (printed once).
bool settle(FuseOptions& o, MPI_Comm comm, io::CheckpointMeta& resumed) {
  if (!o.outputs.resume.empty() && !collectively(comm, [&] {
        resumed = io::readCheckpointMeta(o.outputs.resume, comm, o.limits);
        adoptCheckpointParameters(resumed, o);
      }))
    return false;
  if (!collectively(comm, [&] {
        if (o.outputs.out.empty()) throw InputError("--out is required (the mesh .ply to write)");
        validateFuseOptions(o);
      }))
    return false;
  if (o.field.threads == 0) o.field.threads = threadsPerRank(comm);
  return true;
}

/// A checkpoint holding the finished field: meshed again.
int resumeFromField(const RunSettings& s, const io::CheckpointMeta& meta, MPI_Comm comm,
                    Progress& progress) {
  LoadedScans scans;
  if (!collectively(comm, [&] {
        if (!s.outputs.trajectoryOut.empty())
          throw InputError("--trajectory-out: " + s.outputs.resume +
                           " holds a finished field, not the frames' times; the run that "
                           "wrote it writes the trajectory");
        if (s.mesh.fillHoles)
          throw InputError("--fill-holes: " + s.outputs.resume +
                           " holds a finished field, without the sight maps carving needs; "
                           "fuse the scans again with --fill-holes");
        const ReadSettings& r = s.read;
        const io::ConfFile conf = io::readScanList(r.scans, r.limits, r.source);
        for (const auto& c : conf.scans)
          scans.names.push_back(c.name), scans.paths.push_back(c.path);
        checkScanHashes(meta, scans, hashScans(scans.paths, comm));
      }))
    return 1;
  scans.poses = meta.poses;
  FusedField field;
  if (!collectively(comm, [&] {
        field.store = io::readCheckpointField(s.outputs.resume, meta, field.layout, comm);
      }))
    return 1;
  RankCounters counters;
  counters.bricks = field.store->brickCount();
  progress.stage("resume", s.outputs.resume + ": field of " +
                               std::to_string(field.layout.totalBricks()) + " bricks, per rank " +
                               internal::perRank(comm, counters.bricks));
  return finish(s, comm, progress, scans, field, counters, {});
}

/// Scans at the list's poses: each rank reads a share and streams it to the brick owners.
int streamedRun(const RunSettings& s, MPI_Comm comm, Progress& progress) {
  LoadedScans scans;
  FusedField field;
  RankCounters counters;
  if (!buildStreamed(s.read, s.field, comm, progress, scans, field, counters, nullptr, nullptr,
                     storageWarner(s, comm)) ||
      !writeFieldCheckpoint(s.checkpoints(), comm, progress, scans, field) ||
      !writeTrajectoryFile(s.outputs.trajectoryOut, scans, {}, comm))
    return 1;
  return finish(s, comm, progress, scans, field, counters, {});
}

/// --register: the scans read and held, their poses registered (from the start or from
/// `resumed`, a checkpoint at stage "registration"), then fused at the registered poses.
int registeredRun(const RunSettings& s, MPI_Comm comm, Progress& progress,
                  const io::CheckpointMeta* resumed) {
  LoadedScans scans;
  if (!loadScans(s.read, comm, progress, scans)) return 1;
  RegistrationProgress state;
  if (resumed && !collectively(comm, [&] {
        checkScanHashes(*resumed, scans, hashScans(scans.paths, comm));
        scans.poses = resumed->poses;
        state = RegistrationProgress::fromJson(resumed->progress.at("registration"));
      }))
    return 1;
  if (resumed)
    progress.stage("resume", s.outputs.resume + ": registration " + toString(state.phase) +
                                 ", scan " + std::to_string(state.nextScan) + ", round " +
                                 std::to_string(state.round) + " iteration " +
                                 std::to_string(state.iteration));
  std::vector<RegistrationStep> steps;
  if (!registerPoses(s.registration, s.field, s.checkpoints(), s.outputs.resume, comm, progress,
                     scans, state, steps))
    return 1;
  // The final field streams the scans again at the registered poses: registration keeps only
  // each rank's own share, and the field is the same bits as one built from held scans.
  const std::vector<Pose> registered = scans.poses;
  scans.held.reset();
  FusedField field;
  RankCounters counters;
  if (!buildStreamed(s.read, s.field, comm, progress, scans, field, counters, &registered, nullptr,
                     storageWarner(s, comm)) ||
      !writeFieldCheckpoint(s.checkpoints(), comm, progress, scans, field) ||
      !writeTrajectoryFile(s.outputs.trajectoryOut, scans, {}, comm))
    return 1;
  return finish(s, comm, progress, scans, field, counters, steps);
}

/// The run a checkpoint continues, by the stage it was written at.
int resumedRun(const RunSettings& s, const io::CheckpointMeta& meta, MPI_Comm comm,
               Progress& progress) {
  const std::string stage = meta.progress.value("stage", "");
  if (stage == "field") return resumeFromField(s, meta, comm, progress);
  if (stage == "tracking") return internal::runTracking(s, comm, progress, &meta);
  if (stage == "registration") return registeredRun(s, comm, progress, &meta);
  collectively(comm,
               [&] { throw InputError(s.outputs.resume + ": unknown stage '" + stage + "'"); });
  return 1;
}

}  // namespace

int runFuse(const FuseOptions& given, MPI_Comm comm) {
  memoryLedger().start();
  Progress progress(comm, given.quiet     ? Verbosity::quiet
                          : given.verbose ? Verbosity::verbose
                                          : Verbosity::normal);
  FuseOptions options = given;
  io::CheckpointMeta resumed;
  if (!settle(options, comm, resumed)) return 1;
  const RunSettings s = runSettings(options);
  if (!collectively(comm, [&] { checkOutputs(s, mpi::rank(comm)); })) return 1;
  if (!s.outputs.resume.empty()) return resumedRun(s, resumed, comm, progress);
  bool tracking = false;
  if (!internal::decideTracking(s.read, s.track, comm, tracking)) return 1;
  if (tracking) return internal::runTracking(s, comm, progress);
  if (s.registration.mode == RegistrationMode::None) return streamedRun(s, comm, progress);
  return registeredRun(s, comm, progress, nullptr);
}

}  // namespace rangefuse
