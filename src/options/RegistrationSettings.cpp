#include "rangefuse/options/RegistrationSettings.h"

namespace rangefuse {
namespace {

using Reg = RegistrationSettings;

std::vector<Setting<Reg>> registrationTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"register", "register", R::Result, false, G::Registration,
       "refine poses against the field: none, incremental (Algorithm 1), simultaneous "
       "(Algorithm 2) or both (1 then 2)",
       enumAt(
           &Reg::mode, [](RegistrationMode m) { return toString(m); }, parseRegistrationMode),
       nullptr},
      {"anchor", "anchor", R::Result, false, G::Registration,
       "registration: scan name that stays fixed (default: first)", at(&Reg::anchor), nullptr},
      {"control-stride", "control_stride", R::Result, false, G::Registration,
       "registration: every k-th scan vertex is a control point", at(&Reg::controlStride),
       must<Reg, int>(
           &Reg::controlStride, [](int v) { return v >= 1; }, "must be at least 1")},
      {"max-iterations", "max_iterations", R::Result, false, G::Registration,
       "registration: fits per scan (Algorithm 1) or per field rebuild (Algorithm 2)",
       at(&Reg::maxIterations),
       must<Reg, int>(
           &Reg::maxIterations, [](int v) { return v >= 1; }, "must be at least 1")},
      {"max-rounds", "max_rounds", R::Result, false, G::Registration,
       "registration: field rebuilds in Algorithm 2", at(&Reg::maxRounds),
       must<Reg, int>(
           &Reg::maxRounds, [](int v) { return v >= 1; }, "must be at least 1")},
      {"round-tolerance", "round_tolerance_voxels", R::Result, false, G::Registration,
       "registration: Algorithm 2 ends after a round that moves no scan's vertices this far on "
       "average, voxels",
       at(&Reg::roundTolerance),
       must<Reg, double>(
           &Reg::roundTolerance, [](double v) { return v >= 0 && v <= 1000; },
           "must be in [0, 1000] voxels")},
      {"register-field", "register_field", R::Result, false, G::Registration,
       "registration: grow (Algorithm 1 adds each scan to one field; prism only) or rebuild (a "
       "new field for every scan: the simple method, for comparison)",
       enumAt(
           &Reg::field, [](RegistrationFieldMode m) { return toString(m); },
           parseRegistrationFieldMode),
       nullptr},
      {"register-solve", "register_solve", R::Result, false, G::Registration,
       "registration: joint (Algorithm 2 solves all poses at once, the anchor fixing the frame) "
       "or per-scan (each scan fitted to the field on its own, as in the paper)",
       enumAt(
           &Reg::solve, [](RegistrationSolve m) { return toString(m); }, parseRegistrationSolve),
       nullptr}};
}

}  // namespace

const std::vector<Setting<RegistrationSettings>>& RegistrationSettings::settings() {
  static const std::vector<Setting<RegistrationSettings>> table = registrationTable();
  return table;
}

}  // namespace rangefuse
