// Writing a synthetic scan set as a user's files: one range-grid PLY per scan and truth.conf.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/io/Conf.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/scan/SyntheticScanner.h"

namespace rangefuse::test {

/// Writes every scan of `set` into `dir` (which must exist) and a truth.conf with their poses.
inline void writeScanSet(const std::string& dir, const SyntheticSet& set) {
  std::vector<io::ConfScan> conf;
  for (const auto& sc : set.scans) {
    io::writeRangeGridPly(dir + "/" + sc.name, sc.grid, io::PlyEncoding::BinaryLittleEndian);
    conf.push_back({sc.name, dir + "/" + sc.name, sc.truth});
  }
  io::writeConf(dir + "/truth.conf", conf);
}

}  // namespace rangefuse::test
