#include "rangefuse/fuse/FuseJob.h"

#include <sys/resource.h>

#include <algorithm>
#include <sstream>

#include "rangefuse/core/Error.h"
#include "rangefuse/fuse/Progress.h"
#include "rangefuse/fuse/ScanLoader.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/MeshPly.h"
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

void warnEmptyScans(const io::ConfFile& conf, const std::vector<PrismScan>& scans) {
  for (size_t i = 0; i < scans.size(); ++i)
    if (scans[i].surface.triangles.empty())
      std::fprintf(stderr, "rangefuse: warning: %s: no triangles survive the filters\n",
                   conf.scans[i].path.c_str());
}

size_t countTriangles(const std::vector<PrismScan>& scans) {
  size_t n = 0;
  for (const auto& s : scans) n += s.surface.triangles.size();
  return n;
}

std::string perRank(MPI_Comm comm, uint64_t value) {
  std::vector<uint64_t> all(mpi::size(comm));
  MPI_Gather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, comm);
  std::ostringstream s;
  for (size_t r = 0; r < all.size(); ++r) s << (r ? " / " : "") << all[r];
  return s.str();
}

uint64_t peakMemoryMiB() {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return static_cast<uint64_t>(u.ru_maxrss) / 1024;  // ru_maxrss is in KiB on Linux
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
  const double eps = o.envelope * o.voxel;
  io::ConfFile conf;
  IndexedScans mine;
  if (!collectively(comm, [&] {
        conf = io::readConf(o.scans);
        mine = loadScanShare(conf, o.surface, eps, mpi::rank(comm), mpi::size(comm));
      }))
    return 1;
  const std::vector<PrismScan> scans = shareScans(mine, conf.scans.size(), comm);
  mine.clear();
  if (root) {
    for (const auto& w : conf.warnings) std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
    warnEmptyScans(conf, scans);
  }
  progress.stage("read", std::to_string(scans.size()) + " scans, " +
                             std::to_string(countTriangles(scans)) + " triangles");

  BrickLayout layout;
  if (!collectively(comm, [&] {
        layout = planBricks(scans, fitGrid(scans, o.voxel, o.brick, eps), mpi::size(comm));
      }))
    return 1;
  BrickStore store(layout, mpi::rank(comm));
  progress.stage("bricks", std::to_string(layout.codes.size()) + " bricks of " +
                               std::to_string(o.brick) + "^3, per rank " +
                               perRank(comm, store.brickCount()));

  PrismIntegrator integrator(store);
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
  progress.stage("done", "peak memory per rank (MiB) " + perRank(comm, peakMemoryMiB()));
  return 0;
}

}  // namespace rangefuse
