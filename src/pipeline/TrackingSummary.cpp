#include "rangefuse/pipeline/TrackingSummary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace rangefuse {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The q-quantile (nearest rank) of v, 0 when empty.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

void TrackingSummary::add(const FrameReport& r, const std::string& name, double seconds) {
  ++frames_;
  seconds_.push_back(seconds);
  recovered_ += r.recovered;
  if (!r.fused) {
    lost_.push_back({{"frame", r.frame}, {"name", name}, {"why", r.why}});
    return;
  }
  inliers_.push_back(r.inliers);
  rms_.push_back(r.rms);
}

void TrackingSummary::setLoops(size_t keyFrames, size_t measured, size_t closed, double seconds) {
  loops_ = {
      {"key_frames", keyFrames}, {"measured", measured}, {"closed", closed}, {"seconds", seconds}};
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
            {"max", rms_.empty() ? 0.0 : *std::max_element(rms_.begin(), rms_.end())}}},
          {"frame_seconds",
           {{"mean", mean(seconds_)},
            {"p95", quantile(seconds_, 0.95)},
            {"max", seconds_.empty() ? 0.0 : *std::max_element(seconds_.begin(), seconds_.end())}}},
          {"loops", loops_}};
}

std::string TrackingSummary::frameTimes() const {
  const double m = mean(seconds_), p95 = quantile(seconds_, 0.95);
  char text[120];
  std::snprintf(text, sizeof text,
                "a frame in %.3f s, 95th percentile %.3f s (%.1f times the mean)", m, p95,
                m > 0 ? p95 / m : 0.0);
  return text;
}

}  // namespace rangefuse
