// The options of `rangefuse fuse`: the stages' own settings structs side by side (FuseOptions),
// and the table of every option, made of the stages' own tables (FieldSettings::settings() and
// the others) and the few the command adds. The command line, --help, .ini files, validation,
// the run report and the adoption of a checkpoint's parameters all read this table; defaults
// are the structs' own initialisers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rangefuse/core/Limits.h"
#include "rangefuse/core/Setting.h"
#include "rangefuse/io/ScanSourceOptions.h"
#include "rangefuse/options/FieldSettings.h"
#include "rangefuse/options/OutputSettings.h"
#include "rangefuse/options/RegistrationSettings.h"
#include "rangefuse/options/StreamSettings.h"
#include "rangefuse/surface/ScanSurface.h"

namespace rangefuse {

/// Every option of one fuse run, each stage's in that stage's own settings.
struct FuseOptions {
  std::string scans;             ///< .conf, .ptx or depth-sequence folder
  io::ScanSourceOptions source;  ///< how to read it (format, depth cameras)
  FieldSettings field;           ///< the field (maxVoxels comes from limits)
  SurfaceOptions surface;        ///< the targets and tolerance come from the three below
  double mergeCells = 1;         ///< merge grid cells up to this many voxels (0: never)
  double smoothNoise = 1;        ///< smooth depths noisier than this many voxels (0: never)
  double joinFlat = 0.05;        ///< join flat 2 x 2 blocks within this many voxels (0: never)
  double bandCells = 4e6;        ///< PTX scans of more cells are read in bands by several ranks
  float minWeight = 0.0f;        ///< voxels with summed weight not above this are unobserved
  bool normals = true;           ///< write vertex normals
  RegistrationSettings registration;
  StreamSettings stream;
  OutputSettings outputs;
  bool quiet = false;        ///< print nothing but warnings and errors
  bool verbose = false;      ///< print every registration fit and tracked frame
  InputLimits limits;        ///< refuse input that would need more memory than this
  double scanMemory = 1024;  ///< MiB of prepared scans a rank keeps between passes
  std::vector<std::string>
      givenOptions;  ///< options the user set (others may come from a checkpoint)
};

using FuseParameter = Setting<FuseOptions>;

/// The heading --help gives a group.
const char* groupTitle(OptionGroup group);

/// True for the groups a command needs to build a field: input, field, resources.
bool buildsField(OptionGroup group);

/// Every option of `rangefuse fuse` but the input limits (shared with other commands).
const std::vector<FuseParameter>& fuseParameters();

/// The value as JSON (enums by name).
nlohmann::json parameterJson(const FuseParameter& p, const FuseOptions& o);
/// Sets the value from JSON; throws InputError naming the option when it does not fit.
void setParameter(const FuseParameter& p, FuseOptions& o, const nlohmann::json& value);
/// Sets the value from command-line text; throws InputError naming the option.
void parseParameter(const FuseParameter& p, FuseOptions& o, const std::string& text);
/// The value as the command line writes it (the shortest text that reads back the same).
std::string parameterText(const FuseParameter& p, const FuseOptions& o);

/// Throws InputError naming the first option that is out of range.
void validateFuseOptions(const FuseOptions& options);

/// The options that decide the result, as JSON (run report, checkpoints).
nlohmann::json resultParameters(const FuseOptions& options);

}  // namespace rangefuse
