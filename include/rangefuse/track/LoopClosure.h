// Drift closed while a stream is tracked: key frames kept as the camera moves, and when it
// comes back to where an earlier key frame saw the scene the two are fitted to each other (a
// loop), the key frames' poses are made to agree with every motion measured between them (a
// pose graph) and each frame follows its key frame. The field is then built again at the
// corrected poses, and tracking goes on against it.
#pragma once

#include <mpi.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "rangefuse/core/Pose.h"
#include "rangefuse/register/ScanSource.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse {
namespace internal {
class KeyFrames;
}

/// When a frame becomes a key frame and when two key frames close a loop (lengths in voxels).
struct LoopSettings {
  bool enabled = true;
  double voxel = 0;
  double eps = 0;  ///< the prism envelope: key frames are moved onto the field within it
  /// A fused frame becomes a key frame once the camera moved this share of the last key
  /// frame's median range, or turned this far, since it.
  double keyStepShare = 0.1, keyTurnDeg = 10;
  size_t keyPoints = 3000;    ///< at most this many points kept per key frame
  size_t minLoopFrames = 90;  ///< a loop spans at least this many frames (3 s at 30 frames/s)
  /// Key frames are fitted with correspondences from this far (the drift a loop may close)
  /// down to the end radius, residuals beyond one voxel weighing less.
  double startVoxels = 10, endVoxels = 3;
  double minInliers = 0.3;  ///< share of a key frame's points that must meet the other's
  /// A loop that moves a key frame less than this is left as it is: a loop between key frames
  /// is a few voxels uncertain, and one closed at half a voxel gains nothing (docs/tracking.md).
  double closeVoxels = 2;
  /// While the stream runs, a loop is closed (the field built again) only when it moves a key
  /// frame by this much and no loop was closed in the last closeEvery frames; the others are
  /// kept and closed when the stream ends. Closing every loop at once is what holds tracking
  /// where it comes back (docs/tracking.md), at the cost of fusing the frames again.
  double trackVoxels = 2;
  size_t closeEvery = 0;
};

/// Key frames and the loops between them, for one stream. Every call is collective and leaves
/// every rank with the same poses.
class LoopClosure {
 public:
  LoopClosure(const LoopSettings& settings, const ScanSource& frames, MPI_Comm comm);
  ~LoopClosure();
  LoopClosure(const LoopClosure&) = delete;
  LoopClosure& operator=(const LoopClosure&) = delete;

  /// Frame i was just fused at poses[i] into `field` (its reader still holds it). True when it
  /// closed a loop and moved the poses of frames 0..i: the field must be built again at them.
  bool fused(size_t i, std::vector<Pose>& poses, const BrickStore& field);

  /// The stream has ended: true when the loops measured since the last closure move the
  /// poses by closeVoxels or more (they were then moved: the field must be built again).
  bool finish(std::vector<Pose>& poses);

  /// The key frames and measured motions, for a checkpoint.
  nlohmann::json state() const;
  /// Takes them back from a checkpoint (the key frames are read again). Throws InputError
  /// naming `where` when the state does not fit the stream.
  void restore(const nlohmann::json& state, const std::string& where);

  size_t keyFrames() const;
  size_t loops() const;     ///< loops measured
  size_t closures() const;  ///< loops that moved the poses
  double seconds() const;   ///< time spent fitting and solving, not rebuilding

 private:
  std::unique_ptr<internal::KeyFrames> keys_;
};

}  // namespace rangefuse
