#include "rangefuse/io/DepthSequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"

namespace fs = std::filesystem;

namespace rangefuse::io {
namespace {

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

/// The .png files of DIR/depth, sorted by name.
std::vector<fs::path> depthImages(const std::string& dir) {
  std::vector<fs::path> images;
  std::error_code ec;
  for (fs::directory_iterator it(fs::path(dir) / "depth", ec), end; !ec && it != end;
       it.increment(ec))
    if (it->path().extension() == ".png") images.push_back(it->path());
  if (ec) throw InputError(dir + "/depth: cannot list the folder: " + ec.message());
  std::sort(images.begin(), images.end());
  return images;
}

/// The one .log trajectory of a Redwood folder (trajectory.log when there are several).
fs::path trajectoryLog(const std::string& dir) {
  if (present(fs::path(dir) / "trajectory.log")) return fs::path(dir) / "trajectory.log";
  std::vector<fs::path> logs;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".log") logs.push_back(it->path());
  if (logs.size() != 1)
    throw InputError(dir + ": a Redwood sequence needs one .log trajectory (found " +
                     std::to_string(logs.size()) +
                     "; trajectory.log is taken when there are several)");
  return logs[0];
}

DepthCamera cameraFor(const std::string& dir, const std::optional<DepthCamera>& given, double unit,
                      double maxDepth) {
  const fs::path json = fs::path(dir) / "camera_intrinsic.json";
  if (!given && !present(json))
    throw InputError(dir +
                     ": no camera intrinsics: give --intrinsics fx,fy,cx,cy (pixels) or a "
                     "camera_intrinsic.json file, or put camera_intrinsic.json in the folder");
  DepthCamera c = given ? *given : readIntrinsicJson(json.string());
  c.unit = unit;
  c.maxDepth = maxDepth;
  return c;
}

/// The data lines of a text file with their numbers, '#' comments and blank lines skipped.
std::vector<std::pair<int, std::string>> dataLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open file");
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    lines.emplace_back(n, line);
  }
  return lines;
}

std::string at(const fs::path& path, int line) {
  return path.string() + ": line " + std::to_string(line);
}

/// Reads `count` finite numbers from a line, refusing fewer, more or non-finite ones (strtod,
/// unlike stream extraction, reads "nan" and "inf", so they are named as such).
std::vector<double> numbers(const std::string& text, size_t count, const std::string& where,
                            const char* expected) {
  std::istringstream in(text);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (*end != '\0' || v.size() == count)
      throw InputError(where + ": expected " + expected + ", found '" + word + "'");
    if (!std::isfinite(x)) throw InputError(where + ": NaN or Inf in " + expected);
    v.push_back(x);
  }
  if (v.size() != count) throw InputError(where + ": expected " + expected);
  return v;
}

struct Timed {
  double time;
  std::string file;  ///< depth image, relative to the folder
  Pose pose;         ///< camera to world (trajectories)
  int line = 0;
};

void checkAscending(const std::vector<Timed>& list, const fs::path& file) {
  for (size_t k = 1; k < list.size(); ++k)
    if (!(list[k].time > list[k - 1].time))
      throw InputError(at(file, list[k].line) + ": timestamps out of order (" +
                       std::to_string(list[k].time) + " after " + std::to_string(list[k - 1].time) +
                       ")");
}

/// depth.txt ("t depth/t.png"), or the images of depth/ named by their timestamps.
std::vector<Timed> tumFrames(const std::string& dir) {
  std::vector<Timed> frames;
  const fs::path list = fs::path(dir) / "depth.txt";
  if (present(list)) {
    for (const auto& [n, text] : dataLines(list)) {
      std::istringstream in(text);
      Timed f;
      f.line = n;
      if (!(in >> f.time >> f.file) || !std::isfinite(f.time))
        throw InputError(at(list, n) + ": expected 'timestamp depth/FILE.png'");
      if (!present(fs::path(dir) / f.file))
        throw InputError(at(list, n) + ": " + f.file + " does not exist (missing frame)");
      frames.push_back(f);
    }
    checkAscending(frames, list);
  } else {
    for (const fs::path& p : depthImages(dir)) {
      char* end = nullptr;
      const std::string stem = p.stem().string();
      const double t = std::strtod(stem.c_str(), &end);
      if (*end != '\0' || !std::isfinite(t))
        throw InputError(p.string() + ": without depth.txt, image names must be timestamps");
      frames.push_back({t, "depth/" + p.filename().string(), Pose{}, 0});
    }
    std::sort(frames.begin(), frames.end(),
              [](const Timed& a, const Timed& b) { return a.time < b.time; });
  }
  if (frames.empty()) throw InputError(dir + ": no depth frames (depth.txt or depth/*.png)");
  return frames;
}

