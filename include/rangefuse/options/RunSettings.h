// The settings of one fuse run, by stage. The command's options are the stages' own settings
// structs (FuseParameters.h); runSettings adds what follows from them (lengths in the scans'
// units, resolved thread counts) once, at the top of runFuse.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/io/ScanFiles.h"
#include "rangefuse/options/FieldMethod.h"
#include "rangefuse/options/FieldSettings.h"
#include "rangefuse/options/OutputSettings.h"
#include "rangefuse/options/RegistrationSettings.h"
#include "rangefuse/options/StreamSettings.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

struct FuseOptions;

/// Reading: where the scans are and how each is prepared.
struct ReadSettings {
  std::string scans;             ///< .conf, .ptx or depth-sequence folder
  io::ScanSourceOptions source;  ///< how to read it (format, depth cameras)
  /// Set: the scan list itself (the library's frames, held in memory), read instead of `scans`.
  std::shared_ptr<const io::ConfFile> list;
  InputLimits limits;
  SurfaceOptions surface;  ///< merge target in the scans' units; sight maps for robust fusion
  double eps = 0;          ///< prism envelope, in the scans' units
  double voxel = 0;        ///< the field's voxel, checked against the scans' extent
  uint64_t bandCells = 0;  ///< PTX scans of more cells are read in bands of columns
  uint64_t keepBytes = 0;  ///< prepared scans a rank keeps between passes
  int threads = 1;         ///< threads of this rank
};

/// The mesh taken from the field.
/// How far (voxels) before what a scan saw a point must lie for carving to call it looked
/// through. A voxel, not --free-margin's envelope: the fill across a gap at a grazing angle
/// lies within this of where the views saw past it.
inline constexpr double kCarveMarginVoxels = 1;

struct MeshSettings {
  float minWeight = 0;  ///< voxels with summed weight not above this are unobserved
  bool normals = true;
  int threads = 1;
  bool fillHoles = false;  ///< carve unobserved voxels so the mesh closes (HoleFill)
  double carveMargin = 0;  ///< looked-through margin of the carving (scan units)
};

/// The options that decide the result, as reports and checkpoints record them.
struct RecordedParameters {
  nlohmann::json result;          ///< reports and checkpoints
  nlohmann::json checkpointOnly;  ///< checkpoints alone (checked by hashes instead)
};

/// Where a stage writes its checkpoints, how often, and what they record.
struct CheckpointWriting {
  std::string path;  ///< empty: none
  double every = 0;  ///< seconds between checkpoints of registration and tracking
  RecordedParameters recorded;
};

struct RunSettings {
  ReadSettings read;
  FieldSettings field;
  RegistrationSettings registration;
  StreamSettings track;
  MeshSettings mesh;
  OutputSettings outputs;
  RecordedParameters recorded;

  CheckpointWriting checkpoints() const {
    return {outputs.checkpoint, outputs.checkpointEvery, recorded};
  }
};

/// The settings of a run from checked options whose thread count is resolved.
RunSettings runSettings(const FuseOptions& options);

/// The surface options scans are prepared with: merging cells up to `mergeCells` voxels,
/// depths smoothed until their noise is about `smoothNoise` voxels, flat blocks joined within
/// `joinFlat` voxels, sight maps when the method judges by free space or holes are closed.
SurfaceOptions surfaceOptions(const FuseOptions& options);

}  // namespace rangefuse
