#include "rangefuse/io/Trajectory.h"

#include <Eigen/SVD>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "TextLines.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace rangefuse::io {
namespace {

using internal::dataLines;
using internal::numbers;

std::string at(const std::string& path, int line) {
  return internal::lineOf(path, line);
}

std::vector<TimedPose> readTum(const std::string& path) {
  std::vector<TimedPose> poses;
  int previousLine = 0;
  for (const auto& [n, text] : dataLines(path)) {
    const std::vector<double> v = numbers(text, 8, at(path, n), "'t tx ty tz qx qy qz qw'");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1) > 0.01)
      throw InputError(at(path, n) + ": quaternion is not of unit length");
    if (!poses.empty() && !(v[0] > poses.back().time))
      throw InputError(at(path, n) + ": timestamps out of order (" + std::to_string(v[0]) +
                       " after " + std::to_string(poses.back().time) + " on line " +
                       std::to_string(previousLine) + ")");
    poses.push_back(
        {v[0], Pose{q.normalized().toRotationMatrix(), Eigen::Vector3d(v[1], v[2], v[3])}});
    previousLine = n;
  }
  return poses;
}

std::vector<TimedPose> readLog(const std::string& path) {
  const auto lines = dataLines(path);
  if (lines.size() % 5 != 0)
    throw InputError(path + ": " + std::to_string(lines.size()) +
                     " lines: a trajectory has 5 per frame (three integers, then 4 rows of 4)");
  std::vector<TimedPose> poses;
  for (size_t k = 0; k < lines.size(); k += 5) {
    numbers(lines[k].second, 3, at(path, lines[k].first), "three integers");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      const auto row = numbers(lines[k + 1 + r].second, 4, at(path, lines[k + 1 + r].first),
                               "a matrix row of 4 numbers");
      for (int c = 0; c < 4; ++c) m(r, c) = row[c];
    }
    const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
    const std::string problem = rotationProblem(R);
    if (!problem.empty())
      throw InputError(at(path, lines[k + 1].first) + ": the matrix is " + problem +
                       ", not a rigid motion");
    // Rows rounded in the file (KinectFusion's, to about 1e-4) are read as the nearest
    // rotation, so that poses compare, compose and checkpoint as rotations.
    poses.push_back({static_cast<double>(poses.size()) / kRedwoodFrameRate,
                     rigidPose(Pose{R, m.topRightCorner<3, 1>()}, at(path, lines[k + 1].first))});
  }
  return poses;
}

}  // namespace

bool isLogTrajectory(const std::string& path) {
  return std::filesystem::path(path).extension() == ".log";
}

std::vector<TimedPose> readTrajectory(const std::string& path) {
  std::vector<TimedPose> poses = isLogTrajectory(path) ? readLog(path) : readTum(path);
  if (poses.empty()) throw InputError(path + ": no poses");
  return poses;
}

void writeTrajectory(const std::string& path, const std::vector<TimedPose>& poses) {
  const bool log = isLogTrajectory(path);
  writeAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    if (!log) out << "# camera trajectory\n# timestamp tx ty tz qx qy qz qw (camera to world)\n";
    for (size_t k = 0; k < poses.size(); ++k) {
      const Pose& p = poses[k].cameraToWorld;
      if (log) {
        out << k << ' ' << k << ' ' << k + 1 << '\n';
        for (int r = 0; r < 4; ++r)
          out << (r < 3 ? p.R(r, 0) : 0.0) << ' ' << (r < 3 ? p.R(r, 1) : 0.0) << ' '
              << (r < 3 ? p.R(r, 2) : 0.0) << ' ' << (r < 3 ? p.t(r) : 1.0) << '\n';
        continue;
      }
      const Eigen::Quaterniond q(p.R);
      out << std::fixed << std::setprecision(6) << poses[k].time << std::defaultfloat
          << std::setprecision(17) << ' ' << p.t.x() << ' ' << p.t.y() << ' ' << p.t.z() << ' '
          << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
  });
}

}  // namespace rangefuse::io
