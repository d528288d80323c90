// Depth-image sequences as scan lists: the TUM RGB-D layout (depth.txt or depth/*.png named by
// timestamp, groundtruth.txt matched by nearest timestamp, depth = count / 5000 m) and the
// Redwood / Open3D layout (depth/*.png in name order, a .log trajectory with one pose per
// image, depth in mm, camera_intrinsic.json). Every frame is one scan.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rangefuse/io/Conf.h"
#include "rangefuse/io/DepthCamera.h"

namespace rangefuse::io {

enum class SequenceLayout { Tum, Redwood };

/// The layout of folder `dir`, or nothing when it is neither.
std::optional<SequenceLayout> sequenceLayout(const std::string& dir);

/// For each frame time, the index of the nearest pose time within maxDifference, or -1.
/// Both lists ascending.
std::vector<long> nearestTimes(const std::vector<double>& frames, const std::vector<double>& poses,
                               double maxDifference);

/// The frames of a TUM folder with a pose within `maxDifference` seconds, posed by it (frames
/// without one are listed in warnings). `camera` comes from --intrinsics or, when it is null,
/// from DIR/camera_intrinsic.json. Throws InputError naming the file and line.
ConfFile readTumSequence(const std::string& dir, const std::optional<DepthCamera>& camera,
                         double maxDepth, double maxDifference = 0.02);

/// The frames of a Redwood folder, the k-th image (by name) posed by the k-th trajectory entry.
ConfFile readRedwoodSequence(const std::string& dir, const std::optional<DepthCamera>& camera,
                             double maxDepth);

/// One frame to write: the image and its camera-to-world pose.
struct DepthFrame {
  DepthImage image;
  Pose cameraToWorld;
};

/// Writes a TUM folder (depth/T.png, depth.txt, groundtruth.txt, camera_intrinsic.json) with
/// frame k at time start + k / rate seconds.
void writeTumSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                      const DepthCamera& camera, double start = 1000.0, double rate = 30.0);

/// Writes a Redwood folder (depth/NNNNNN.png, trajectory.log, camera_intrinsic.json).
void writeRedwoodSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                          const DepthCamera& camera);

}  // namespace rangefuse::io
