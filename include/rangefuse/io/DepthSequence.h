// Depth-image sequences as scan lists: the TUM RGB-D layout (depth.txt or depth/*.png named by
// timestamp, groundtruth.txt matched by nearest timestamp, depth = count / 5000 m), the
// Redwood / Open3D layout (depth/*.png in name order, a .log trajectory with one pose per
// image, depth in mm, camera_intrinsic.json; Open3D's RealSense recorder writes the same
// folder without the trajectory) and the 7-Scenes / 3DMatch layout (frame-NNNNNN.depth.png in
// mm, frame-NNNNNN.pose.txt camera to world, camera-intrinsics.txt). Every frame is one scan. A
// sequence without a trajectory (no groundtruth.txt, no .log) is read with every frame at the first
// camera's pose, the identity, and marked unposed: its frames must be tracked.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rangefuse/io/Conf.h"
#include "rangefuse/io/DepthCamera.h"

namespace rangefuse::io {

enum class SequenceLayout { Tum, Redwood, SevenScenes };

/// 7-Scenes' camera matrix file, in the sequence's folder.
inline constexpr const char* kSevenScenesIntrinsics = "camera-intrinsics.txt";

/// The layout of folder `dir`, or nothing when it is none: TUM when it holds depth.txt or
/// groundtruth.txt, else Redwood when it holds depth/, else 7-Scenes when it holds
/// frame-*.depth.png images.
std::optional<SequenceLayout> sequenceLayout(const std::string& dir);

/// What in folder `dir` contradicts reading it in layout `forced` (--scan-format): a TUM frame
/// list or trajectory for Redwood; numbered depth images and no depth.txt for TUM, whose
/// images are named by timestamp. Empty when nothing does.
std::string layoutContradiction(const std::string& dir, SequenceLayout forced);

/// Why folder `dir` is no sequence, for the message (e.g. it holds colour images only).
std::string notASequence(const std::string& dir);

/// How to read a sequence's depth images beyond the folder's own files.
struct DepthReading {
  std::optional<DepthCamera> camera;  ///< --intrinsics (null: DIR/camera_intrinsic.json)
  double depthMax = 0;                ///< farther depths are dropped (0: keep all)
  double depthScale = 0;              ///< counts per metre (0: the layout's: 5000 or 1000)
};

/// For each frame time, the index of the nearest pose time within maxDifference, or -1.
/// Both lists ascending.
std::vector<long> nearestTimes(const std::vector<double>& frames, const std::vector<double>& poses,
                               double maxDifference);

/// The frames of a TUM folder with a pose within `maxDifference` seconds, posed by it (frames
/// without one are listed in warnings); without groundtruth.txt, every frame, unposed. With
/// rgb.txt, each frame takes the colour image nearest in time within `maxDifference` (frames
/// without one: a warning). Throws InputError naming the file and line.
ConfFile readTumSequence(const std::string& dir, const DepthReading& reading,
                         double maxDifference = 0.02);

/// The frames of a Redwood folder, the k-th image (by name) posed by the k-th trajectory entry;
/// without a .log, every frame, unposed. Frame k's time is k / 30 s. With color/ (or image/),
/// the k-th PNG by name is frame k's colour image (as many as depth images, else InputError);
/// JPEG colour images are not read (a warning).
ConfFile readRedwoodSequence(const std::string& dir, const DepthReading& reading);

/// The frames of a 7-Scenes folder (frame-NNNNNN.depth.png, in number order), frame N at
/// N / 30 s, each posed by its frame-NNNNNN.pose.txt (a 4 x 4 camera-to-world matrix); with no
/// pose files, every frame unposed. The camera: --intrinsics, camera_intrinsic.json or
/// camera-intrinsics.txt. Colour images (frame-NNNNNN.color.png) are not read: 7-Scenes' are
/// not registered to the depth. Throws InputError naming the file: some frames without a pose
/// (or poses without a frame), a pose that is not a rigid motion, no intrinsics.
ConfFile readSevenScenesSequence(const std::string& dir, const DepthReading& reading);

/// One frame to write: the image and its camera-to-world pose.
struct DepthFrame {
  DepthImage image;
  Pose cameraToWorld;
  Image colour = {};  ///< registered to the depth; empty (width 0): none
};

/// Writes a TUM folder (depth/T.png, depth.txt, groundtruth.txt, camera_intrinsic.json, and
/// rgb/T.png, or rgb/T.jpg with `jpegColour`, with rgb.txt when the frames have colour) with
/// frame k at time start + k / rate seconds.
void writeTumSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                      const DepthCamera& camera, double start = 1000.0, double rate = 30.0,
                      bool jpegColour = false);

/// Writes a Redwood folder (depth/NNNNNN.png, trajectory.log, camera_intrinsic.json, and
/// color/NNNNNN.png when the frames have colour; color/NNNNNN.jpg with `jpegColour`, as
/// Open3D's recorder writes them).
void writeRedwoodSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                          const DepthCamera& camera, bool jpegColour = false);

/// Writes a 7-Scenes folder: frame-NNNNNN.depth.png (mm), frame-NNNNNN.pose.txt unless
/// `withPoses` is false, camera-intrinsics.txt.
void writeSevenScenesSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                              const DepthCamera& camera, bool withPoses = true);

}  // namespace rangefuse::io