/// groundtruth.txt: "t tx ty tz qx qy qz qw", camera to world.
std::vector<Timed> tumPoses(const std::string& dir) {
  const fs::path file = fs::path(dir) / "groundtruth.txt";
  std::vector<Timed> poses;
  for (const auto& [n, text] : dataLines(file)) {
    const std::vector<double> v = numbers(text, 8, at(file, n), "'t tx ty tz qx qy qz qw'");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1) > 0.01)
      throw InputError(at(file, n) + ": quaternion is not of unit length");
    Timed p{v[0], "", Pose{q.normalized().toRotationMatrix(), Eigen::Vector3d(v[1], v[2], v[3])},
            n};
    poses.push_back(p);
  }
  if (poses.empty()) throw InputError(file.string() + ": no poses");
  checkAscending(poses, file);
  return poses;
}

/// A .log trajectory: per frame a line of three integers, then four rows of the 4 x 4
/// camera-to-world matrix.
std::vector<Pose> logPoses(const fs::path& file) {
  const auto lines = dataLines(file);
  if (lines.size() % 5 != 0)
    throw InputError(file.string() + ": " + std::to_string(lines.size()) +
                     " lines: a trajectory has 5 per frame (three integers, then 4 rows of 4)");
  std::vector<Pose> poses;
  for (size_t k = 0; k < lines.size(); k += 5) {
    numbers(lines[k].second, 3, at(file, lines[k].first), "three integers");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      const auto row = numbers(lines[k + 1 + r].second, 4, at(file, lines[k + 1 + r].first),
                               "a matrix row of 4 numbers");
      for (int c = 0; c < 4; ++c) m(r, c) = row[c];
    }
    const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R.determinant() < 0)
      throw InputError(at(file, lines[k + 1].first) + ": the matrix is not a rigid motion");
    poses.push_back(Pose{R, m.topRightCorner<3, 1>()});
  }
  return poses;
}

ConfScan frameScan(const std::string& dir, const std::string& file, const Pose& cameraToWorld,
                   const DepthCamera& camera) {
  return ConfScan{file, (fs::path(dir) / file).lexically_normal().string(), scanPose(cameraToWorld),
                  std::nullopt, camera};
}

}  // namespace

std::optional<SequenceLayout> sequenceLayout(const std::string& dir) {
  const fs::path d(dir);
  if (present(d / "depth.txt") || present(d / "groundtruth.txt")) return SequenceLayout::Tum;
  if (present(d / "depth")) {
    std::error_code ec;
    for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".log") return SequenceLayout::Redwood;
  }
  return std::nullopt;
}

std::vector<long> nearestTimes(const std::vector<double>& frames, const std::vector<double>& poses,
                               double maxDifference) {
  std::vector<long> match(frames.size(), -1);
  for (size_t k = 0; k < frames.size(); ++k) {
    const auto next = std::lower_bound(poses.begin(), poses.end(), frames[k]);
    long best = -1;
    double gap = maxDifference;
    if (next != poses.end() && *next - frames[k] <= gap) {
      best = next - poses.begin();
      gap = *next - frames[k];
    }
    if (next != poses.begin() && frames[k] - *(next - 1) <= gap) best = next - 1 - poses.begin();
    match[k] = best;
  }
  return match;
}

