#include <cstdio>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/scan/SyntheticScanner.h"

namespace po = boost::program_options;

namespace rangefuse::cli {
namespace {

struct PerturbOptions {
  std::string scans, out;
  io::ScanSourceOptions source;
  InputLimits limits;
  double voxel = 0, rotDeg = 5, transVox = 5;
  uint64_t seed = 1;
};

/// The centre of the bounding box of every scan's points in the world.
Eigen::Vector3d objectCentre(const io::ConfFile& conf, const InputLimits& limits) {
  Eigen::AlignedBox3d box;
  for (const auto& s : conf.scans)
    for (const auto& p : io::readScanGrid(s, limits).points) box.extend(s.pose.apply(p));
  if (box.isEmpty()) throw InputError("perturb: the scans hold no points");
  return box.center();
}

int run(const PerturbOptions& o) {
  if (!(o.voxel > 0)) throw InputError("perturb: --voxel must be positive");
  if (o.rotDeg < 0 || o.transVox < 0)
    throw InputError("perturb: --rot-deg and --trans-vox must not be negative");
  if (o.out.empty()) throw InputError("perturb: --out FILE.conf is required");
  io::FileRoles files;
  files.outputs = io::outputWithTemporary("perturbed list", o.out);
  for (std::string& f : io::scanListFiles(o.scans))
    files.inputs.push_back({"scan list's file", std::move(f)});
  io::refuseOverlaps(files);
  io::requireExtension(o.out, "perturbed list", {".conf"});
  io::ConfFile conf = io::readScanList(o.scans, o.limits, o.source);
  const Eigen::Vector3d centre = objectCentre(conf, o.limits);
  std::mt19937_64 rng(o.seed);
  for (size_t i = 1; i < conf.scans.size(); ++i) {  // the first scan stays: the anchor
    Eigen::Vector3d angles, shift;
    conf.scans[i].pose =
        perturbPose(conf.scans[i].pose, centre, o.rotDeg, o.transVox * o.voxel, rng, angles, shift);
  }
  io::writeConf(o.out, conf.scans);
  std::printf("perturb: %zu poses (all but the first) -> %s\n", conf.scans.size(), o.out.c_str());
  return 0;
}

}  // namespace

int perturbCommand(int argc, char** argv, MPI_Comm comm) {
  PerturbOptions o;
  po::options_description d(
      "rangefuse perturb: the scanner's pose perturbation applied to a .conf");
  auto add = d.add_options();
  add("help,h", "show this help");
  add("scans", po::value(&o.scans),
      "scan list (.conf, .ptx or sequence folder); its scans give the object centre");
  add("voxel", po::value(&o.voxel), "voxel size: the unit of --trans-vox");
  add("rot-deg", po::value(&o.rotDeg)->default_value(5.0), "max angle per axis, degrees");
  add("trans-vox", po::value(&o.transVox)->default_value(5.0), "max shift per axis, voxels");
  add("seed", po::value(&o.seed)->default_value(1), "random seed");
  add("out", po::value(&o.out), "perturbed .conf to write (scan names relative to its folder)");
  addSourceOptions(d, o.source, "--scans");
  addLimitOptions(d, o.limits, false);
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, d, vm,
      "rangefuse perturb --scans bun.conf --voxel 0.001 --out bun_perturbed.conf", "perturb", comm);
  if (parsed >= 0) return parsed;
  return runOnRoot(comm, [&] { return run(o); });
}

}  // namespace rangefuse::cli
