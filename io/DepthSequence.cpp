#include "rangefuse/io/DepthSequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "SequenceParts.h"
#include "TextLines.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/AtomicFile.h"
#include "rangefuse/io/Jpeg.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/Trajectory.h"

namespace fs = std::filesystem;

namespace rangefuse::io {
namespace internal {

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

DepthCamera sequenceCamera(const std::string& dir, const DepthReading& reading,
                           double countsPerMetre) {
  const std::optional<DepthCamera>& given = reading.camera;
  const fs::path json = fs::path(dir) / "camera_intrinsic.json";
  const fs::path kFile = fs::path(dir) / kSevenScenesIntrinsics;
  if (!given && !present(json) && !present(kFile))
    throw InputError(dir +
                     ": no camera intrinsics: give --intrinsics fx,fy,cx,cy (pixels) or a "
                     "camera_intrinsic.json file, or put camera_intrinsic.json (or 7-Scenes' " +
                     std::string(kSevenScenesIntrinsics) + ") in the folder");
  DepthCamera c = given           ? *given
                  : present(json) ? readIntrinsicJson(json.string())
                                  : readIntrinsicMatrix(kFile.string());
  c.unit = 1.0 / (reading.depthScale > 0 ? reading.depthScale : countsPerMetre);
  c.depthMax = reading.depthMax;
  return c;
}

ConfScan frameScan(const std::string& dir, const std::string& file, const Pose& cameraToWorld,
                   const DepthCamera& camera, double time) {
  ConfScan scan{file, (fs::path(dir) / file).lexically_normal().string(), scanPose(cameraToWorld),
                std::nullopt, camera};
  scan.time = time;
  return scan;
}

ConfFile unposed(const std::string& dir, const std::vector<std::string>& files,
                 const std::vector<double>& times, const DepthCamera& camera) {
  ConfFile list;
  list.posed = false;
  for (size_t k = 0; k < files.size(); ++k)
    list.scans.push_back(frameScan(dir, files[k], Pose{}, camera, times[k]));
  return list;
}

}  // namespace internal
namespace {

/// True when folder `dir` holds a 7-Scenes depth image (frame-*.depth.png).
bool holdsSevenScenesFrames(const std::string& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (internal::sevenScenesNumber(name, "depth.png") >= 0) return true;
  }
  return false;
}

using internal::frameScan;
using internal::present;
using internal::unposed;

/// The .png files of DIR/depth, sorted by name; hidden ones (a recorder's files being
/// written, .name.png) are not frames.
std::vector<fs::path> depthImages(const std::string& dir) {
  std::vector<fs::path> images;
  std::error_code ec;
  for (fs::directory_iterator it(fs::path(dir) / "depth", ec), end; !ec && it != end;
       it.increment(ec)) {
    const fs::path& p = it->path();
    if (p.extension() == ".png" && p.filename().string()[0] != '.') images.push_back(p);
  }
  if (ec) throw InputError(dir + "/depth: cannot list the folder: " + ec.message());
  std::sort(images.begin(), images.end());
  return images;
}

/// The one .log trajectory of a Redwood folder (trajectory.log when there are several), or an
/// empty path when it has none.
fs::path trajectoryLog(const std::string& dir) {
  if (present(fs::path(dir) / "trajectory.log")) return fs::path(dir) / "trajectory.log";
  std::vector<fs::path> logs;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".log") logs.push_back(it->path());
  if (logs.size() > 1)
    throw InputError(dir + ": a Redwood sequence needs one .log trajectory (found " +
                     std::to_string(logs.size()) +
                     "; trajectory.log is taken when there are several)");
  return logs.empty() ? fs::path() : logs[0];
}

std::string at(const fs::path& path, int line) {
  return internal::lineOf(path.string(), line);
}

std::vector<std::pair<int, std::string>> dataLines(const fs::path& path) {
  return internal::dataLines(path.string());
}

struct Timed {
  double time;
  std::string file;  ///< depth image, relative to the folder
  int line = 0;
};

void checkAscending(const std::vector<Timed>& list, const fs::path& file) {
  for (size_t k = 1; k < list.size(); ++k)
    if (!(list[k].time > list[k - 1].time))
      throw InputError(at(file, list[k].line) + ": timestamps out of order (" +
                       std::to_string(list[k].time) + " after " + std::to_string(list[k - 1].time) +
                       ")");
}

