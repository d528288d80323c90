#include "rangefuse/fuse/FuseJob.h"

#include <algorithm>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/fuse/Progress.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/MeshPly.h"
#include "rangefuse/io/RangeGridPly.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/MarchingCubes.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/prism/PrismField.h"

namespace rangefuse {
namespace {

/// Runs fn; turns any exception into a collective failure reported once.
template <class Fn>
bool collectively(MPI_Comm comm, Fn&& fn) {
  std::string error;
  try {
    fn();
  } catch (const std::exception& e) {
    error = e.what();
  }
  return mpi::agree(error.empty(), error, comm);
}

std::vector<ScanSurface> readScans(const FuseOptions& o, bool root, size_t& triangles) {
  io::ConfFile conf = io::readConf(o.scans);
  if (root)
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
  std::vector<ScanSurface> scans;
  triangles = 0;
  for (const auto& s : conf.scans) {
    RangeGrid grid = io::readRangeGridPly(s.path);
    scans.push_back(buildScanSurface(grid, s.pose, o.surface));
    if (scans.back().triangles.empty() && root)
      std::fprintf(stderr, "rangefuse: warning: %s: no triangles survive the filters\n",
                   s.path.c_str());
    triangles += scans.back().triangles.size();
  }
  return scans;
}

std::string perRank(MPI_Comm comm, uint64_t value) {
  std::vector<uint64_t> all(mpi::size(comm));
  MPI_Gather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, comm);
  std::ostringstream s;
  for (size_t r = 0; r < all.size(); ++r) s << (r ? " / " : "") << all[r];
  return s.str();
}

void validate(const FuseOptions& o) {
  if (o.scans.empty()) throw InputError("--scans is required (a .conf file)");
  if (o.out.empty()) throw InputError("--out is required (the mesh .ply to write)");
  if (!(o.voxel > 0)) throw InputError("--voxel must be positive (in the scans' units)");
  if (!(o.envelope > 0)) throw InputError("--envelope must be positive (in voxels)");
  if (o.brick < 2 || o.brick > 64) throw InputError("--brick must be between 2 and 64");
  if (o.surface.normalPasses < 0) throw InputError("--normal-passes must be >= 0");
}

}  // namespace

int runFuse(const FuseOptions& o, MPI_Comm comm) {
  Progress progress(comm);
  const bool root = progress.isRoot();
  if (!collectively(comm, [&] { validate(o); })) return 1;
  std::vector<ScanSurface> scans;
  size_t triangles = 0;
  if (!collectively(comm, [&] { scans = readScans(o, root, triangles); })) return 1;
  progress.stage(
      "read", std::to_string(scans.size()) + " scans, " + std::to_string(triangles) + " triangles");

  const double eps = o.envelope * o.voxel;
  BrickLayout layout;
  if (!collectively(comm, [&] {
        layout = planBricks(scans, fitGrid(scans, o.voxel, o.brick, eps), eps, mpi::size(comm));
      }))
    return 1;
  BrickStore store(layout, mpi::rank(comm));
  progress.stage("bricks", std::to_string(layout.codes.size()) + " bricks of " +
                               std::to_string(o.brick) + "^3, per rank " +
                               perRank(comm, store.brickCount()));

  PrismIntegrator integrator(store, eps);
  uint64_t updates = 0;
  for (const auto& s : scans) updates += integrator.addScan(s).voxelUpdates;
  const std::string updated = perRank(comm, updates);
  progress.stage("field", "voxels updated per rank " + updated);

  MeshStats ms;
  TriangleMesh mesh = extractDistributedMesh(store, o.minWeight, comm, &ms);
  const std::string halo = perRank(comm, ms.haloBricksReceived);
  progress.stage("mesh", std::to_string(mesh.faces.size()) + " triangles, " +
                             std::to_string(mesh.vertices.size()) +
                             " vertices, halo bricks per rank " + halo);
  if (!collectively(comm, [&] {
        if (!root) return;
        if (o.normals) mesh.normals = vertexNormals(mesh);
        io::writeMeshPly(o.out, mesh);
      }))
    return 1;
  progress.stage("write", o.out);
  return 0;
}

}  // namespace rangefuse
