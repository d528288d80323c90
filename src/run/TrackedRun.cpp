#include "TrackedRun.h"

#include "rangefuse/core/Error.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/FieldBuild.h"
#include "rangefuse/pipeline/FinishRun.h"
#include "rangefuse/pipeline/RegisterStage.h"
#include "rangefuse/track/TrackStage.h"

namespace rangefuse::internal {
namespace {

using mpi::collectively;

/// Algorithm 2 after the stream: the tracked frames (lost ones left out) registered together
/// against the field of all of them, then fused again at the refined poses.
int refineTracked(const RunSettings& s, MPI_Comm comm, Progress& progress,
                  const std::vector<Pose>& tracked, const std::vector<char>& lost) {
  LoadedScans scans;
  if (!loadScans(s.read, comm, progress, scans, &tracked, &lost)) return 1;
  RegistrationProgress state;
  std::vector<RegistrationStep> steps;
  if (!registerPoses(s.registration, s.field, s.checkpoints(), s.outputs.resume, comm, progress,
                     scans, state, steps) ||
      !writeTrajectoryFile(s.outputs.trajectoryOut, scans, {}, comm))
    return 1;
  // Back to one pose per frame of the list, for the final field that reads the list again.
  std::vector<Pose> refined = tracked;
  for (size_t i = 0, k = 0; i < refined.size(); ++i)
    if (!lost[i]) refined[i] = scans.poses[k++];
  scans.held.reset();
  FusedField field;
  RankCounters counters;
  if (!buildStreamed(s.read, s.field, comm, progress, scans, field, counters, &refined, &lost,
                     storageWarner(s, comm)) ||
      !writeFieldCheckpoint(s.checkpoints(), comm, progress, scans, field))
    return 1;
  return finish(s, comm, progress, scans, field, counters, steps);
}

/// Throws InputError when the run asks what a tracked stream cannot do.
void checkTrackable(const RunSettings& s) {
  const RegistrationMode mode = s.registration.mode;
  if (mode != RegistrationMode::None && mode != RegistrationMode::Simultaneous)
    throw InputError("--register " + std::string(toString(mode)) +
                     ": tracked frames are registered as they arrive (Algorithm 1); after "
                     "the stream only --register simultaneous refines them");
  if (s.mesh.fillHoles && mode != RegistrationMode::Simultaneous)
    throw InputError(
        "--fill-holes: a tracked stream is fused as its frames arrive, with no sight maps to "
        "carve with; add --register simultaneous (the frames are then fused again) or give the "
        "stream's trajectory");
  if (mode == RegistrationMode::Simultaneous && !s.outputs.checkpoint.empty())
    throw InputError(
        "--checkpoint: a tracked stream refined by --register simultaneous "
        "cannot be checkpointed yet");
}

}  // namespace

bool decideTracking(const ReadSettings& read, const StreamSettings& track, MPI_Comm comm,
                    bool& tracking) {
  return collectively(comm, [&] {
    if (track.follow) {  // the folder may hold no frames yet
      if (track.track == "off")
        throw InputError("--follow tracks a stream while it is recorded: leave out --track off");
      tracking = true;
      return;
    }
    const io::ConfFile conf = io::readScanList(read.scans, read.limits, read.source);
    tracking = tracksFrames(track.track, conf.posed, read.scans);
  });
}

int runTracking(const RunSettings& s, MPI_Comm comm, Progress& progress,
                const io::CheckpointMeta* resumed) {
  if (!collectively(comm, [&] { checkTrackable(s); })) return 1;
  LoadedScans scans;
  std::vector<char> lost;
  FusedField field;
  RankCounters counters;
  if (!openStream(s, comm, progress, scans) ||
      !trackStream(s, comm, progress, scans, lost, field, counters, resumed))
    return 1;
  if (s.registration.mode == RegistrationMode::Simultaneous) {
    const std::vector<Pose> tracked = scans.poses;
    scans.held.reset();
    field = FusedField{};
    return refineTracked(s, comm, progress, tracked, lost);
  }
  if (!writeTrajectoryFile(s.outputs.trajectoryOut, scans, lost, comm)) return 1;
  // The tracking field is a prism field; other methods fuse the tracked frames again.
  if (s.field.method != FieldMethod::Prism) {
    const std::vector<Pose> tracked = scans.poses;
    scans.held.reset();
    const std::optional<TrackingSummary> summary = std::move(field.tracking);
    field = FusedField{};
    field.tracking = summary;  // the report's tracking figures are the stream's
    if (!buildStreamed(s.read, s.field, comm, progress, scans, field, counters, &tracked, &lost,
                       storageWarner(s, comm)))
      return 1;
  }
  if (!writeFieldCheckpoint(s.checkpoints(), comm, progress, scans, field)) return 1;
  return finish(s, comm, progress, scans, field, counters, {});
}

}  // namespace rangefuse::internal
