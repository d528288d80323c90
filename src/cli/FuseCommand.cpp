#include <boost/program_options.hpp>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/fuse/FuseJob.h"

namespace po = boost::program_options;

namespace rangefuse::cli {

void addFieldOptions(po::options_description& d, FuseOptions& o) {
  auto add = d.add_options();
  add("help,h", "show this help");
  add("config", po::value<std::string>(),
      "read options from an .ini file (key = value, same names)");
  add("scans", po::value(&o.scans), "scan list (.conf, Stanford bmesh lines)");
  add("voxel", po::value(&o.voxel), "voxel size, in the scans' units");
  add("method", po::value(&o.method)->default_value("prism"),
      "field: prism (Tubic et al.), robust (prism samples kept by agreement or free space: "
      "docs/robust.md), consensus (Wheeler et al.) or naive (closest surface)");
  add("envelope", po::value(&o.envelope)->default_value(3.0), "prism half-thickness, voxels");
  add("quorum", po::value(&o.quorum)->default_value(-1),
      "consensus: summed confidence a consensus surface needs (-1: 2.25 x views / 48)");
  add("min-views", po::value(&o.minViews)->default_value(2),
      "consensus and robust: views a surface needs besides the quorum, so that one view alone "
      "never passes where few views make the quorum small (1: the quorum alone)");
  add("edge-angle", po::value(&o.edgeAngle)->default_value(78),
      "consensus: a point whose offset from its surface point is more than this many degrees "
      "from the normal lies beside an open edge and stays unobserved (90: off)");
  add("same-distance", po::value(&o.sameDistance)->default_value(2.0),
      "consensus and robust: observations within this many voxels may be the same surface");
  add("same-angle", po::value(&o.sameAngle)->default_value(45.0),
      "consensus and robust: ... if their normals differ by at most this many degrees");
  add("free-margin", po::value(&o.freeMargin)->default_value(-1),
      "robust: an image looked through a point lying more than this many voxels before what it "
      "saw along its line of sight (-1: the envelope; inf: free space off, so a surface fewer than "
      "--min-views images saw never stands)");
  add("brick", po::value(&o.brick)->default_value(8), "voxels per brick edge");
  add("min-weight", po::value(&o.minWeight)->default_value(0.0f),
      "voxels whose summed confidence is not above this are unobserved");
  add("merge-cells", po::value(&o.mergeCells)->default_value(1.0),
      "merge blocks of k x k range-grid cells while k cells span at most this many voxels, "
      "so dense scans cost what the voxels need (0: never merge)");
  add("normal-passes", po::value(&o.surface.normalPasses)->default_value(2),
      "neighbour-averaging passes over vertex normals");
  add("max-edge", po::value(&o.surface.maxEdgeFactor)->default_value(4.0),
      "drop scan triangles with an edge longer than this x grid spacing");
  add("min-cosine", po::value(&o.surface.minCosine)->default_value(0.15),
      "drop scan triangles whose normal makes a cosine below this with the view ray");
  add("scan-memory", po::value(&o.scanMemory)->default_value(1024),
      "MiB of prepared scans a rank keeps between reading and fusing; scans past it are read "
      "again (prism fields without registration stream their scans)");
  add("threads", po::value(&o.threads)->default_value(0),
      "threads per rank for reading scans and adding them to the field (0: the CPUs the rank "
      "may run on, shared among the ranks on its node); any count gives the same bits");
  addLimitOptions(d, o.limits);
}

void addLimitOptions(po::options_description& d, InputLimits& limits) {
  auto add = d.add_options();
  add("max-elements", po::value(&limits.maxElements)->default_value(limits.maxElements),
      "refuse a PLY element (vertices, faces, cells) or checkpoint metadata larger than this");
  add("max-grid-cells", po::value(&limits.maxGridCells)->default_value(limits.maxGridCells),
      "refuse a range grid with more num_cols x num_rows cells than this");
  add("max-voxels", po::value(&limits.maxVoxels)->default_value(limits.maxVoxels),
      "refuse a field that needs more voxels than this, all ranks together (~40 bytes each)");
}

po::options_description fuseOptions(FuseOptions& o) {
  po::options_description d("rangefuse fuse: fuse range scans into one mesh");
  auto add = d.add_options();
  add("out", po::value(&o.out),
      "output mesh: .ply (binary), or .xdmf (HDF5 data in the same name .h5, for ParaView)");
  add("report", po::value(&o.report), "write a JSON run report (stage times, counts, memory)");
  add("preview", po::value(&o.preview), "write a ray-cast PNG picture of the fused field");
  add("normals", po::value(&o.normals)->default_value(true), "write vertex normals");
  add("register", po::value(&o.registration)->default_value("none"),
      "refine poses against the field: none, incremental (Algorithm 1), simultaneous "
      "(Algorithm 2) or both (1 then 2)");
  add("anchor", po::value(&o.anchor), "registration: scan name that stays fixed (default: first)");
  add("control-stride", po::value(&o.controlStride)->default_value(1),
      "registration: every k-th scan vertex is a control point");
  add("max-iterations", po::value(&o.maxIterations)->default_value(100),
      "registration: fits per scan (Algorithm 1) or per field rebuild (Algorithm 2)");
  add("max-rounds", po::value(&o.maxRounds)->default_value(8),
      "registration: field rebuilds in Algorithm 2");
  add("round-tolerance", po::value(&o.roundTolerance)->default_value(0.1),
      "registration: Algorithm 2 ends after a round that moves no scan's vertices this far on "
      "average, voxels");
  add("register-field", po::value(&o.registerField)->default_value("grow"),
      "registration: grow (Algorithm 1 adds each scan to one field; prism only) or rebuild (a "
      "new field for every scan: the simple method, for comparison)");
  add("poses-out", po::value(&o.posesOut), "write the refined poses (.conf)");
  add("checkpoint", po::value(&o.checkpoint), "write an HDF5 checkpoint of the field (.h5)");
  add("checkpoint-every", po::value(&o.checkpointEvery)->default_value(0.0),
      "seconds between registration checkpoints (0: after every scan / iteration)");
  add("resume", po::value(&o.resume),
      "continue from a checkpoint; options left out come from it, given ones must match");
  addFieldOptions(d, o);
  return d;
}

int fuseCommand(int argc, char** argv, MPI_Comm comm) {
  FuseOptions o;
  po::variables_map vm;
  const int parsed = parseCollectively(
      argc, argv, fuseOptions(o), vm,
      "mpirun -np 2 rangefuse fuse --scans bun.conf --voxel 0.001 --out bunny.ply", "fuse", comm);
  if (parsed >= 0) return parsed;
  for (const auto& [name, value] : vm)
    if (!value.defaulted()) o.givenOptions.push_back(name);
  return runFuse(o, comm);
}

}  // namespace rangefuse::cli