ConfFile readTumSequence(const std::string& dir, const std::optional<DepthCamera>& camera,
                         double maxDepth, double maxDifference) {
  const DepthCamera cam = cameraFor(dir, camera, 1.0 / 5000, maxDepth);
  const std::vector<Timed> frames = tumFrames(dir), poses = tumPoses(dir);
  std::vector<double> frameTimes, poseTimes;
  for (const Timed& f : frames) frameTimes.push_back(f.time);
  for (const Timed& p : poses) poseTimes.push_back(p.time);
  const std::vector<long> match = nearestTimes(frameTimes, poseTimes, maxDifference);
  ConfFile list;
  size_t unmatched = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (match[k] < 0) {
      ++unmatched;
      continue;
    }
    list.scans.push_back(frameScan(dir, frames[k].file, poses[match[k]].pose, cam));
  }
  if (unmatched > 0)
    list.warnings.push_back(dir + "/groundtruth.txt: " + std::to_string(unmatched) + " of " +
                            std::to_string(frames.size()) + " depth frames have no pose within " +
                            std::to_string(maxDifference) + " s and are left out");
  if (list.scans.empty())
    throw InputError(dir + "/groundtruth.txt: no depth frame has a pose within " +
                     std::to_string(maxDifference) + " s");
  return list;
}

ConfFile readRedwoodSequence(const std::string& dir, const std::optional<DepthCamera>& camera,
                             double maxDepth) {
  const DepthCamera cam = cameraFor(dir, camera, 1e-3, maxDepth);
  const fs::path log = trajectoryLog(dir);
  const std::vector<Pose> poses = logPoses(log);
  const std::vector<fs::path> images = depthImages(dir);
  if (poses.size() != images.size())
    throw InputError(log.string() + ": " + std::to_string(poses.size()) + " poses but " + dir +
                     "/depth holds " + std::to_string(images.size()) +
                     " images: each image needs its pose, in name order");
  if (images.empty()) throw InputError(dir + "/depth: no .png depth images");
  ConfFile list;
  for (size_t k = 0; k < images.size(); ++k)
    list.scans.push_back(frameScan(dir, "depth/" + images[k].filename().string(), poses[k], cam));
  return list;
}

namespace {

void makeFolders(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "depth", ec);
  if (ec) throw InputError(dir + "/depth: cannot create the folder: " + ec.message());
}

}  // namespace

void writeTumSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                      const DepthCamera& camera, double start, double rate) {
  makeFolders(dir);
  std::vector<std::string> names;
  for (size_t k = 0; k < frames.size(); ++k) {
    std::ostringstream name;
    name << std::fixed << std::setprecision(6) << start + k / rate;
    names.push_back(name.str());
    writeDepthPng(dir + "/depth/" + names.back() + ".png", frames[k].image);
  }
  writeAtomically(dir + "/depth.txt", [&](std::ostream& out) {
    out << "# depth maps\n# timestamp filename\n";
    for (const std::string& t : names) out << t << " depth/" << t << ".png\n";
  });
  writeAtomically(dir + "/groundtruth.txt", [&](std::ostream& out) {
    out << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n" << std::setprecision(17);
    for (size_t k = 0; k < frames.size(); ++k) {
      const Pose& p = frames[k].cameraToWorld;
      const Eigen::Quaterniond q(p.R);
      out << names[k] << ' ' << p.t.x() << ' ' << p.t.y() << ' ' << p.t.z() << ' ' << q.x() << ' '
          << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
  });
  writeIntrinsicJson(dir + "/camera_intrinsic.json", camera);
}

void writeRedwoodSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                          const DepthCamera& camera) {
  makeFolders(dir);
  for (size_t k = 0; k < frames.size(); ++k) {
    std::ostringstream name;
    name << dir << "/depth/" << std::setw(6) << std::setfill('0') << k << ".png";
    writeDepthPng(name.str(), frames[k].image);
  }
  writeAtomically(dir + "/trajectory.log", [&](std::ostream& out) {
    out << std::setprecision(17);
    for (size_t k = 0; k < frames.size(); ++k) {
      const Pose& p = frames[k].cameraToWorld;
      out << k << ' ' << k << ' ' << k + 1 << '\n';
      for (int r = 0; r < 4; ++r)
        out << (r < 3 ? p.R(r, 0) : 0.0) << ' ' << (r < 3 ? p.R(r, 1) : 0.0) << ' '
            << (r < 3 ? p.R(r, 2) : 0.0) << ' ' << (r < 3 ? p.t(r) : 1.0) << '\n';
    }
  });
  writeIntrinsicJson(dir + "/camera_intrinsic.json", camera);
}

}  // namespace rangefuse::io
