// A depth stream's folder while it is still being recorded (--follow): frames that appear in
// it join the stream (private to the fuse stage).
#pragma once

#include <mpi.h>

#include <vector>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"

namespace rangefuse::internal {

/// Watches the scan list of --scans. Rank 0 decides how many frames the list holds and every
/// rank takes that many from its own reading, so all ranks agree on the stream whatever their
/// views of the file system. While recording goes on, the newest frame is left for the next
/// look (it may still be being written).
class FollowedFolder {
 public:
  /// The list `read` names, ending when nothing new appears for `timeout` seconds.
  FollowedFolder(const ReadSettings& read, double timeout, MPI_Comm comm);

  /// Collective: the list's first frames (at least two, or all once recording stopped),
  /// waiting for them; throws InputError when none came within --follow-timeout.
  io::ConfFile first();
  /// Collective: appends frames that joined the list since to `scans` (names, paths, times,
  /// readers, the held scans; not poses) and returns true, after waiting for them; false once
  /// recording has stopped (the stop file, or nothing new within --follow-timeout) and no frame
  /// is left.
  bool more(LoadedScans& scans);

 private:
  /// Rank 0 waits until the list holds more than `have` frames it may take, or recording
  /// stopped; every rank gets the count to take (0 on failure to read it at all).
  size_t waitForFrames(size_t have);

  ReadSettings o_;
  double timeout_;
  MPI_Comm comm_;
  size_t seen_ = 0;  ///< rank 0: the most frames the list has held
  double seenAt_;    ///< rank 0: when it first held that many
  bool stopped_ = false;
};

}  // namespace rangefuse::internal
