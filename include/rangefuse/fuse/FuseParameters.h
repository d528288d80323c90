// Every fuse option described once: its command-line name, the key reports and checkpoints keep
// it under (unit in the name), its help, and the check of its value. The command line, the
// validation, the run report and the adoption of a checkpoint's parameters all read this table,
// and defaults come from FuseOptions' own initialisers.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "rangefuse/fuse/FuseJob.h"

namespace rangefuse {

/// Where an option's value lives in FuseOptions.
using OptionValue = std::variant<double*, float*, int*, bool*, std::string*, FieldMethod*,
                                 RegistrationMode*, RegistrationFieldMode*, RegistrationSolve*>;

/// Whether an option decides the result: kept in reports and checkpoints, and compared on
/// resume; kept in checkpoints only (the scan list, checked by hashes instead); or neither
/// (where outputs go, resources).
enum class Recorded { Result, CheckpointOnly, No };

/// Which part of a run an option sets: commands that only build a field (render) take the
/// input, field and resource groups; --help lists the groups in this order.
enum class OptionGroup { Input, Field, Output, Registration, Tracking, Checkpoint, Resources };

/// The heading --help gives a group.
const char* groupTitle(OptionGroup group);

/// True for the groups a command needs to build a field: input, field, resources.
bool buildsField(OptionGroup group);

struct FuseParameter {
  std::string option;  ///< command-line name, without "--"
  std::string key;     ///< report and checkpoint key (empty when not recorded)
  Recorded recorded = Recorded::No;
  bool required = false;  ///< has no default: --help shows none
  OptionGroup group = OptionGroup::Field;
  std::string help;
  std::function<OptionValue(FuseOptions&)> value;
  /// Empty when the value is acceptable, else what it must be ("must be ..."); may be null.
  std::function<std::string(const FuseOptions&)> check;
  /// The value an option given without one takes (empty: it needs a value).
  std::string implicitValue = {};
};

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
