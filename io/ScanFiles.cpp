#include "rangefuse/io/ScanFiles.h"

#include <filesystem>
#include <map>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/RangeGridPly.h"

namespace rangefuse::io {
namespace {

bool isPtx(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".ptx";
}

/// Splits "FILE.ptx#K" into the file and K (from 1); false for any other name.
bool ptxReference(const std::string& path, std::string& file, size_t& k) {
  const size_t hash = path.rfind('#');
  if (hash == std::string::npos || !isPtx(path.substr(0, hash))) return false;
  const std::string number = path.substr(hash + 1);
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos ||
      number.size() > 9)
    return false;
  file = path.substr(0, hash);
  k = std::stoul(number);
  return k >= 1;
}

/// The scans of every PTX file a .conf names, each file indexed once.
void locatePtxScans(ConfFile& conf, const std::string& confPath, const InputLimits& limits) {
  std::map<std::string, std::vector<PtxScan>> indexed;
  for (ConfScan& s : conf.scans) {
    std::string file;
    size_t k = 0;
    if (!ptxReference(s.path, file, k)) continue;
    auto it = indexed.find(file);
    if (it == indexed.end()) it = indexed.emplace(file, indexPtx(file, limits)).first;
    if (k > it->second.size())
      throw InputError(confPath + ": " + s.name + ": " + file + " holds only " +
                       std::to_string(it->second.size()) + " scans");
    s.path = file;
    s.ptx = it->second[k - 1];
  }
}

}  // namespace

ConfFile readScanList(const std::string& path, const InputLimits& limits) {
  if (!isPtx(path)) {
    ConfFile conf = readConf(path);
    locatePtxScans(conf, path, limits);
    return conf;
  }
  ConfFile list;
  const std::string name = std::filesystem::path(path).filename().string();
  const std::vector<PtxScan> scans = indexPtx(path, limits);
  for (size_t k = 0; k < scans.size(); ++k)
    list.scans.push_back({name + "#" + std::to_string(k + 1), path, scans[k].pose, scans[k]});
  return list;
}

RangeGrid readScanGrid(const ConfScan& scan, const InputLimits& limits) {
  if (scan.ptx) return readPtxScan(scan.path, *scan.ptx);
  return readRangeGridPly(scan.path, limits);
}

}  // namespace rangefuse::io
