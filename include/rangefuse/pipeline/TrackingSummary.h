// What a tracked depth stream's frames came to, for the run report: how many were fused, which
// were lost and why, and how well the fused ones fitted the field.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rangefuse/register/Tracking.h"

namespace rangefuse {

class TrackingSummary {
 public:
  /// Takes one frame's outcome, named `name` (its file), which took `seconds` from the last
  /// frame's outcome (reading, fitting and adding it).
  void add(const FrameReport& report, const std::string& name, double seconds = 0);

  /// The stream's key frames, the loops measured between them, those that moved the poses
  /// (closed) and the seconds spent fitting and solving them.
  void setLoops(size_t keyFrames, size_t measured, size_t closed, double seconds);

  /// {"frames", "fused", "lost", "recovered", "lost_frames": [{"frame", "name", "why"}],
  /// "inliers": {"min", "median"}, "rms_residual": {"median", "max"}, "frame_seconds":
  /// {"mean", "p95", "max"}, "loops": {"key_frames", "measured", "closed", "seconds"}}
  /// (residuals in world units), over the frames taken.
  nlohmann::json toJson() const;

  /// "mean 0.17 s, 95th percentile 0.25 s (1.5 times the mean)": how even the frames' times
  /// are, which an interactive stream needs as much as their mean.
  std::string frameTimes() const;

 private:
  size_t frames_ = 0, recovered_ = 0;
  nlohmann::json lost_ = nlohmann::json::array();
  std::vector<double> inliers_, rms_;  ///< of the fused frames
  std::vector<double> seconds_;        ///< of every frame
  nlohmann::json loops_ = {{"key_frames", 0}, {"measured", 0}, {"closed", 0}, {"seconds", 0.0}};
};

}  // namespace rangefuse
