#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>

#include "Commands.h"
#include "rangefuse/eval/MeshDistance.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/parallel/Mpi.h"

namespace po = boost::program_options;

namespace rangefuse::cli {
namespace {

struct EvalOptions {
  std::string mesh, reference;
  double voxel = 1;
  size_t samples = 200000;
};

void printRow(const char* name, const DistanceStats& s, double voxel) {
  std::printf("%-13s mean %.6g  median %.6g  p90 %.6g  p99 %.6g  max %.6g  (mean %.3f voxel)\n",
              name, s.mean, s.median, s.p90, s.p99, s.max, s.mean / voxel);
}

int run(const EvalOptions& o) {
  TriangleMesh mesh = io::readMeshPly(o.mesh), ref = io::readMeshPly(o.reference);
  DistanceStats acc = summarize(sampledDistances(mesh, ref, o.samples, 1));
  DistanceStats comp = summarize(sampledDistances(ref, mesh, o.samples, 2));
  std::printf("mesh %s (%zu triangles) against %s (%zu triangles), %zu samples each way\n",
              o.mesh.c_str(), mesh.faces.size(), o.reference.c_str(), ref.faces.size(), o.samples);
  printRow("accuracy", acc, o.voxel);
  printRow("completeness", comp, o.voxel);
  std::printf("chamfer       %.6g (%.3f voxel)\n", 0.5 * (acc.mean + comp.mean),
              0.5 * (acc.mean + comp.mean) / o.voxel);
  return 0;
}

}  // namespace

int evalCommand(int argc, char** argv, MPI_Comm comm) {
  EvalOptions o;
  po::options_description d("rangefuse eval: distances between a mesh and a reference mesh");
  d.add_options()("help,h", "show this help")("mesh", po::value(&o.mesh)->required(),
                                              "mesh to judge")(
      "reference", po::value(&o.reference)->required(), "reference mesh")(
      "voxel", po::value(&o.voxel)->default_value(1.0), "voxel size, to report in voxels")(
      "samples", po::value(&o.samples)->default_value(200000), "area-weighted samples per mesh");
  int code = 0;
  std::string error;
  if (mpi::rank(comm) == 0) {
    try {
      po::variables_map vm;
      po::store(po::parse_command_line(argc, argv, d), vm);
      if (vm.count("help")) {
        std::cout << d;
      } else {
        po::notify(vm);
        code = run(o);
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (!mpi::agree(error.empty(), error, comm)) return 1;
  return code;
}

}  // namespace rangefuse::cli
