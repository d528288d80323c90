#include "rangefuse/io/ScanFiles.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "SequenceParts.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/DepthSequence.h"
#include "rangefuse/io/Jpeg.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/io/RangeGridPly.h"

namespace rangefuse::io {
namespace {

std::string extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool isPtx(const std::string& path) {
  return extension(path) == ".ptx";
}

bool isE57(const std::string& path) {
  return extension(path) == ".e57";
}

/// Splits "FILE.ptx#K" or "FILE.e57#K" into the file and K (from 1); false for any other name.
bool scanReference(const std::string& path, std::string& file, size_t& k) {
  const size_t hash = path.rfind('#');
  if (hash == std::string::npos) return false;
  const std::string ext = extension(path.substr(0, hash));
  if (ext != ".ptx" && ext != ".e57") return false;
  const std::string number = path.substr(hash + 1);
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos ||
      number.size() > 9)
    return false;
  file = path.substr(0, hash);
  k = std::stoul(number);
  return k >= 1;
}

/// The scans of every PTX or E57 file a .conf names, each file indexed once.
void locateFileScans(ConfFile& conf, const std::string& confPath, const InputLimits& limits) {
  std::map<std::string, std::vector<PtxScan>> ptx;
  std::map<std::string, std::vector<E57Scan>> e57;
  for (ConfScan& s : conf.scans) {
    std::string file;
    size_t k = 0;
    if (!scanReference(s.path, file, k)) continue;
    size_t held = 0;
    if (isPtx(file)) {
      auto it = ptx.find(file);
      if (it == ptx.end()) it = ptx.emplace(file, indexPtx(file, limits)).first;
      held = it->second.size();
      if (k <= held) s.ptx = it->second[k - 1];
    } else {
      auto it = e57.find(file);
      if (it == e57.end()) it = e57.emplace(file, indexE57(file, limits)).first;
      held = it->second.size();
      if (k <= held) s.e57 = it->second[k - 1];
    }
    if (k > held)
      throw InputError(confPath + ": " + s.name + ": " + file + " holds only " +
                       std::to_string(held) + " scans");
    s.path = file;
  }
}

std::optional<DepthCamera> givenCamera(const ScanSourceOptions& source) {
  if (source.intrinsics.empty()) return std::nullopt;
  return parseIntrinsics(source.intrinsics);
}

ConfFile readSequence(const std::string& dir, const std::string& format,
                      const ScanSourceOptions& source) {
  std::optional<SequenceLayout> layout = sequenceLayout(dir);
  if (format == "tum") layout = SequenceLayout::Tum;
  if (format == "redwood") layout = SequenceLayout::Redwood;
  if (format == "7scenes") layout = SequenceLayout::SevenScenes;
  if (!layout) throw InputError(dir + ": " + notASequence(dir));
  if (format != "auto")
    if (const std::string why = layoutContradiction(dir, *layout); !why.empty())
      throw InputError(dir + ": --scan-format " + format + " does not fit the folder: " + why +
                       "; leave --scan-format out to read it by its own files (--depth-scale "
                       "sets the counts a metre)");
  const DepthReading reading{givenCamera(source), source.depthMax, source.depthScale};
  switch (*layout) {
    case SequenceLayout::Tum:
      return readTumSequence(dir, reading);
    case SequenceLayout::Redwood:
      return readRedwoodSequence(dir, reading);
    case SequenceLayout::SevenScenes:
      break;
  }
  return readSevenScenesSequence(dir, reading);
}

/// A .conf's depth images (NAME.png) take the camera of their sequence folder.
void locateDepthImages(ConfFile& conf, const ScanSourceOptions& source) {
  std::map<std::string, DepthCamera> cameras;
  for (ConfScan& s : conf.scans) {
    if (std::filesystem::path(s.path).extension() != ".png") continue;
    // A 7-Scenes frame lies in its sequence's folder; the others lie in its depth/ folder.
    const std::filesystem::path image(s.path);
    const bool sevenScenes =
        internal::sevenScenesNumber(image.filename().string(), "depth.png") >= 0;
    const std::string dir =
        (sevenScenes ? image.parent_path() : image.parent_path().parent_path()).string();
    auto it = cameras.find(dir);
    if (it == cameras.end()) {
      const ConfFile probe = readSequence(dir, "auto", source);
      it = cameras.emplace(dir, *probe.scans.front().depth).first;
    }
    s.depth = it->second;
  }
}

ConfFile readPtxList(const std::string& path, const InputLimits& limits) {
  ConfFile list;
  const std::string name = std::filesystem::path(path).filename().string();
  const std::vector<PtxScan> scans = indexPtx(path, limits);
  for (size_t k = 0; k < scans.size(); ++k)
    list.scans.push_back({name + "#" + std::to_string(k + 1), path, scans[k].pose, scans[k]});
  return list;
}

ConfFile readE57List(const std::string& path, const InputLimits& limits) {
  ConfFile list;
  const std::string name = std::filesystem::path(path).filename().string();
  const std::vector<E57Scan> scans = indexE57(path, limits);
  for (size_t k = 0; k < scans.size(); ++k) {
    ConfScan s{name + "#" + std::to_string(k + 1), path, scans[k].pose};
    s.e57 = scans[k];
    if (scans[k].rows == 0)
      list.warnings.push_back(
          s.name + " (" + scans[k].name +
          "): no row and column indices; gridded by spherical projection "
          "around the scan's origin, the angular step estimated from its points");
    list.scans.push_back(std::move(s));
  }
  return list;
}

/// Why a file given as a scan list is not one, from its first bytes; empty when it may be a
/// .conf (text the .conf reader then judges).
std::string notAScanList(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[16] = {};
  in.read(head, sizeof head);
  const std::string start(head, static_cast<size_t>(in.gcount()));
  const auto begins = [&](const char* magic) { return start.rfind(magic, 0) == 0; };
  const std::string expected =
      ": --scans takes a scan list: a .conf with one line 'bmesh FILE tx ty tz qx qy qz qw' per "
      "range-grid PLY file (0 0 0 0 0 0 1: as scanned), a .ptx or .e57 file, or a depth-sequence "
      "folder";
  if (begins("ply\n") || begins("ply\r")) return "is a PLY file, not a scan list" + expected;
  if (begins("\x89PNG")) return "is a PNG image, not a scan list" + expected;
  if (begins("\x89HDF")) return "is an HDF5 file (a checkpoint? continue it with --resume)";
  return "";
}

}  // namespace

