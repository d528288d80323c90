// HDF5 checkpoints, written and read collectively with parallel HDF5 (MPI-IO).
#pragma once

#include <mpi.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/Pose.h"
#include "rangefuse/volume/BrickStore.h"

namespace rangefuse::io {

constexpr int kCheckpointVersion = 2;  ///< 2: every dataset carries a checksum

/// Everything but the voxels: the same on every rank.
struct CheckpointMeta {
  int version = kCheckpointVersion;
  nlohmann::json parameters;            ///< the options that decide the result
  std::vector<std::string> scanNames;   ///< as in the .conf
  std::vector<std::string> scanHashes;  ///< FNV-1a 64 of each scan file, hex
  std::vector<Pose> poses;              ///< current poses
  nlohmann::json progress;              ///< stage and where in it (see docs/checkpoints.md)
  bool hasField = false;
  VoxelGrid grid;
};

/// Collective: writes meta and (when given) every rank's bricks to path.tmp, then renames it
/// to path, so an interrupted write never replaces a good checkpoint. Throws InputError.
void writeCheckpoint(const std::string& path, const CheckpointMeta& meta, const BrickStore* store,
                     MPI_Comm comm);

/// Collective: reads and checks the meta (format, version, shapes, sizes against limits).
/// Throws InputError naming the file and what is wrong.
CheckpointMeta readCheckpointMeta(const std::string& path, MPI_Comm comm,
                                  const InputLimits& limits = {});

/// Collective: the field of a checkpoint, re-partitioned over comm's ranks; each rank reads
/// only its own bricks.
std::unique_ptr<BrickStore> readCheckpointField(const std::string& path, const CheckpointMeta& meta,
                                                BrickLayout& layout, MPI_Comm comm);

/// FNV-1a 64 of a file's bytes, as 16 hex digits; throws InputError if unreadable.
std::string fileHash(const std::string& path);

}  // namespace rangefuse::io
