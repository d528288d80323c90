#include <cstdio>
#include <iostream>

#include "CliCommon.h"
#include "Commands.h"
#include "rangefuse/core/Error.h"
#include "rangefuse/io/DepthCamera.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/io/OutputOverlap.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/mesh/DistributedMesh.h"
#include "rangefuse/mesh/PartStitching.h"
#include "rangefuse/parallel/Mpi.h"
#include "rangefuse/parallel/Threads.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/parallelio/MeshPartPly.h"
#include "rangefuse/parallelio/MeshPartXdmf.h"
#include "rangefuse/pipeline/OutputChecks.h"

namespace po = boost::program_options;

namespace rangefuse::cli {
namespace {

/// Parses a checkpoint command's options, the checkpoint also as the first positional argument:
/// -1 to run, else the exit code (0 after --help, 2 on a bad command line, on every rank).
int parseWithCheckpoint(int argc, char** argv, const po::options_description& d,
                        const std::string& example, const std::string& command, MPI_Comm comm) {
  po::positional_options_description pos;
  pos.add("checkpoint", 1);
  po::variables_map vm;
  std::string error;
  bool help = false;
  try {
    po::store(po::command_line_parser(argc, argv).options(d).positional(pos).run(), vm);
    help = vm.count("help") > 0;
    if (!help) po::notify(vm);
  } catch (const po::unknown_option& e) {
    error = unknownOptionMessage(e, d);
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!mpi::agree(error.empty(), error + " (see 'rangefuse " + command + " --help')", comm))
    return 2;
  if (!help) return -1;
  if (mpi::rank(comm) == 0) std::cout << d << "\nExample:\n  " << example << "\n";
  return 0;
}

/// The mesh (and an XDMF mesh's data) checked against the checkpoint it is made from.
void refuseOverwrite(const std::string& checkpoint, const std::string& out) {
  OutputSettings written;
  written.out = out;
  io::FileRoles files;
  files.inputs = {{"checkpoint", checkpoint}};
  files.outputs = outputFiles(written);  // the mesh, an XDMF's data, their temporaries
  io::refuseOverlaps(files);
  for (const io::RolePath& f : files.outputs) io::checkWritable(f.path, f.role);
  io::requireExtension(out, "mesh", {".ply", ".xdmf"});
}

int meshFromCheckpoint(const std::string& path, const std::string& out, bool normals,
                       MPI_Comm comm) {
  io::CheckpointMeta meta;
  BrickLayout layout;
  std::unique_ptr<BrickStore> store;
  if (!mpi::collectively(comm, [&] {
        if (out.empty()) throw InputError("mesh: --out MESH.ply is required");
        refuseOverwrite(path, out);
        meta = io::readCheckpointMeta(path, comm);
        store = io::readCheckpointField(path, meta, layout, comm);
      }))
    return 1;
  const float minWeight = meta.parameters.value("min_weight", 0.0f);
  MeshPart part = extractDistributedMesh(*store, minWeight, comm, nullptr, threadsPerRank(comm));
  if (normals) addPartNormals(part, comm);
  if (!(io::isXdmfPath(out) ? io::writeMeshPartXdmf(out, part, comm)
                            : io::writeMeshPartPly(out, part, comm)))
    return 1;
  if (mpi::rank(comm) == 0)
    std::printf("mesh: %llu triangles from %zu bricks -> %s\n",
                static_cast<unsigned long long>(part.totalFaces), layout.totalBricks(),
                out.c_str());
  return 0;
}

/// Where the run stood, in words: what resuming from the checkpoint will do.
std::string progressText(const nlohmann::json& progress) {
  const std::string stage = progress.value("stage", "");
  if (stage == "field") return "finished field (resuming meshes it; 'rangefuse mesh' too)";
  if (stage == "registration" && progress.contains("registration")) {
    const nlohmann::json& r = progress["registration"];
    return "registration, " + r.value("phase", std::string("?")) + " phase, next scan " +
           std::to_string(r.value("next_scan", 0)) + ", round " +
           std::to_string(r.value("round", 0)) + " (resuming continues it)";
  }
  if (stage == "tracking" && progress.contains("tracking"))
    return "tracking, next frame " +
           std::to_string(progress["tracking"].value("next_frame", size_t{0}) + 1) +
           " (resuming continues the stream)";
  return progress.dump();
}

/// A scan's pose as its own kind of file writes it: a depth frame's camera-to-world pose as a
/// TUM trajectory line (t, then q as qx qy qz qw), any other scan's as its .conf line does
/// (the conjugate rotation, the Stanford convention).
std::string poseText(const std::string& name, const Pose& scanToWorld) {
  const bool frame = io::sensorKindOf(name) == io::SensorKind::camera;
  const Pose p = frame ? io::cameraPose(scanToWorld) : scanToWorld;
  const Eigen::Quaterniond q(frame ? p.R : Eigen::Matrix3d(p.R.transpose()));
  char text[160];
  std::snprintf(text, sizeof text, "t %.6g %.6g %.6g  q %.6g %.6g %.6g %.6g (%s)", p.t.x(), p.t.y(),
                p.t.z(), q.x(), q.y(), q.z(), q.w(),
                frame ? "camera to world, as a TUM trajectory" : "as a .conf line");
  return text;
}

void printInfo(const std::string& path, const io::CheckpointMeta& m) {
  std::printf("%s: rangefuse checkpoint, format version %d\n", path.c_str(), m.version);
  std::printf("progress:   %s\n", progressText(m.progress).c_str());
  std::printf("state:      %s\n", m.progress.dump().c_str());
  std::printf("parameters: %s\n", m.parameters.dump().c_str());
  std::printf("scans:      %zu\n", m.scanNames.size());
  for (size_t i = 0; i < m.scanNames.size(); ++i)
    std::printf("  %-24s hash %s  %s\n", m.scanNames[i].c_str(), m.scanHashes[i].c_str(),
                poseText(m.scanNames[i], m.poses[i]).c_str());
  if (m.hasField)
    std::printf("field:      voxel %.6g, bricks of %d^3, origin %.6g %.6g %.6g\n", m.grid.voxel,
                m.grid.brick, m.grid.origin.x(), m.grid.origin.y(), m.grid.origin.z());
  else
    std::printf("field:      none\n");
}

}  // namespace

int meshCommand(int argc, char** argv, MPI_Comm comm) {
  std::string path, out;
  bool normals = true;
  po::options_description d("rangefuse mesh: the stitched mesh of the field in a checkpoint");
  auto add = d.add_options();
  add("help,h", "show this help");
  add("checkpoint", po::value(&path), "HDF5 checkpoint (also the first positional argument)");
  add("out", po::value(&out),
      "mesh to write: .ply (binary), or .xdmf (HDF5 data in the same name .h5)");
  add("normals", po::value(&normals)->default_value(true, "true"),
      "write vertex normals (true or false)");
  const int parsed = parseWithCheckpoint(
      argc, argv, d, "mpirun -np 2 rangefuse mesh run.h5 --out mesh.ply", "mesh", comm);
  return parsed >= 0 ? parsed : meshFromCheckpoint(path, out, normals, comm);
}

int infoCommand(int argc, char** argv, MPI_Comm comm) {
  std::string path;
  po::options_description d(
      "rangefuse info: what a checkpoint holds: where the run stood, its parameters, scans and "
      "poses, the field's lattice");
  d.add_options()("help,h", "show this help")(
      "checkpoint", po::value(&path)->required(),
      "HDF5 checkpoint (also the first positional argument)");
  const int parsed =
      parseWithCheckpoint(argc, argv, d, "rangefuse info out/bunny.h5", "info", comm);
  if (parsed >= 0) return parsed;
  io::CheckpointMeta meta;
  if (!mpi::collectively(comm, [&] { meta = io::readCheckpointMeta(path, comm); })) return 1;
  if (mpi::rank(comm) == 0) printInfo(path, meta);
  return 0;
}

}  // namespace rangefuse::cli
