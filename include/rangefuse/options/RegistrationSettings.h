// Registration's settings (--register and its fits), each described once (settings()).
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Setting.h"
#include "rangefuse/options/FieldMethod.h"

namespace rangefuse {

/// Registration of the scans against the field (--register) and its fits.
struct RegistrationSettings {
  RegistrationMode mode = RegistrationMode::None;
  std::string anchor;           ///< scan name that fixes the frame (empty: the first)
  int controlStride = 1;        ///< every k-th scan vertex is a control point
  int maxIterations = 100;      ///< fits per scan (Algorithm 1) or per round (Algorithm 2)
  int maxRounds = 8;            ///< field rebuilds in Algorithm 2
  double roundTolerance = 0.1;  ///< Algorithm 2 ends below this, voxels
  RegistrationFieldMode field = RegistrationFieldMode::Grow;
  RegistrationSolve solve = RegistrationSolve::Joint;

  /// Every setting above, in --help's order.
  static const std::vector<Setting<RegistrationSettings>>& settings();
  /// Throws InputError with the message the fuse command gives for the first bad value.
  void validate() const;
};

inline void RegistrationSettings::validate() const {
  validateSettings(settings(), *this);
}

}  // namespace rangefuse
