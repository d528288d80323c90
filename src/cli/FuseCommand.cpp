#include <boost/program_options.hpp>
#include <fstream>
#include <iostream>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/fuse/FuseJob.h"
#include "rangefuse/parallel/Mpi.h"

namespace po = boost::program_options;

namespace rangefuse::cli {

void addFieldOptions(po::options_description& d, FuseOptions& o) {
  d.add_options()("help,h", "show this help")(
      "config", po::value<std::string>(),
      "read options from an .ini file (key = value, same names)")(
      "scans", po::value(&o.scans), "scan list (.conf, Stanford bmesh lines)")(
      "voxel", po::value(&o.voxel), "voxel size, in the scans' units")(
      "envelope", po::value(&o.envelope)->default_value(3.0), "prism half-thickness, voxels")(
      "brick", po::value(&o.brick)->default_value(8), "voxels per brick edge")(
      "min-weight", po::value(&o.minWeight)->default_value(0.0f),
      "voxels whose summed confidence is not above this are unobserved")(
      "normal-passes", po::value(&o.surface.normalPasses)->default_value(2),
      "neighbour-averaging passes over vertex normals")(
      "max-edge", po::value(&o.surface.maxEdgeFactor)->default_value(4.0),
      "drop scan triangles with an edge longer than this x grid spacing")(
      "min-cosine", po::value(&o.surface.minCosine)->default_value(0.15),
      "drop scan triangles whose normal makes a cosine below this with the view ray");
}

namespace {

po::options_description fuseOptions(FuseOptions& o) {
  po::options_description d("rangefuse fuse: fuse range scans into one mesh");
  d.add_options()("out", po::value(&o.out), "output mesh (.ply, binary)")(
      "report", po::value(&o.report),
      "write a JSON run report (stage times, counts, memory per rank)")(
      "preview", po::value(&o.preview), "write a ray-cast PNG picture of the fused field")(
      "normals", po::value(&o.normals)->default_value(true), "write vertex normals");
  addFieldOptions(d, o);
  return d;
}

}  // namespace

int fuseCommand(int argc, char** argv, MPI_Comm comm) {
  FuseOptions o;
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, fuseOptions(o), vm,
      "mpirun -np 2 rangefuse fuse --scans bun.conf --voxel 0.001 --out bunny.ply", "fuse", comm);
  return parsed >= 0 ? parsed : runFuse(o, comm);
}

}  // namespace rangefuse::cli
