// The field methods and the registration modes, as enums: named only at the edges (command
// line, reports, checkpoints). Each method is a row of methodRegistry(), which says what the
// pipeline does with it, so a new method is added in one place.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/register/RegistrationMode.h"

namespace rangefuse {

enum class FieldMethod { Prism, Robust, Consensus, Naive };
enum class RegistrationFieldMode { Grow, Rebuild };

/// What the pipeline needs to know of a field method.
struct MethodInfo {
  FieldMethod id;
  const char* name;     ///< on the command line and in reports
  const char* summary;  ///< one line for --help
  /// Distances from closest-surface queries over routed triangles (else prism integration).
  bool closestSurface;
  /// Prism samples kept by agreement or free space (hypotheses, sight maps). Registration
  /// fields are closest-surface fields for closestSurface methods, prism fields otherwise.
  bool hypotheses;
};

/// Every method, in the order --help lists them.
const std::vector<MethodInfo>& methodRegistry();

/// The registry's row of a method.
const MethodInfo& methodInfo(FieldMethod method);

const char* toString(FieldMethod method);
const char* toString(RegistrationMode mode);
const char* toString(RegistrationFieldMode mode);
const char* toString(RegistrationSolve solve);

/// The enum named `text`; throws InputError naming `option` and the valid names.
FieldMethod parseFieldMethod(const std::string& option, const std::string& text);
RegistrationMode parseRegistrationMode(const std::string& option, const std::string& text);
RegistrationFieldMode parseRegistrationFieldMode(const std::string& option,
                                                 const std::string& text);
RegistrationSolve parseRegistrationSolve(const std::string& option, const std::string& text);

}  // namespace rangefuse
