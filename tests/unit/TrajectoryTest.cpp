// Camera trajectories: TUM and .log files written and read back exactly, ATE against hand-computed
// cases (a rigidly moved copy has none; a saddle of offsets no rigid motion removes keeps all),
// RPE of a steady drift, and the constant-velocity prediction of the tracker.
#include <gtest/gtest.h>

#include <iomanip>
#include <sstream>

#include "TempDir.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/eval/TrajectoryError.h"
#include "rangefuse/io/Trajectory.h"
#include "rangefuse/register/Tracking.h"

using namespace rangefuse;
using test::TempDir;

namespace {

Pose turn(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  return Pose{Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(), t};
}

std::vector<io::TimedPose> path(int n) {
  std::vector<io::TimedPose> out;
  for (int k = 0; k < n; ++k)
    out.push_back({1000 + 0.25 * k, turn(0.1 * k, Eigen::Vector3d(1, 2, 3),
                                         Eigen::Vector3d(std::cos(k), 0.3 * k, std::sin(k)))});
  return out;
}

}  // namespace

TEST(Trajectory, TumAndLogFilesRoundTrip) {
  TempDir dir;
  const auto written = path(7);
  for (const char* name : {"t.txt", "t.log"}) {
    io::writeTrajectory(dir.file(name), written);
    const auto read = io::readTrajectory(dir.file(name));
    ASSERT_EQ(read.size(), written.size()) << name;
    for (size_t k = 0; k < read.size(); ++k) {
      EXPECT_LT((read[k].cameraToWorld.R - written[k].cameraToWorld.R).norm(), 1e-14) << name;
      EXPECT_LT((read[k].cameraToWorld.t - written[k].cameraToWorld.t).norm(), 1e-14) << name;
      // A .log has no times: frame k is taken at k / 30 s, as a Redwood sequence's frames are.
      EXPECT_DOUBLE_EQ(read[k].time,
                       io::isLogTrajectory(name) ? k / io::kRedwoodFrameRate : written[k].time)
          << name;
    }
  }
}

TEST(Trajectory, BadFilesNameTheFileAndLine) {
  TempDir dir;
  dir.write("a.txt", "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  EXPECT_THROW(
      {
        try {
          io::readTrajectory(dir.file("a.txt"));
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("a.txt: line 2: timestamps out of order"),
                    std::string::npos);
          throw;
        }
      },
      InputError);
  // A mirror is named as one, not as a matrix off a rotation.
  dir.write("m.log", "0 0 1\n-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  try {
    io::readTrajectory(dir.file("m.log"));
    ADD_FAILURE() << "a reflection was read as a pose";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m.log: line 2: the matrix is a reflection"),
              std::string::npos)
        << e.what();
  }
  dir.write("b.txt", "# nothing\n");
  EXPECT_THROW(io::readTrajectory(dir.file("b.txt")), InputError);
  EXPECT_THROW(io::readTrajectory(dir.file("missing.txt")), InputError);
}

TEST(TrajectoryError, ARigidlyMovedCopyHasNoError) {
  const auto reference = path(12);
  const Pose move = turn(0.7, Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(5, -2, 1));
  auto estimate = reference;
  for (auto& p : estimate)
    p.cameraToWorld = Pose{move.R * p.cameraToWorld.R, move.apply(p.cameraToWorld.t)};
  const TrajectoryError e = compareTrajectories(estimate, reference);
  EXPECT_EQ(e.matched, 12u);
  EXPECT_LT(e.ateRmse, 1e-12);
  EXPECT_LT(e.rpeTranslationRmse, 1e-12);
  EXPECT_LT(e.rpeRotationRmseDeg, 1e-5);
}

