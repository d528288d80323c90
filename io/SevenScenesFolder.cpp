// The 7-Scenes / 3DMatch frame folder: every file of a frame in the folder itself, named
// frame-NNNNNN.KIND.EXT, the camera as a bare K matrix.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "SequenceParts.h"
#include "TextLines.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/Trajectory.h"

namespace fs = std::filesystem;

namespace rangefuse::io {
namespace {

struct Numbered {
  long number;
  std::string file;  ///< name in the folder
};

/// The folder's files named frame-NNNNNN.<kind>, by number.
std::vector<Numbered> numberedFiles(const std::string& dir, const std::string& kind) {
  std::vector<Numbered> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    const long number = internal::sevenScenesNumber(file, kind);
    if (number >= 0) files.push_back({number, file});
  }
  if (ec) throw InputError(dir + ": cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end(),
            [](const Numbered& a, const Numbered& b) { return a.number < b.number; });
  return files;
}

std::string frameName(long number, const char* kind) {
  char text[48];
  std::snprintf(text, sizeof text, "frame-%06ld.%s", number, kind);
  return text;
}

/// A frame's camera-to-world pose: 4 rows of 4 numbers, the last 0 0 0 1, a rigid motion.
Pose readPoseMatrix(const std::string& path) {
  const auto rows = internal::squareRows(path, 4, "a 4 x 4 camera-to-world matrix");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = rows[r][c];
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    throw InputError(path + ": the last row is not '0 0 0 1': not a rigid motion");
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (const std::string problem = rotationProblem(R); !problem.empty())
    throw InputError(path + ": the matrix is " + problem + ", not a rigid motion");
  return rigidPose(Pose{R, m.topRightCorner<3, 1>()}, path);
}

/// Throws when the pose files do not pair one to one with the depth images.
void checkPairs(const std::string& dir, const std::vector<Numbered>& images,
                const std::vector<Numbered>& poses) {
  for (size_t k = 0; k < std::max(images.size(), poses.size()); ++k) {
    const bool imageFirst =
        k < images.size() && (k >= poses.size() || images[k].number < poses[k].number);
    const bool poseFirst =
        k < poses.size() && (k >= images.size() || poses[k].number < images[k].number);
    const std::string counts = std::to_string(images.size()) + " depth images but " +
                               std::to_string(poses.size()) + " pose files";
    if (imageFirst)
      throw InputError((fs::path(dir) / frameName(images[k].number, "pose.txt")).string() +
                       ": missing (" + counts +
                       "): each frame needs its pose, or no frame has one and the stream is "
                       "tracked");
    if (poseFirst)
      throw InputError((fs::path(dir) / poses[k].file).string() + ": a pose without its depth " +
                       "image " + frameName(poses[k].number, "depth.png") + " (" + counts + ")");
  }
}

}  // namespace

long internal::sevenScenesNumber(const std::string& file, const std::string& kind) {
  // frame-, 1 to 9 digits, '.', kind. Parsed by hand: <regex> brought GCC 12's false
  // -Wmaybe-uninitialized into the sanitizer build.
  const std::string prefix = "frame-";
  if (kind != "depth.png" && kind != "pose.txt") return -1;
  if (file.size() <= prefix.size() + kind.size() + 1 || file.compare(0, prefix.size(), prefix) ||
      file.compare(file.size() - kind.size(), kind.size(), kind))
    return -1;
  const size_t digitsEnd = file.size() - kind.size() - 1;
  if (file[digitsEnd] != '.') return -1;
  if (digitsEnd - prefix.size() > 9) return -1;  // at least one: the size test above
  long number = 0;
  for (size_t i = prefix.size(); i < digitsEnd; ++i) {
    if (file[i] < '0' || file[i] > '9') return -1;
    number = 10 * number + (file[i] - '0');
  }
  return number;
}

ConfFile readSevenScenesSequence(const std::string& dir, const DepthReading& reading) {
  const DepthCamera cam = internal::sequenceCamera(dir, reading, 1000);
  const std::vector<Numbered> images = numberedFiles(dir, "depth.png");
  if (images.empty()) throw InputError(dir + ": no frame-NNNNNN.depth.png images");
  const std::vector<Numbered> poses = numberedFiles(dir, "pose.txt");
  std::vector<std::string> files;
  std::vector<double> times;
  for (const Numbered& image : images) {
    files.push_back(image.file);
    times.push_back(static_cast<double>(image.number) / kRedwoodFrameRate);
  }
  if (poses.empty()) return internal::unposed(dir, files, times, cam);
  checkPairs(dir, images, poses);
  ConfFile list;
  for (size_t k = 0; k < images.size(); ++k) {
    const Pose cameraToWorld = readPoseMatrix((fs::path(dir) / poses[k].file).string());
    list.scans.push_back(internal::frameScan(dir, files[k], cameraToWorld, cam, times[k]));
  }
  return list;
}

void writeSevenScenesSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                              const DepthCamera& camera, bool withPoses) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create the folder: " + ec.message());
  for (size_t k = 0; k < frames.size(); ++k) {
    const long n = static_cast<long>(k);
    writeDepthPng((fs::path(dir) / frameName(n, "depth.png")).string(), frames[k].image);
    if (!withPoses) continue;
    const Pose& p = frames[k].cameraToWorld;
    writeAtomically((fs::path(dir) / frameName(n, "pose.txt")).string(), [&](std::ostream& out) {
      out.precision(17);
      for (int r = 0; r < 3; ++r)
        out << p.R(r, 0) << ' ' << p.R(r, 1) << ' ' << p.R(r, 2) << ' ' << p.t(r) << '\n';
      out << "0 0 0 1\n";
    });
  }
  writeAtomically((fs::path(dir) / kSevenScenesIntrinsics).string(), [&](std::ostream& out) {
    out.precision(17);
    out << camera.fx << " 0 " << camera.cx << "\n0 " << camera.fy << ' ' << camera.cy
        << "\n0 0 1\n";
  });
}

}  // namespace rangefuse::io
