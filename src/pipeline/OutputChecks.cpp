#include "rangefuse/pipeline/OutputChecks.h"

#include <filesystem>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/OutputCheck.h"
#include "rangefuse/parallelio/MeshPartXdmf.h"

namespace rangefuse {
namespace {

/// One file a run may write: its role, path and the extensions its writer produces.
struct NamedOutput {
  std::string role, path;
  std::vector<std::string> extensions;
};

std::vector<NamedOutput> namedOutputs(const OutputSettings& o) {
  const std::string meshData = io::isXdmfPath(o.out) ? io::xdmfDataPath(o.out) : "";
  return {{"mesh", o.out, {".ply", ".xdmf"}},
          {"mesh data", meshData, {".h5"}},
          {"checkpoint", o.checkpoint, {".h5", ".hdf5"}},
          {"report", o.report, {".json"}},
          {"preview", o.preview, {".png"}},
          {"poses", o.posesOut, {".conf"}},
          {"trajectory", o.trajectoryOut, {".txt", ".log"}}};
}

/// Every file the run reads; the checkpoint resumed only when another file is written over it
/// (the same file is updated by renames, as jobs/run_resumable.sh relies on).
std::vector<io::RolePath> inputFiles(const RunSettings& s) {
  const OutputSettings& o = s.outputs;
  std::vector<io::RolePath> files = {{"options file", o.config}};
  if (!o.resume.empty() && !(!o.checkpoint.empty() && io::sameFile(o.checkpoint, o.resume)))
    files.push_back({"checkpoint resumed", o.resume});
  if (!s.read.scans.empty())
    for (std::string& f : io::scanListFiles(s.read.scans))
      files.push_back({f == s.read.scans ? "scan list" : "scan list's file", std::move(f)});
  return files;
}

/// A camera trajectory is the path of depth frames: of range grids or stations there is none.
void refuseTrajectoryOfScans(const RunSettings& s) {
  std::error_code ec;
  if (s.outputs.trajectoryOut.empty() || std::filesystem::is_directory(s.read.scans, ec)) return;
  throw InputError(s.outputs.trajectoryOut + ": --trajectory-out writes a depth-image folder's " +
                   "camera path, and " + s.read.scans +
                   " is a scan list (--poses-out writes its scans' poses as a .conf)");
}

void refuseOldCheckpoint(const OutputSettings& o) {
  std::error_code ec;
  if (o.checkpoint.empty() || o.overwrite || !std::filesystem::exists(o.checkpoint, ec) ||
      (!o.resume.empty() && io::sameFile(o.checkpoint, o.resume)))
    return;
  throw InputError(o.checkpoint + ": the checkpoint exists; continue it with --resume " +
                   o.checkpoint + ", or give --overwrite to start again over it");
}

}  // namespace

std::vector<io::RolePath> outputFiles(const OutputSettings& o) {
  std::vector<io::RolePath> files;
  for (const NamedOutput& n : namedOutputs(o))
    for (io::RolePath& f : io::outputWithTemporary(n.role, n.path)) files.push_back(std::move(f));
  return files;
}

void checkOutputs(const RunSettings& s, int rank) {
  const OutputSettings& o = s.outputs;
  // An output over an input first: of all the faults, the one that would destroy data.
  io::FileRoles files{outputFiles(o), inputFiles(s), {}};
  if (s.track.follow) files.watched.push_back({"followed folder", s.read.scans});
  io::refuseOverlaps(files);
  refuseOldCheckpoint(o);
  refuseTrajectoryOfScans(s);
  for (const io::RolePath& f : files.outputs) {
    const bool everyRank = f.role == "mesh" || f.role == "mesh data" || f.role == "checkpoint";
    if (f.role.rfind("temporary", 0) != 0 && (rank == 0 || everyRank))
      io::checkWritable(f.path, f.role);
  }
  for (const NamedOutput& n : namedOutputs(o))
    if (!n.path.empty()) io::requireExtension(n.path, n.role, n.extensions);
}

std::vector<std::string> storageWarnings(const OutputSettings& o, bool normals,
                                         const BrickLayout& layout) {
  const uint64_t B = layout.grid.brick, bricks = layout.totalBricks();
  const uint64_t checkpoint = bricks * B * B * B * 24;
  const uint64_t faces = 2 * B * B * bricks;
  const uint64_t mesh = faces * 13 + faces / 2 * (normals ? 24 : 12);
  std::vector<std::string> warnings;
  for (const auto& w :
       {o.checkpoint.empty() ? "" : io::spaceWarning(o.checkpoint, checkpoint, "checkpoint"),
        o.out.empty() ? "" : io::spaceWarning(o.out, mesh, "mesh")})
    if (!w.empty()) warnings.push_back(w);
  return warnings;
}

}  // namespace rangefuse
