// What the depth-sequence readers share, private to io/: the camera a folder's frames take,
// one frame as a scan, and a list of frames to be tracked.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "rangefuse/io/Conf.h"
#include "rangefuse/io/DepthSequence.h"

namespace rangefuse::io::internal {

/// True when `p` exists (no exception on a permission error: it is then absent).
bool present(const std::filesystem::path& p);

/// The camera of folder `dir`: --intrinsics, else DIR/camera_intrinsic.json, else 7-Scenes'
/// DIR/camera-intrinsics.txt; its depth unit from --depth-scale, else the layout's
/// `countsPerMetre`. Throws InputError naming the folder when there is none.
DepthCamera sequenceCamera(const std::string& dir, const DepthReading& reading,
                           double countsPerMetre);

/// Frame `file` (relative to `dir`) taken at `time` from `cameraToWorld` as a scan.
ConfScan frameScan(const std::string& dir, const std::string& file, const Pose& cameraToWorld,
                   const DepthCamera& camera, double time);

/// The number of a 7-Scenes file named frame-NNNNNN.<kind> (kind "depth.png" or "pose.txt"),
/// or -1 when `file` is not named so.
long sevenScenesNumber(const std::string& file, const std::string& kind);

/// Every frame at the first camera's pose (the identity): the list of a sequence to track.
ConfFile unposed(const std::string& dir, const std::vector<std::string>& files,
                 const std::vector<double>& times, const DepthCamera& camera);

}  // namespace rangefuse::io::internal
