#include "rangefuse/track/TrackedFrames.h"

#include "rangefuse/core/Error.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/pipeline/HeldScans.h"
#include "rangefuse/track/TrackStage.h"

namespace rangefuse::internal {
TrackedFrames::TrackedFrames(const ReadSettings& read, const FieldSettings& field,
                             ColourKind colour, MPI_Comm comm)
    : read_(read), field_(field), comm_(comm) {
  scans_.rank = mpi::rank(comm);
  scans_.posed = false;
  scans_.colour = colour;
  StreamSettings track;
  track.skipLost = true;  // a caller's stream goes on past a frame that did not fit
  settings_ = trackingSettings(track, 1, field.voxel, field.eps());
  calls_.frame = [this](size_t i, bool done) {
    if (done) return scans_.held->release(i);
    mpi::collectivelyOrThrow(comm_, [&] {
      if (scans_.holds(i)) scans_.held->readAndOffer(i);
    });
  };
  calls_.motion = [this](size_t last, size_t next, const Pose& guess) {
    return (*pixels_)(last, next, guess);
  };
  calls_.onFrame = [this](const FrameReport& r) { last_ = r; };
  calls_.onBoundary = [](const TrackingState&) {};
}

TrackedFrames::~TrackedFrames() = default;

void TrackedFrames::open(const io::ConfScan& first) {
  scans_.names = {first.name}, scans_.paths = {first.path}, scans_.times = {first.time};
  scans_.readers = {0};
  scans_.poses = {io::scanPose(Pose{})};
  scans_.held = heldScans({first}, scans_.readers, scans_.rank, read_);
  const TrackingLattice f{field_.voxel,     field_.brick,   field_.eps(),
                          field_.maxVoxels, field_.threads, scans_.colour};
  tracked_ = std::make_unique<TrackingField>(f, scans_, comm_);
  mpi::collectivelyOrThrow(
      comm_, [&] { pixels_ = std::make_unique<PixelMotion>(read_, field_.voxel, comm_); });
  tracker_ = std::make_unique<FrameTracker>(*scans_.held, scans_.poses, scans_.times, nullptr,
                                            settings_, *tracked_, comm_, state_, calls_);
}

void TrackedFrames::append(const io::ConfScan& next) {
  const size_t i = scans_.names.size();
  const int reader = static_cast<int>(i % static_cast<size_t>(mpi::size(comm_)));
  scans_.names.push_back(next.name), scans_.paths.push_back(next.path);
  scans_.times.push_back(next.time);
  scans_.readers.push_back(reader);
  scans_.held->append({next}, {reader});
  tracker_->grew();
}

FrameReport TrackedFrames::track() {
  const io::ConfScan& frame = read_.list->scans.back();
  const bool first = !tracker_;
  if (first)
    open(frame);
  else
    append(frame);
  if (!(first ? tracker_->start() : tracker_->next())) throw mpi::Reported();
  return last_;
}

MeshPart TrackedFrames::meshPart(int threads) {
  return extractDistributedMesh(tracked_->store(), 0, comm_, nullptr, threads);
}

}  // namespace rangefuse::internal
