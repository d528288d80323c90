#include "rangefuse/pipeline/TrackingSummary.h"

#include <algorithm>

namespace rangefuse {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

void TrackingSummary::add(const FrameReport& r, const std::string& name) {
  ++frames_;
  recovered_ += r.recovered;
  if (!r.fused) {
    lost_.push_back({{"frame", r.frame}, {"name", name}, {"why", r.why}});
    return;
  }
  inliers_.push_back(r.inliers);
  rms_.push_back(r.rms);
}

nlohmann::json TrackingSummary::toJson() const {
  const auto [least, most] = std::minmax_element(inliers_.begin(), inliers_.end());
  return {{"frames", frames_},
          {"fused", inliers_.size()},
          {"lost", lost_.size()},
          {"recovered", recovered_},
          {"lost_frames", lost_},
          {"inliers", {{"min", inliers_.empty() ? 0.0 : *least}, {"median", median(inliers_)}}},
          {"rms_residual",
           {{"median", median(rms_)},
            {"max", rms_.empty() ? 0.0 : *std::max_element(rms_.begin(), rms_.end())}}}};
}

}  // namespace rangefuse