/// A TUM list of images ("t folder/t.png" a line, times ascending) in `dir`; `folder` names
/// the images' folder in the messages.
std::vector<Timed> timedList(const std::string& dir, const fs::path& list,
                             const std::string& folder) {
  std::vector<Timed> images;
  for (const auto& [n, text] : dataLines(list)) {
    std::istringstream in(text);
    Timed f;
    f.line = n;
    if (!(in >> f.time >> f.file) || !std::isfinite(f.time))
      throw InputError(at(list, n) + ": expected 'timestamp " + folder + "/FILE.png'");
    if (!present(fs::path(dir) / f.file))
      throw InputError(at(list, n) + ": " + f.file + " does not exist (missing image)");
    images.push_back(f);
  }
  checkAscending(images, list);
  return images;
}

/// depth.txt ("t depth/t.png"), or the images of depth/ named by their timestamps.
std::vector<Timed> tumFrames(const std::string& dir) {
  std::vector<Timed> frames;
  const fs::path list = fs::path(dir) / "depth.txt";
  if (present(list)) {
    frames = timedList(dir, list, "depth");
  } else {
    for (const fs::path& p : depthImages(dir)) {
      char* end = nullptr;
      const std::string stem = p.stem().string();
      const double t = std::strtod(stem.c_str(), &end);
      if (*end != '\0' || !std::isfinite(t))
        throw InputError(p.string() + ": without depth.txt, image names must be timestamps");
      frames.push_back({t, "depth/" + p.filename().string(), 0});
    }
    std::sort(frames.begin(), frames.end(),
              [](const Timed& a, const Timed& b) { return a.time < b.time; });
  }
  if (frames.empty()) throw InputError(dir + ": no depth frames (depth.txt or depth/*.png)");
  return frames;
}

/// rgb.txt's colour images ("t rgb/t.png"), or none when the folder has no rgb.txt.
std::vector<Timed> tumColours(const std::string& dir) {
  const fs::path list = fs::path(dir) / "rgb.txt";
  return present(list) ? timedList(dir, list, "rgb") : std::vector<Timed>{};
}

/// Gives each frame the colour image nearest in time within `maxDifference` seconds (TUM's
/// association); frames without one stay grey, and a warning says how many.
void associateColours(const std::string& dir, ConfFile& list, double maxDifference) {
  const std::vector<Timed> images = tumColours(dir);
  if (images.empty()) return;
  std::vector<double> frameTimes, imageTimes;
  for (const ConfScan& s : list.scans) frameTimes.push_back(s.time);
  for (const Timed& t : images) imageTimes.push_back(t.time);
  const std::vector<long> match = nearestTimes(frameTimes, imageTimes, maxDifference);
  size_t without = 0;
  for (size_t k = 0; k < list.scans.size(); ++k) {
    if (match[k] < 0) {
      ++without;
      continue;
    }
    list.scans[k].colour = (fs::path(dir) / images[match[k]].file).lexically_normal().string();
  }
  if (without > 0)
    list.warnings.push_back(
        dir + "/rgb.txt: " + std::to_string(without) + " of " + std::to_string(list.scans.size()) +
        " depth frames have no colour image within " + std::to_string(maxDifference) + " s");
}

/// The Redwood / recorder colour folder (color/ or image/), its PNG or JPEG images in name
/// order, one per depth image; nothing when there is no such folder. Other files there are
/// ignored; a folder with none of those images gets a warning and the frames stay grey.
void redwoodColours(const std::string& dir, ConfFile& list) {
  for (const char* folder : {"color", "image"}) {
    const fs::path d = fs::path(dir) / folder;
    if (!present(d)) continue;
    std::vector<fs::path> images, other;
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      if (name.empty() || name[0] == '.' || !e.is_regular_file()) continue;
      (isColourImageName(name) ? images : other).push_back(e.path());
    }
    if (images.empty()) {
      if (!other.empty())
        list.warnings.push_back(d.string() + ": no PNG or JPEG images (" +
                                other.front().filename().string() +
                                " is neither); the frames are fused without colour");
      return;
    }
    std::sort(images.begin(), images.end());
    if (images.size() != list.scans.size())
      throw InputError(d.string() + " holds " + std::to_string(images.size()) +
                       " colour images but depth/ " + std::to_string(list.scans.size()) +
                       ": each depth image needs its colour image, in name order");
    for (size_t k = 0; k < images.size(); ++k)
      list.scans[k].colour = images[k].lexically_normal().string();
    return;
  }
}

}  // namespace

