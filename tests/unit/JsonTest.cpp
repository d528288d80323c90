// io/Json.h: poses as checkpoints keep them, bit for bit, and refused when they are not poses.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <stdexcept>

#include "rangefuse/io/Json.h"

namespace rangefuse {
namespace {

TEST(Json, PoseNumbersReadBackBitForBit) {
  Pose p;
  p.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  p.t = Eigen::Vector3d(0.1, -1e-17, 12345.678901234567);
  const nlohmann::json j = io::poseNumbers(p);
  ASSERT_EQ(j.size(), 12u);
  EXPECT_EQ(j[1].get<double>(), p.R(1, 0));  // column by column
  const Pose back = io::poseFromNumbers(nlohmann::json::parse(j.dump()));
  EXPECT_EQ(back.R, p.R);
  EXPECT_EQ(back.t, p.t);
}

TEST(Json, PoseFromNumbersRefusesWhatIsNotAPose) {
  nlohmann::json j = io::poseNumbers(Pose{});
  j.erase(11);
  EXPECT_THROW(io::poseFromNumbers(j), std::runtime_error);
  j = io::poseNumbers(Pose{});
  j[0] = 2.0;  // a scaling, not a rotation
  EXPECT_THROW(io::poseFromNumbers(j), std::runtime_error);
  j = io::poseNumbers(Pose{});
  j[10] = std::nan("");
  EXPECT_THROW(io::poseFromNumbers(j), std::runtime_error);
  EXPECT_THROW(io::poseFromNumbers(nlohmann::json("pose")), std::exception);
}

}  // namespace
}  // namespace rangefuse
