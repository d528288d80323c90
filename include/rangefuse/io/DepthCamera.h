// Depth cameras (RGB-D sensors): pinhole intrinsics in the OpenCV convention and the mapping of
// a depth image onto rangefuse's range grid and scan frame.
#pragma once

#include <string>

#include "rangefuse/core/Image.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/core/RangeGrid.h"
#include "rangefuse/io/DepthPng.h"

namespace rangefuse::io {

/// Camera looking along +z with x to the right and y down (OpenCV, TUM, Redwood, Open3D).
struct DepthCamera {
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels
  int width = 0, height = 0;              ///< 0: not given (then any image size is accepted)
  double unit = 1e-3;                     ///< scene units (metres) per depth count
  double depthMax = 0;                    ///< farther counts are dropped (0: keep all)
};

/// The image's grid in rangefuse's scan frame: the sensor at the origin looking toward -z, rows
/// growing with +y, so pixel (u, v) is cell (height - 1 - v, u). The frame is the camera's
/// turned half a turn about x (see scanPose). Throws InputError naming `path` when the image
/// size disagrees with the camera's.
RangeGrid depthGrid(const DepthImage& image, const DepthCamera& camera, const std::string& path);

/// Colours grid's points (made by depthGrid from a depth image of the same size) from a colour
/// image registered to the depth, as recorders write it: the point of pixel (u, v) takes the
/// colour of pixel (u, v). Throws InputError naming `path` when the sizes differ.
void colourFromImage(RangeGrid& grid, const Image& colour, const std::string& path);

/// The other way: a pinhole grid's colours as an image registered to its depth image (black
/// where there is no point).
Image colourImage(const RangeGrid& grid);

/// The other way, for a pinhole grid (synthetic scans): depth along the camera axis in counts
/// of `unit`, 0 where there is no point or the depth does not fit 16 bits. A point on its
/// pixel's ray stays on it; depthGrid gives it back to within half a count in depth.
DepthImage depthImage(const RangeGrid& grid, double unit);

/// The camera of a pinhole grid, in the OpenCV convention (rows counted from the top).
DepthCamera depthCamera(const RangeGrid& grid, double unit);

/// The scan frame's pose from a camera-to-world pose, and back.
Pose scanPose(const Pose& cameraToWorld);
Pose cameraPose(const Pose& scanToWorld);

/// Open3D's camera_intrinsic.json: {"width", "height", "intrinsic_matrix": 9 numbers, column
/// major}. Throws InputError naming the file.
DepthCamera readIntrinsicJson(const std::string& path);

/// A 7-Scenes camera-intrinsics.txt: the 3 x 3 matrix K ("fx 0 cx", "0 fy cx", "0 0 1"), the
/// image size not given (any is accepted). Throws InputError naming the file (and line).
DepthCamera readIntrinsicMatrix(const std::string& path);

/// Writes Open3D's layout (atomically).
void writeIntrinsicJson(const std::string& path, const DepthCamera& camera);

/// `--intrinsics`: "fx,fy,cx,cy", a camera_intrinsic.json path or a K matrix's .txt path.
DepthCamera parseIntrinsics(const std::string& text);

}  // namespace rangefuse::io