TEST(TrajectoryError, ASaddleOfOffsetsIsItsOwnError) {
  // Offsets +e, -e, -e, +e across the corners of a square are orthogonal to every motion a
  // rigid alignment makes to first order: the ATE is e, by hand.
  const double e = 0.01;
  const Eigen::Vector3d corners[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const double sign[4] = {1, -1, -1, 1};
  std::vector<io::TimedPose> reference, estimate;
  for (int k = 0; k < 4; ++k) {
    reference.push_back({double(k), Pose{Eigen::Matrix3d::Identity(), corners[k]}});
    estimate.push_back({double(k), Pose{Eigen::Matrix3d::Identity(),
                                        corners[k] + sign[k] * e * Eigen::Vector3d::UnitZ()}});
  }
  const TrajectoryError err = compareTrajectories(estimate, reference);
  EXPECT_NEAR(err.ateRmse, e, 1e-6);
  EXPECT_NEAR(err.ateMax, e, 1e-6);
}

TEST(TrajectoryError, ASteadyDriftIsItsRelativeError) {
  // The estimate drifts by v a second: every pair a second apart is off by |v|.
  const Eigen::Vector3d v(0.003, -0.004, 0);
  auto reference = path(20), estimate = path(20);
  for (auto& p : reference) p.cameraToWorld.R.setIdentity();
  for (auto& p : estimate) p.cameraToWorld.R.setIdentity();
  for (auto& p : estimate) p.cameraToWorld.t += (p.time - 1000) * v;
  const TrajectoryError e = compareTrajectories(estimate, reference);
  EXPECT_EQ(e.rpePairs, 16u);  // times 0.25 s apart: pairs (k, k + 4)
  EXPECT_NEAR(e.rpeTranslationRmse, v.norm(), 1e-12);
  EXPECT_THROW(compareTrajectories(estimate, {reference[0]}), InputError);
}

TEST(TrajectoryError, OneTrajectoryAsTumAndAsLogMatchesEveryPose) {
  // The same poses written as TUM with a run's frame times (k / 30 s) and as a .log: read back,
  // every pose matches by time and the error is nil.
  TempDir dir;
  std::vector<io::TimedPose> run = path(99);
  for (size_t k = 0; k < run.size(); ++k) run[k].time = k / io::kRedwoodFrameRate;
  io::writeTrajectory(dir.file("rs.txt"), run);
  io::writeTrajectory(dir.file("rs.log"), run);
  const TrajectoryError e = compareTrajectories(io::readTrajectory(dir.file("rs.txt")),
                                                io::readTrajectory(dir.file("rs.log")));
  EXPECT_EQ(e.matching, PoseMatching::byTime);
  EXPECT_EQ(e.matched, 99u);
  EXPECT_LT(e.ateRmse, 1e-9);
  // RPE over a second takes pairs 30 frames apart, not 1 frame apart: 99 - 30 pairs.
  EXPECT_NEAR(static_cast<double>(e.rpePairs), 69, 1);
}

TEST(Trajectory, ALogRoundedToFewDigitsReadsAsRotations) {
  // KinectFusion's poses (the 7-Scenes kitchen) give R to about 1e-4: read as the nearest
  // rotation, the same poses written as TUM compare with the .log at no error, angles included.
  TempDir dir;
  std::vector<io::TimedPose> run = path(60);
  std::ostringstream rounded;
  rounded << std::fixed << std::setprecision(4);
  for (size_t k = 0; k < run.size(); ++k) {
    run[k].time = k / io::kRedwoodFrameRate;
    rounded << k << ' ' << k << ' ' << k + 1 << '\n';
    const Pose& p = run[k].cameraToWorld;
    for (int r = 0; r < 3; ++r)
      rounded << p.R(r, 0) << ' ' << p.R(r, 1) << ' ' << p.R(r, 2) << ' ' << p.t(r) << '\n';
    rounded << "0 0 0 1\n";
  }
  dir.write("kf.log", rounded.str());
  const auto log = io::readTrajectory(dir.file("kf.log"));
  for (const auto& p : log)
    EXPECT_TRUE((p.cameraToWorld.R.transpose() * p.cameraToWorld.R).isIdentity(1e-12));
  io::writeTrajectory(dir.file("kf.txt"), log);
  const TrajectoryError e = compareTrajectories(io::readTrajectory(dir.file("kf.txt")), log);
  EXPECT_EQ(e.matched, 60u);
  EXPECT_LT(e.ateRmse, 1e-9);
  EXPECT_LT(e.rpeRotationRmseDeg, 1e-3);
}

TEST(TrajectoryError, ByIndexPairsPosesOfTheSameNumberAndHalfMustMatch) {
  // Real timestamps against a .log's frame numbers: nothing matches in time, all by index.
  const auto tum = path(10);
  auto log = tum;
  for (size_t k = 0; k < log.size(); ++k) log[k].time = k / io::kRedwoodFrameRate;
  EXPECT_THROW(compareTrajectories(tum, log), InputError);
  const TrajectoryError e = compareTrajectories(tum, log, 0.02, 1.0, PoseMatching::byIndex);
  EXPECT_EQ(e.matched, 10u);
  EXPECT_LT(e.ateRmse, 1e-12);
  // Fewer than half of the estimate's poses with a partner is refused, not reported on 4.
  std::vector<io::TimedPose> short4(log.begin(), log.begin() + 4);
  EXPECT_THROW(compareTrajectories(tum, short4, 0.02, 1.0, PoseMatching::byIndex), InputError);
}

TEST(Tracking, PredictionContinuesTheLastMotionOrFollowsTheGuide) {
  const Pose a = turn(0.2, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 0));
  const Pose step = turn(0.05, Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(0.1, 0, 0));
  const Pose b{a.R * step.R, a.R * step.t + a.t};
  const Pose c{b.R * step.R, b.R * step.t + b.t};
  std::vector<Pose> poses = {a, b, Pose{}, Pose{}};
  const Pose p = predictPose(poses, nullptr, 0, 1, 2);
  EXPECT_LT((p.R - c.R).norm(), 1e-12);
  EXPECT_LT((p.t - c.t).norm(), 1e-12);
  // Over two intervals (a frame dropped), twice the motion; by frame times, the same.
  const Pose d{c.R * step.R, c.R * step.t + c.t};
  const Pose q = predictPose(poses, nullptr, 0, 1, 3);
  EXPECT_LT((q.R - d.R).norm(), 1e-12);
  EXPECT_LT((q.t - d.t).norm(), 1e-12);
  const Pose r = predictPose(poses, nullptr, 0, 1, 3, {0.0, 0.5, 0.75, 1.5});
  EXPECT_LT((r.t - d.t).norm(), 1e-12);
  // No earlier frame: the last pose stands.
  EXPECT_LT((predictPose(poses, nullptr, -1, 1, 2).t - b.t).norm(), 1e-15);
  // A guide's relative motion is applied to where the tracker put the last frame.
  const std::vector<Pose> guide = {Pose{}, Pose{}, step};
  const Pose g = predictPose(poses, &guide, 0, 1, 2);
  EXPECT_LT((g.t - c.t).norm(), 1e-12);
}
