// A tracked stream's summary for the run report against hand-counted answers: fused and lost
// frames, the inlier shares and residuals of the fused ones, and the frames' times (mean, 95th
// percentile by nearest rank, maximum).
#include <gtest/gtest.h>

#include "rangefuse/pipeline/TrackingSummary.h"

using namespace rangefuse;

TEST(TrackingSummary, CountsFramesAndTheirTimes) {
  TrackingSummary summary;
  for (size_t i = 0; i < 20; ++i) {
    FrameReport r;
    r.frame = i;
    r.fused = i != 7;
    r.why = r.fused ? "" : "turned 20 deg since the last frame";
    r.inliers = 0.5 + 0.01 * static_cast<double>(i);
    r.rms = 0.001 * static_cast<double>(i + 1);
    summary.add(r, "f" + std::to_string(i), 0.1 * static_cast<double>(i + 1));  // 0.1 .. 2.0 s
  }
  const nlohmann::json j = summary.toJson();
  EXPECT_EQ(j["frames"], 20);
  EXPECT_EQ(j["fused"], 19);
  EXPECT_EQ(j["lost"], 1);
  EXPECT_EQ(j["lost_frames"][0]["name"], "f7");
  EXPECT_DOUBLE_EQ(j["inliers"]["min"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["rms_residual"]["max"].get<double>(), 0.020);
  EXPECT_NEAR(j["frame_seconds"]["mean"].get<double>(), 1.05, 1e-12);
  EXPECT_NEAR(j["frame_seconds"]["p95"].get<double>(), 1.9, 1e-12);  // the 19th of 20
  EXPECT_NEAR(j["frame_seconds"]["max"].get<double>(), 2.0, 1e-12);
  EXPECT_NE(summary.frameTimes().find("95th percentile 1.900 s (1.8 times the mean)"),
            std::string::npos)
      << summary.frameTimes();
}
