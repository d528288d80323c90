#include "FuzzEntries.h"

#include <sstream>

#include "CliCommon.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"

namespace po = boost::program_options;

namespace rangefuse::fuzz {
InputLimits fuzzLimits() {
  InputLimits l;
  l.maxElements = 1 << 22;
  l.maxGridCells = 1 << 22;
  l.maxVoxels = 1 << 22;
  return l;
}

void rangeGridPly(const std::string& bytes) {
  refusedCleanly([&] { io::parseRangeGridPly("fuzz.ply", bytes, fuzzLimits()); });
}

void meshPly(const std::string& bytes) {
  refusedCleanly([&] { io::parseMeshPly("fuzz.ply", bytes, fuzzLimits()); });
}

void conf(const std::string& bytes) {
  std::istringstream in(bytes);
  refusedCleanly([&] { io::parseConf("dir/fuzz.conf", in); });
}

void fuseIni(const std::string& bytes) {
  FuseOptions o;
  po::options_description desc = cli::fuseOptions(o);
  std::istringstream in(bytes);
  try {
    po::variables_map vm;
    po::store(po::parse_config_file(in, desc), vm);
    po::notify(vm);
  } catch (const po::error&) {
    return;  // the tool prints these as option errors
  }
  refusedCleanly([&] { validateFuseOptions(o); });
}

Entry entryNamed(const std::string& name) {
  if (name == "range_grid_ply") return rangeGridPly;
  if (name == "mesh_ply") return meshPly;
  if (name == "conf") return conf;
  if (name == "fuse_ini") return fuseIni;
  if (name == "checkpoint") return checkpoint;
  if (name == "ptx") return ptx;
  if (name == "e57") return e57;
  if (name == "depth_png") return depthPng;
  if (name == "depth_sequence") return depthSequence;
  if (name == "colour_image") return colourImage;
  return nullptr;
}

}  // namespace rangefuse::fuzz
