#include "rangefuse/fuse/OutputChecks.h"

#include <filesystem>
#include <map>

#include "rangefuse/core/Error.h"
#include "rangefuse/io/MeshPartXdmf.h"
#include "rangefuse/io/OutputCheck.h"

namespace rangefuse {

void checkOutputs(const OutputSettings& o, int rank) {
  const std::string meshData = io::isXdmfPath(o.out) ? io::xdmfDataPath(o.out) : "";
  const std::vector<std::pair<std::string, std::string>> outputs = {
      {"mesh", o.out},
      {"mesh data", meshData},
      {"checkpoint", o.checkpoint},
      {"report", o.report},
      {"preview", o.preview},
      {"poses", o.posesOut},
      {"trajectory", o.trajectoryOut}};
  std::map<std::string, std::string> seen;
  for (const auto& [what, path] : outputs) {
    if (path.empty()) continue;
    const std::string key = std::filesystem::absolute(path).lexically_normal().string();
    if (seen.count(key))
      throw InputError(path + ": given as both the " + seen[key] + " and the " + what);
    seen[key] = what;
    if (rank == 0 || what == "mesh" || what == "mesh data" || what == "checkpoint")
      io::checkWritable(path, what);
  }
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
