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
  /// Takes one frame's outcome, named `name` (its file).
  void add(const FrameReport& report, const std::string& name);

  /// {"frames", "fused", "lost", "recovered", "lost_frames": [{"frame", "name", "why"}],
  /// "inliers": {"min", "median"}, "rms_residual": {"median", "max"}} (residuals in world
  /// units), over the frames taken.
  nlohmann::json toJson() const;

 private:
  size_t frames_ = 0, recovered_ = 0;
  nlohmann::json lost_ = nlohmann::json::array();
  std::vector<double> inliers_, rms_;  ///< of the fused frames
};

}  // namespace rangefuse
