#include "rangefuse/options/FieldSettings.h"

#include <cmath>

namespace rangefuse {
namespace {

using F = FieldSettings;

/// Every registered method with its summary.
std::string methodHelp() {
  std::string help = "field:";
  for (const MethodInfo& m : methodRegistry())
    help += std::string(" ") + m.name + ": " + m.summary + ";";
  help.back() = '.';
  return help;
}

std::string checkVoxel(const F& f) {
  if (f.voxel == 0)  // the default: not given
    return "is required: the voxel size in the scans' units (e.g. --voxel 0.001 for 1 mm voxels "
           "on scans in metres)";
  return f.voxel > 0 && std::isfinite(f.voxel) ? ""
                                               : "must be positive and finite (in the scans' "
                                                 "units)";
}

std::string checkColour(const F& f) {
  if (f.colour != "auto" && f.colour != "rgb" && f.colour != "intensity" && f.colour != "none")
    return "must be auto, rgb, intensity or none";
  if ((f.colour == "rgb" || f.colour == "intensity") && methodInfo(f.method).closestSurface)
    return "needs --method prism or robust (the others fuse depth only)";
  return "";
}

std::vector<Setting<F>> fieldTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"voxel", "voxel", R::Result, true, G::Field, "voxel size, in the scans' units",
       at(&F::voxel), checkVoxel},
      {"method", "method", R::Result, false, G::Field, methodHelp(),
       enumAt(
           &F::method, [](FieldMethod m) { return toString(m); }, parseFieldMethod),
       nullptr},
      {"colour", "colour", R::Result, false, G::Field,
       "colour of the mesh: auto (what every scan carries: red green blue, or intensity), rgb, "
       "intensity or none; fused by --method prism and robust",
       at(&F::colour), checkColour},
      {"envelope", "envelope_voxels", R::Result, false, G::Field, "prism half-thickness, voxels",
       at(&F::envelope),
       must<F, double>(
           &F::envelope, [](double v) { return v > 0 && v <= 1000; },
           "must be in (0, 1000] voxels")},
      {"quorum", "quorum", R::Result, false, G::Field,
       "consensus: summed confidence a consensus surface needs (-1: 2.25 x views / 48)",
       at(&F::quorum),
       must<F, double>(
           &F::quorum, [](double v) { return std::isfinite(v) && (v >= 0 || v == -1); },
           "must not be negative (or -1: scaled to the number of views)")},
      {"min-views", "min_views", R::Result, false, G::Field,
       "consensus and robust: views a surface needs besides the quorum, so that one view alone "
       "never passes where few views make the quorum small (1: the quorum alone)",
       at(&F::minViews),
       must<F, int>(
           &F::minViews, [](int v) { return v >= 1; }, "must be at least 1")},
      {"edge-angle", "edge_angle_deg", R::Result, false, G::Field,
       "consensus: a point whose offset from its surface point is more than this many degrees "
       "from the normal lies beside an open edge and stays unobserved (90: off)",
       at(&F::edgeAngle),
       must<F, double>(
           &F::edgeAngle, [](double v) { return v >= 0 && v <= 90; },
           "must be in [0, 90] degrees")},
      {"same-distance", "same_distance_voxels", R::Result, false, G::Field,
       "consensus and robust: observations within this many voxels may be the same surface",
       at(&F::sameDistance),
       must<F, double>(
           &F::sameDistance, [](double v) { return v > 0 && v <= 1000; },
           "must be in (0, 1000] voxels")},
      {"same-angle", "same_angle_deg", R::Result, false, G::Field,
       "consensus and robust: ... if their normals differ by at most this many degrees",
       at(&F::sameAngle),
       must<F, double>(
           &F::sameAngle, [](double v) { return v > 0 && v <= 180; },
           "must be in (0, 180] degrees")},
      {"free-margin", "free_margin_voxels", R::Result, false, G::Field,
       "robust: an image looked through a point lying more than this many voxels before what it "
       "saw along its line of sight (-1: the envelope; inf: free space off, so a surface fewer "
       "than --min-views images saw never stands)",
       at(&F::freeMargin),
       must<F, double>(
           &F::freeMargin, [](double v) { return v >= 0 || v == -1; },
           "must be a number of voxels >= 0 (-1: the envelope; inf: off)")},
      {"fill-holes", "fill_holes", R::Result, false, G::Field,
       "close the mesh: space behind what the scans saw that none looked through (by more than "
       "--free-margin) counts as inside, so holes close; vertices of the fill are marked "
       "(PLY property and XDMF attribute 'filled')",
       at(&F::fillHoles), nullptr, "true"},
      {"brick", "brick", R::Result, false, G::Field, "voxels per brick edge", at(&F::brick),
       must<F, int>(
           &F::brick, [](int v) { return v >= 2 && v <= 64; }, "must be between 2 and 64")},
      {"threads", "", R::No, false, G::Resources,
       "threads per rank for reading scans and adding them to the field (0: the CPUs the rank "
       "may run on, shared among the ranks on its node); any count gives the same bits",
       at(&F::threads),
       must<F, int>(
           &F::threads, [](int v) { return v >= 0; },
           "must be >= 0 (0: the rank's share of its CPUs)")}};
}

}  // namespace

const std::vector<Setting<FieldSettings>>& FieldSettings::settings() {
  static const std::vector<Setting<FieldSettings>> table = fieldTable();
  return table;
}

}  // namespace rangefuse
