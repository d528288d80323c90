#include "rangefuse/pipeline/Checkpointing.h"

#include <algorithm>
#include <map>
#include <set>

#include "rangefuse/core/Error.h"
#include "rangefuse/options/FuseParameters.h"
#include "rangefuse/parallel/Mpi.h"

namespace rangefuse {
namespace {

bool given(const FuseOptions& o, const std::string& option) {
  return std::find(o.givenOptions.begin(), o.givenOptions.end(), option) != o.givenOptions.end();
}

/// Options added after checkpoints were first written, with the value the runs before them had.
const std::pair<const char*, const char*> kBeforeTheOption[] = {
    {"merge-cells", "0"},             // unmerged grids
    {"smooth-noise", "0"},            // depths as read
    {"join-flat", "0"},               // every cell's own triangles
    {"depth-normal-passes", "-1"},    // depth frames' normals as every scan's
    {"min-views", "1"},               // the quorum alone
    {"register-solve", "per-scan"}};  // per-scan fits

}  // namespace

std::vector<std::string> hashScans(const std::vector<std::string>& paths, MPI_Comm comm) {
  // Each file once, however many scans it holds (a PTX file of six stations is not read six
  // times), every size-th file on each rank; hashes and errors are gathered by everyone, so all
  // ranks throw the same first error (reported once by the caller) or agree on the hashes.
  std::vector<std::string> files;
  std::map<std::string, size_t> fileOf;
  for (const auto& p : paths)
    if (fileOf.emplace(p, files.size()).second) files.push_back(p);
  const int me = mpi::rank(comm), n = mpi::size(comm);
  std::map<size_t, std::string> mine;
  for (size_t i = me; i < files.size(); i += n) {
    try {
      mine[i] = io::fileHash(files[i]);
    } catch (const std::exception& e) {
      mine[i] = std::string("!") + e.what();
    }
  }
  std::vector<std::string> hashes(files.size());
  for (auto& [i, h] : mpi::gatherIndexed(mine, -1, comm)) hashes[i] = std::move(h);
  for (const auto& h : hashes)
    if (!h.empty() && h[0] == '!') throw InputError(h.substr(1));
  std::vector<std::string> out;
  for (const auto& p : paths) out.push_back(hashes[fileOf.at(p)]);
  return out;
}

io::CheckpointMeta checkpointMeta(const RecordedParameters& recorded, const LoadedScans& scans,
                                  const std::vector<std::string>& hashes,
                                  const nlohmann::json& progress, const FusedField* field) {
  io::CheckpointMeta m;
  m.parameters = recorded.result;
  for (const auto& [key, value] : recorded.checkpointOnly.items()) m.parameters[key] = value;
  m.scanNames = scans.names;
  m.scanHashes = hashes;
  m.poses = scans.poses;
  m.progress = progress;
  m.hasField = field != nullptr;
  if (field) m.grid = field->layout.grid;
  return m;
}

void adoptCheckpointParameters(const io::CheckpointMeta& meta, FuseOptions& o) {
  const nlohmann::json mine = resultParameters(o);
  std::vector<std::string> differ;
  // A checkpoint written before an option existed was written as its value here says.
  for (const FuseParameter& p : fuseParameters())
    for (const auto& [option, before] : kBeforeTheOption)
      if (p.option == option && !meta.parameters.contains(p.key) && !given(o, p.option))
        parseParameter(p, o, before);
  for (const FuseParameter& p : fuseParameters()) {
    if (p.recorded == Recorded::No || !meta.parameters.contains(p.key)) continue;
    const nlohmann::json& theirs = meta.parameters[p.key];
    if (!given(o, p.option)) {
      setParameter(p, o, theirs);
    } else if (p.recorded == Recorded::Result && mine[p.key] != theirs) {
      differ.push_back("--" + p.option + " " + mine[p.key].dump() +
                       " (checkpoint: " + theirs.dump() + ")");
    }
  }
  if (differ.empty()) return;
  std::string msg = "--resume " + o.outputs.resume + ": parameters differ from the checkpoint's:";
  for (const auto& d : differ) msg += " " + d + ";";
  throw InputError(msg + " leave them out to take the checkpoint's");
}

void checkScanHashes(const io::CheckpointMeta& meta, const LoadedScans& scans,
                     const std::vector<std::string>& hashes) {
  std::string changed;
  if (meta.scanNames != scans.names)
    throw InputError("--resume: the scan list differs from the checkpoint's (" +
                     std::to_string(meta.scanNames.size()) + " scans there, " +
                     std::to_string(scans.names.size()) + " here)");
  for (size_t i = 0; i < hashes.size(); ++i)
    if (hashes[i] != meta.scanHashes[i]) changed += " " + scans.paths[i];
  if (!changed.empty())
    throw InputError("--resume: input files changed since the checkpoint:" + changed);
}

}  // namespace rangefuse