std::optional<SequenceLayout> sequenceLayout(const std::string& dir) {
  const fs::path d(dir);
  if (present(d / "depth.txt") || present(d / "groundtruth.txt")) return SequenceLayout::Tum;
  if (present(d / "depth")) return SequenceLayout::Redwood;
  if (holdsSevenScenesFrames(dir)) return SequenceLayout::SevenScenes;
  return std::nullopt;
}

std::string layoutContradiction(const std::string& dir, SequenceLayout forced) {
  const fs::path d(dir);
  if (forced == SequenceLayout::SevenScenes) {
    for (const char* other : {"depth.txt", "groundtruth.txt", "depth"})
      if (present(d / other))
        return std::string("it holds ") + other + ", a TUM or Redwood folder's file";
    return "";
  }
  if (!present(d / "depth") && !present(d / "depth.txt") && holdsSevenScenesFrames(dir))
    return "its depth images are frame-NNNNNN.depth.png beside their poses, as a 7-Scenes "
           "folder's";
  if (forced == SequenceLayout::Redwood) {
    for (const char* tum : {"depth.txt", "groundtruth.txt"})
      if (present(d / tum)) return std::string("it holds ") + tum + ", a TUM RGB-D folder's file";
    return "";
  }
  if (present(d / "depth.txt")) return "";
  const std::vector<fs::path> images = depthImages(dir);
  if (images.empty()) return "";
  const std::string stem = images.front().stem().string();
  if (stem.find('.') != std::string::npos) return "";
  return "its depth images are numbered (depth/" + images.front().filename().string() +
         ") and it has no depth.txt, as a Redwood or Open3D-recorder folder; TUM's are named "
         "by timestamp";
}

std::string notASequence(const std::string& dir) {
  const fs::path d(dir);
  // A folder of range grids with their scan list: the list is what --scans wants.
  std::vector<std::string> lists;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(d, ec)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".conf" || ext == ".ptx") lists.push_back(entry.path().filename().string());
  }
  std::sort(lists.begin(), lists.end());
  if (!lists.empty()) {
    std::string names;
    for (size_t k = 0; k < lists.size() && k < 3; ++k)
      names += (k ? ", " : "") + (d / lists[k]).string();
    return "is a folder, not a depth sequence; it holds " + names +
           (lists.size() > 3 ? ", ..." : "") + ": give --scans one of those";
  }
  for (const char* colour : {"color", "rgb", "image"})
    if (present(d / colour))
      return std::string("holds colour images (") + colour +
             "/) but no depth images: a sequence needs depth/ (16-bit PNG) or depth.txt";
  return "a folder of scans must be a depth-image sequence: TUM RGB-D (depth.txt, optionally "
         "groundtruth.txt), Redwood / Open3D recorder (depth/, optionally a .log trajectory) or "
         "7-Scenes (frame-NNNNNN.depth.png, optionally frame-NNNNNN.pose.txt)";
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

ConfFile readTumSequence(const std::string& dir, const DepthReading& reading,
                         double maxDifference) {
  const DepthCamera cam = internal::sequenceCamera(dir, reading, 5000);
  const std::vector<Timed> frames = tumFrames(dir);
  std::vector<double> frameTimes, poseTimes;
  std::vector<std::string> files;
  for (const Timed& f : frames) frameTimes.push_back(f.time), files.push_back(f.file);
  const fs::path truth = fs::path(dir) / "groundtruth.txt";
  if (!present(truth)) {
    ConfFile list = unposed(dir, files, frameTimes, cam);
    associateColours(dir, list, maxDifference);
    return list;
  }
  const std::vector<TimedPose> poses = readTrajectory(truth.string());
  for (const TimedPose& p : poses) poseTimes.push_back(p.time);
  const std::vector<long> match = nearestTimes(frameTimes, poseTimes, maxDifference);
  ConfFile list;
  size_t unmatched = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (match[k] < 0) {
      ++unmatched;
      continue;
    }
    list.scans.push_back(
        frameScan(dir, frames[k].file, poses[match[k]].cameraToWorld, cam, frames[k].time));
  }
  if (unmatched > 0)
    list.warnings.push_back(dir + "/groundtruth.txt: " + std::to_string(unmatched) + " of " +
                            std::to_string(frames.size()) + " depth frames have no pose within " +
                            std::to_string(maxDifference) + " s and are left out");
  if (list.scans.empty())
    throw InputError(dir + "/groundtruth.txt: no depth frame has a pose within " +
                     std::to_string(maxDifference) + " s");
  associateColours(dir, list, maxDifference);
  return list;
}