ConfFile readScanList(const std::string& path, const InputLimits& limits,
                      const ScanSourceOptions& source) {
  const std::string& format = source.format;
  source.validate();
  std::error_code ec;
  const bool folder = std::filesystem::is_directory(path, ec);
  if (format == "tum" || format == "redwood" || format == "7scenes" || (format == "auto" && folder))
    return readSequence(path, format, source);
  if (format == "ptx" || (format == "auto" && isPtx(path))) return readPtxList(path, limits);
  if (format == "e57" || (format == "auto" && isE57(path))) return readE57List(path, limits);
  if (format == "auto" && !folder) {
    // An E57 file under another name is told by its first bytes.
    std::ifstream in(path, std::ios::binary);
    char head[8] = {};
    if (in.read(head, 8) && std::string(head, 8) == "ASTM-E57") return readE57List(path, limits);
  }
  if (const std::string why = notAScanList(path); !why.empty()) throw InputError(path + ": " + why);
  ConfFile conf = readConf(path);
  locateFileScans(conf, path, limits);
  locateDepthImages(conf, source);
  return conf;
}

std::vector<std::string> scanListFiles(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return filesUnder(path);
  std::vector<std::string> files = {path};
  if (isPtx(path) || isE57(path) || !notAScanList(path).empty()) return files;
  ConfFile conf;
  try {
    conf = readConf(path);
  } catch (const InputError&) {
    return files;
  }
  std::set<std::string> sequences;
  for (const ConfScan& s : conf.scans) {
    std::string file = s.path;
    size_t k = 0;
    scanReference(s.path, file, k);
    files.push_back(file);
    if (extension(file) == ".png")
      sequences.insert(fs::path(file).parent_path().parent_path().string());
  }
  for (const std::string& dir : sequences)
    for (std::string& f : filesUnder(dir)) files.push_back(std::move(f));
  return files;
}

void preferIntensity(ConfFile& conf) {
  for (ConfScan& s : conf.scans) {
    if (s.ptx) s.ptx->intensity = true;
    if (s.e57) s.e57->intensity = true;
  }
}

void dropColourImages(ConfFile& conf) {
  for (ConfScan& s : conf.scans) s.colour.clear();
}

ConfFile splitIntoBands(const ConfFile& conf, uint64_t maxCells) {
  ConfFile out;
  out.warnings = conf.warnings;
  for (const ConfScan& s : conf.scans) {
    int bands = 1;
    if (s.ptx) bands = bandCount(s.ptx->cols, s.ptx->rows, maxCells);
    if (s.e57 && s.e57->rows > 0) bands = bandCount(s.e57->cols, s.e57->rows, maxCells);
    for (int b = 0; b < bands; ++b) {
      out.scans.push_back(s);
      out.scans.back().band = b;
      out.scans.back().bands = bands;
    }
  }
  return out;
}

RangeGrid readScanGrid(const ConfScan& scan, const InputLimits& limits) {
  if (scan.memory) {
    if (!scan.depth) return scan.memory->grid;
    RangeGrid g = depthGrid(scan.memory->depth, *scan.depth, scan.path);
    if (!scan.memory->colour.rgb.empty()) colourFromImage(g, scan.memory->colour, scan.path);
    return g;
  }
  if (scan.ptx) return readPtxScan(scan.path, *scan.ptx);
  if (scan.e57) return readE57Scan(scan.path, *scan.e57);
  if (scan.depth) {
    RangeGrid g = depthGrid(readDepthPng(scan.path, limits.maxGridCells), *scan.depth, scan.path);
    if (!scan.colour.empty())
      colourFromImage(g, readColourImage(scan.colour, limits.maxGridCells), scan.colour);
    return g;
  }
  return readRangeGridPly(scan.path, limits);
}

SensorKind sensorKindOf(const std::string& path) {
  const std::string file = path.substr(0, path.rfind('#'));  // a scan's name: FILE.ptx#K
  if (isPtx(file) || isE57(file)) return SensorKind::station;
  return extension(file) == ".png" ? SensorKind::camera : SensorKind::grid;
}

}  // namespace rangefuse::io
