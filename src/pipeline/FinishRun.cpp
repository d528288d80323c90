#include "rangefuse/pipeline/FinishRun.h"

#include "PreviewView.h"
#include "RunReport.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/Conf.h"
#include "rangefuse/io/Png.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallelio/MeshPartPly.h"
#include "rangefuse/parallelio/MeshPartXdmf.h"
#include "rangefuse/pipeline/Checkpointing.h"
#include "rangefuse/pipeline/OutputChecks.h"
#include "rangefuse/pipeline/RunLines.h"
#include "rangefuse/render/MeshPicture.h"
#include "rangefuse/robust/SpaceCarving.h"

namespace rangefuse::internal {
namespace {

using mpi::collectively;

bool writeOutputs(const OutputSettings& o, const MeshSettings& m, MPI_Comm comm,
                  const LoadedScans& scans, MeshPart& mesh) {
  if (m.normals) addPartNormals(mesh, comm);
  const bool written = io::isXdmfPath(o.out) ? io::writeMeshPartXdmf(o.out, mesh, comm)
                                             : io::writeMeshPartPly(o.out, mesh, comm);
  if (!written) return false;
  if (o.preview.empty()) return true;
  const Image picture =
      pictureOfMesh(mesh, previewView(o.previewView, o.up, scans, mesh, comm), 0, comm);
  return collectively(comm, [&] {
    if (mpi::rank(comm) == 0) io::writePng(o.preview, picture);
  });
}

bool writePoses(const std::string& path, MPI_Comm comm, const LoadedScans& scans) {
  if (path.empty()) return true;
  return collectively(comm, [&] {
    if (mpi::rank(comm) != 0) return;
    std::vector<io::ConfScan> out;
    for (size_t i = 0; i < scans.names.size(); ++i)
      out.push_back({scans.names[i], scans.paths[i], scans.poses[i]});
    io::writeConf(path, out);
  });
}

/// Every file the write stage leaves: the mesh (and an XDMF mesh's HDF5 data), the preview, the
/// poses and the trajectory.
std::string writtenFiles(const OutputSettings& o) {
  std::string files = o.out;
  for (const std::string& f : {io::isXdmfPath(o.out) ? io::xdmfDataPath(o.out) : std::string(),
                               o.preview, o.posesOut, o.trajectoryOut})
    if (!f.empty()) files += ", " + f;
  return files;
}

/// ", of them N closing holes (area A)" with --fill-holes.
std::string filledLine(const MeshPart& mesh) {
  if (!mesh.marksFilled) return "";
  char area[32];
  std::snprintf(area, sizeof area, "%.4g", mesh.filledArea);
  return ", " + std::to_string(mesh.filledFaces) + " of them closing holes (area " + area + ")";
}

}  // namespace

std::function<void(const BrickLayout&)> storageWarner(const RunSettings& s, MPI_Comm comm) {
  return [outputs = s.outputs, normals = s.mesh.normals, comm](const BrickLayout& layout) {
    if (mpi::rank(comm) != 0) return;
    for (const std::string& w : storageWarnings(outputs, normals, layout))
      std::fprintf(stderr, "rangefuse: warning: %s\n", w.c_str());
  };
}

bool writeFieldCheckpoint(const CheckpointWriting& c, MPI_Comm comm, Progress& progress,
                          const LoadedScans& scans, const FusedField& field) {
  if (c.path.empty()) return true;
  if (!collectively(comm, [&] {
        const std::vector<std::string> hashes = hashScans(scans.paths, comm);
        io::writeCheckpoint(c.path,
                            checkpointMeta(c.recorded, scans, hashes, {{"stage", "field"}}, &field),
                            field.store.get(), comm);
      }))
    return false;
  progress.stage("checkpoint", c.path);
  return true;
}

MeshPart meshField(const MeshSettings& m, MPI_Comm comm, const FusedField& field, MeshStats& ms) {
  mpi::collectivelyOrThrow(comm, [&] {
    if (m.fillHoles && field.sights.empty())
      throw InputError("--fill-holes: this run has no sight maps to carve with");
  });
  const SpaceCarving carving(field.sights, m.carveMargin);
  const HoleFill fill{
      [&](const Eigen::AlignedBox3d& box, const std::vector<Eigen::Vector3d>& points) {
        return carving.inside(box, points);
      },
      static_cast<float>(field.layout.grid.voxel)};
  return extractDistributedMesh(*field.store, m.minWeight, comm, &ms, m.threads,
                                m.fillHoles ? &fill : nullptr);
}

int finish(const RunSettings& s, MPI_Comm comm, Progress& progress, const LoadedScans& scans,
           FusedField& field, RankCounters& counters, const std::vector<RegistrationStep>& steps) {
  const OutputSettings& o = s.outputs;
  MeshStats ms;
  MeshPart mesh;
  try {
    mesh = meshField(s.mesh, comm, field, ms);
  } catch (const mpi::Reported&) {
    return 1;
  }
  counters.haloBricks = ms.haloBricksReceived;
  counters.triangles = ms.localTriangles;
  progress.stage("mesh", std::to_string(mesh.totalFaces) + " triangles, " +
                             std::to_string(mesh.totalVertices) + " vertices" + filledLine(mesh) +
                             ", halo bricks per rank " + perRank(comm, ms.haloBricksReceived));
  if (!writeOutputs(o, s.mesh, comm, scans, mesh) || !writePoses(o.posesOut, comm, scans)) return 1;
  progress.stage("write", writtenFiles(o));
  progress.stage("done", "peak memory per rank (MiB) " + perRank(comm, peakMemoryMiB()));
  if (o.report.empty()) return 0;
  if (!collectively(comm, [&] { writeRunReport(s, comm, progress, counters, field, mesh, steps); }))
    return 1;
  progress.stage("report", o.report);
  return 0;
}

}  // namespace rangefuse::internal
