// What a fuse run puts in a checkpoint, and what it checks before resuming from one.
#pragma once

#include <mpi.h>

#include "rangefuse/options/RunSettings.h"
#include "rangefuse/parallelio/Checkpoint.h"
#include "rangefuse/pipeline/FusedField.h"
#include "rangefuse/pipeline/LoadedScans.h"
#include "rangefuse/pipeline/RankCounters.h"

namespace rangefuse {

/// Collective: content hashes of the scan files, one per path (a file named twice is read
/// once; the ranks share the files), every rank getting them all.
std::vector<std::string> hashScans(const std::vector<std::string>& paths, MPI_Comm comm);

/// The checkpoint meta of a run at `progress` with the scans' current poses.
io::CheckpointMeta checkpointMeta(const RecordedParameters& recorded, const LoadedScans& scans,
                                  const std::vector<std::string>& hashes,
                                  const nlohmann::json& progress, const FusedField* field);

/// Fills the result-deciding options the user did not give from the checkpoint, and throws
/// InputError listing every given option that differs from the checkpoint's.
void adoptCheckpointParameters(const io::CheckpointMeta& meta, FuseOptions& options);

/// Throws InputError naming each scan whose file changed since the checkpoint.
void checkScanHashes(const io::CheckpointMeta& meta, const LoadedScans& scans,
                     const std::vector<std::string>& hashes);

}  // namespace rangefuse
