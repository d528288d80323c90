// The library's tracked frames (private to the fuse stage): a depth stream handed over frame by
// frame, each tracked against the field of those before it and fused into it, as the command
// tracks a folder (TrackStage), kept alive between the caller's calls.
#pragma once

#include <mpi.h>

#include <memory>

#include "rangefuse/core/MeshPart.h"
#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"
#include "rangefuse/register/Tracking.h"
#include "rangefuse/track/PixelMotion.h"
#include "rangefuse/track/TrackingField.h"

namespace rangefuse::internal {

class TrackedFrames {
 public:
  /// `read.list` holds the frames: each is appended there before it is tracked.
  TrackedFrames(const ReadSettings& read, const FieldSettings& field, ColourKind colour,
                MPI_Comm comm);
  ~TrackedFrames();

  /// Collective: tracks the list's last frame (the first fixes the world frame at the identity
  /// camera) and fuses it when the fit holds. Throws mpi::Reported on every rank when the
  /// stream is given up (the reason in failure()) or a stage failed.
  FrameReport track();

  /// Why the stream was given up.
  const std::string& failure() const { return state_.failure; }
  /// Each frame's scan pose (a lost frame keeps the last good one) and whether it was lost.
  const std::vector<Pose>& poses() const { return scans_.poses; }
  const std::vector<char>& lost() const { return state_.lost; }
  /// The tracking field as it stands (valid until the next frame).
  const BrickStore& store() const { return tracked_->store(); }
  /// Lets go of frame i's images (the caller drops its own hold on them too): a frame neither
  /// fused last nor being tracked is not read again.
  void forget(size_t i) { scans_.held->dropMemory(i); }
  /// Collective: this rank's part of the tracking field's mesh.
  MeshPart meshPart(int threads);

 private:
  void open(const io::ConfScan& first);
  void append(const io::ConfScan& next);

  ReadSettings read_;
  FieldSettings field_;
  MPI_Comm comm_;
  LoadedScans scans_;
  TrackerSettings settings_;
  TrackingState state_;
  StreamCalls calls_;
  FrameReport last_;
  std::unique_ptr<TrackingField> tracked_;
  std::unique_ptr<PixelMotion> pixels_;
  std::unique_ptr<FrameTracker> tracker_;
};

}  // namespace rangefuse::internal
