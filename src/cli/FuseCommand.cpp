#include <boost/program_options.hpp>
#include <fstream>
#include <iostream>

#include "Commands.h"
#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/parallel/Mpi.h"

namespace po = boost::program_options;

namespace rangefuse::cli {
namespace {

po::options_description fuseOptions(FuseOptions& o, std::string& config) {
  po::options_description d("rangefuse fuse: fuse range scans into one mesh");
  d.add_options()("help,h", "show this help")(
      "config", po::value(&config), "read options from an .ini file (key = value, same names)")(
      "scans", po::value(&o.scans), "scan list (.conf, Stanford bmesh lines)")(
      "out", po::value(&o.out), "output mesh (.ply, binary)")("voxel", po::value(&o.voxel),
                                                              "voxel size, in the scans' units")(
      "envelope", po::value(&o.envelope)->default_value(3.0), "prism half-thickness, voxels")(
      "brick", po::value(&o.brick)->default_value(8), "voxels per brick edge")(
      "min-weight", po::value(&o.minWeight)->default_value(0.0f),
      "voxels whose summed confidence is not above this are unobserved")(
      "normal-passes", po::value(&o.surface.normalPasses)->default_value(2),
      "neighbour-averaging passes over vertex normals")(
      "max-edge", po::value(&o.surface.maxEdgeFactor)->default_value(4.0),
      "drop scan triangles with an edge longer than this x grid spacing")(
      "min-cosine", po::value(&o.surface.minCosine)->default_value(0.15),
      "drop scan triangles whose normal makes a cosine below this with the view ray")(
      "normals", po::value(&o.normals)->default_value(true), "write vertex normals");
  return d;
}

/// Parses command line then config file (command line wins); false after --help.
bool parse(int argc, char** argv, FuseOptions& o) {
  std::string config;
  po::options_description desc = fuseOptions(o, config);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(desc).run(), vm);
  if (vm.count("help")) {
    if (mpi::rank() == 0)
      std::cout << desc
                << "\nExample:\n  mpirun -np 2 rangefuse fuse --scans bun.conf --voxel 0.001 --out "
                   "bunny.ply\n";
    return false;
  }
  if (vm.count("config")) {
    const std::string path = vm["config"].as<std::string>();
    std::ifstream in(path);
    if (!in) throw po::error(path + ": cannot open config file");
    po::store(po::parse_config_file(in, desc), vm);
  }
  po::notify(vm);
  return true;
}

}  // namespace

int fuseCommand(int argc, char** argv, MPI_Comm comm) {
  FuseOptions o;
  std::string error;
  bool run = false;
  try {
    run = parse(argc, argv, o);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi::agree(error.empty(), error + " (see 'rangefuse fuse --help')", comm)) return 2;
  return run ? runFuse(o, comm) : 0;
}

}  // namespace rangefuse::cli
