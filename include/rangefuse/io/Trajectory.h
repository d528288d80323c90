// Camera trajectories: the TUM RGB-D text format (`timestamp tx ty tz qx qy qz qw` per line,
// camera to world) and the Redwood / Open3D `.log` format (per frame a line of three integers,
// then the 4 x 4 camera-to-world matrix in four rows). The evaluation tools of both benchmarks
// read these files.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Pose.h"

namespace rangefuse::io {

/// Frames a second of a Redwood / Open3D sequence: a .log has no times, so frame k is taken at
/// k / kRedwoodFrameRate seconds (the rate of the Kinect and RealSense streams they record).
inline constexpr double kRedwoodFrameRate = 30;

/// One pose of a trajectory: when (seconds; a .log has none: k / kRedwoodFrameRate) and where.
struct TimedPose {
  double time = 0;
  Pose cameraToWorld;
};

/// True when `path` names a .log trajectory (else it is TUM text).
bool isLogTrajectory(const std::string& path);

/// Reads a TUM trajectory (timestamps ascending) or, by extension, a .log one (frame k at
/// k / kRedwoodFrameRate s).
/// Throws InputError naming the file and line: bad numbers, a quaternion not of unit length, a
/// matrix that is not a rigid motion, timestamps out of order, no poses.
std::vector<TimedPose> readTrajectory(const std::string& path);

/// Writes either format, chosen by extension, atomically; full double precision.
void writeTrajectory(const std::string& path, const std::vector<TimedPose>& poses);

}  // namespace rangefuse::io
