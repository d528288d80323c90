#include "rangefuse/options/StreamSettings.h"

#include <cmath>

namespace rangefuse {
namespace {

using Stream = StreamSettings;

std::vector<Setting<Stream>> streamTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"track", "track", R::Result, false, G::Tracking,
       "depth streams: track every frame against the field of the frames before it (on), use "
       "the given trajectory (off), or track only when there is none (auto); with a trajectory, "
       "tracking takes its motion as each frame's first guess",
       at(&Stream::track),
       [](const Stream& s) {
         return s.track == "on" || s.track == "off" || s.track == "auto"
                    ? ""
                    : "must be on, off or auto";
       },
       "on"},
      {"first-pose", "first_pose", R::Result, false, G::Tracking,
       "tracking: the first camera's pose in the world, 'tx,ty,tz,qx,qy,qz,qw' (camera to "
       "world, as TUM writes it; default: the identity)",
       at(&Stream::firstPose), nullptr},
      {"min-inliers", "min_inliers", R::Result, false, G::Tracking,
       "tracking: a frame is lost when fewer of its points than this share find the field",
       at(&Stream::minInliers),
       must<Stream, double>(
           &Stream::minInliers, [](double v) { return v >= 0 && v <= 1; },
           "must be a share in [0, 1]")},
      {"max-step", "max_step_voxels", R::Result, false, G::Tracking,
       "tracking: a frame is lost when its fit puts the camera more than this many voxels from "
       "where its motion so far predicted (a slide along a wall, not a motion)",
       at(&Stream::maxStep),
       must<Stream, double>(
           &Stream::maxStep, [](double v) { return v > 0; }, "must be positive voxels")},
      {"skip-lost", "skip_lost", R::Result, false, G::Tracking,
       "tracking: leave frames that lose tracking out, report them and go on; false: the run "
       "stops at the first with an error",
       at(&Stream::skipLost), nullptr, "true"},
      {"close-loops", "close_loops", R::Result, false, G::Tracking,
       "tracking: keep key frames as the camera moves and, when it comes back to where one saw "
       "the scene, fit the two, correct the poses of every frame so far and fuse them again "
       "(each closure costs about what fusing the frames so far did; docs/tracking.md)",
       at(&Stream::closeLoops), nullptr, "true"},
      {"preview-every", "", R::No, false, G::Tracking,
       "tracking: every N frames, write --preview as the partial model seen from the current "
       "camera (the last picture is the finished field's)",
       at(&Stream::previewEvery),
       must<Stream, int>(
           &Stream::previewEvery, [](int v) { return v >= 0; },
           "must be a number of frames >= 0 (0: never)")},
      {"follow", "", R::No, false, G::Tracking,
       "tracking: the folder is still being recorded: frames that appear in it join the stream "
       "until a file named STOP appears there or --follow-timeout passes with no new frame",
       at(&Stream::follow), nullptr, "true"},
      {"follow-timeout", "", R::No, false, G::Tracking,
       "tracking: with --follow, seconds without a new frame after which the stream ends",
       at(&Stream::followTimeout),
       must<Stream, double>(
           &Stream::followTimeout, [](double v) { return v > 0 && std::isfinite(v); },
           "must be a positive number of seconds")}};
}

}  // namespace

const std::vector<Setting<StreamSettings>>& StreamSettings::settings() {
  static const std::vector<Setting<StreamSettings>> table = streamTable();
  return table;
}

}  // namespace rangefuse