ConfFile readRedwoodSequence(const std::string& dir, const DepthReading& reading) {
  const DepthCamera cam = internal::sequenceCamera(dir, reading, 1000);
  const std::vector<fs::path> images = depthImages(dir);
  if (images.empty()) throw InputError(dir + "/depth: no .png depth images");
  std::vector<std::string> files;
  std::vector<double> times;
  for (const fs::path& image : images) {
    times.push_back(static_cast<double>(files.size()) / kRedwoodFrameRate);
    files.push_back("depth/" + image.filename().string());
  }
  const fs::path log = trajectoryLog(dir);
  if (log.empty()) {
    ConfFile list = unposed(dir, files, times, cam);
    redwoodColours(dir, list);
    return list;
  }
  const std::vector<TimedPose> poses = readTrajectory(log.string());
  if (poses.size() != images.size())
    throw InputError(log.string() + ": " + std::to_string(poses.size()) + " poses but " + dir +
                     "/depth holds " + std::to_string(images.size()) +
                     " images: each image needs its pose, in name order");
  ConfFile list;
  for (size_t k = 0; k < images.size(); ++k)
    list.scans.push_back(frameScan(dir, files[k], poses[k].cameraToWorld, cam, times[k]));
  redwoodColours(dir, list);
  return list;
}

namespace {

void makeFolders(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "depth", ec);
  if (ec) throw InputError(dir + "/depth: cannot create the folder: " + ec.message());
}

/// A colour image as PNG or, by its name, JPEG (quality 95).
void writeColour(const std::string& path, const Image& image) {
  if (fs::path(path).extension() == ".jpg")
    writeJpeg(path, image, 95);
  else
    writePng(path, image);
}

}  // namespace

void writeTumSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                      const DepthCamera& camera, double start, double rate, bool jpegColour) {
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
  if (!frames.empty() && frames[0].colour.width > 0) {
    fs::create_directories(fs::path(dir) / "rgb");
    const char* ext = jpegColour ? ".jpg" : ".png";
    for (size_t k = 0; k < frames.size(); ++k)
      writeColour(dir + "/rgb/" + names[k] + ext, frames[k].colour);
    writeAtomically(dir + "/rgb.txt", [&](std::ostream& out) {
      out << "# color images\n# timestamp filename\n";
      for (const std::string& t : names) out << t << " rgb/" << t << ext << "\n";
    });
  }
  std::vector<TimedPose> trajectory;
  for (size_t k = 0; k < frames.size(); ++k)
    trajectory.push_back({std::strtod(names[k].c_str(), nullptr), frames[k].cameraToWorld});
  writeTrajectory(dir + "/groundtruth.txt", trajectory);
  writeIntrinsicJson(dir + "/camera_intrinsic.json", camera);
}

void writeRedwoodSequence(const std::string& dir, const std::vector<DepthFrame>& frames,
                          const DepthCamera& camera, bool jpegColour) {
  makeFolders(dir);
  for (size_t k = 0; k < frames.size(); ++k) {
    std::ostringstream name;
    name << std::setw(6) << std::setfill('0') << k;
    writeDepthPng(dir + "/depth/" + name.str() + ".png", frames[k].image);
    if (frames[k].colour.width > 0) {
      fs::create_directories(fs::path(dir) / "color");
      writeColour(dir + "/color/" + name.str() + (jpegColour ? ".jpg" : ".png"), frames[k].colour);
    }
  }
  std::vector<TimedPose> trajectory;
  for (size_t k = 0; k < frames.size(); ++k)
    trajectory.push_back({static_cast<double>(k), frames[k].cameraToWorld});
  writeTrajectory(dir + "/trajectory.log", trajectory);
  writeIntrinsicJson(dir + "/camera_intrinsic.json", camera);
}

}  // namespace rangefuse::io
