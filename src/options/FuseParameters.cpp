#include "rangefuse/options/FuseParameters.h"

#include <cmath>

#include "rangefuse/core/Error.h"

namespace rangefuse {
namespace {

using O = FuseOptions;

bool finite(double v) {
  return std::isfinite(v);
}

/// Appends `more` to `table`.
void append(std::vector<FuseParameter>& table, std::vector<FuseParameter> more) {
  for (FuseParameter& p : more) table.push_back(std::move(p));
}

/// Adds a check that needs options of other stages to the option named `option`.
void alsoCheck(std::vector<FuseParameter>& table, const std::string& option,
               std::function<std::string(const FuseOptions&)> more) {
  for (FuseParameter& p : table)
    if (p.option == option) {
      p.check = [own = p.check, more](const FuseOptions& o) {
        const std::string wrong = own ? own(o) : "";
        return wrong.empty() ? more(o) : wrong;
      };
    }
}

/// The options the command adds to the stages' own: how scans are prepared, the mesh, the
/// messages and resources.
std::vector<FuseParameter> commandOptions() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"min-weight", "min_weight", R::Result, false, G::Field,
       "voxels whose summed confidence is not above this are unobserved", at(&O::minWeight),
       must<O, float>(
           &O::minWeight, [](float v) { return std::isfinite(v); }, "must be finite")},
      {"merge-cells", "merge_cells_voxels", R::Result, false, G::Field,
       "merge blocks of k x k range-grid cells while k cells span at most this many voxels, so "
       "dense scans cost what the voxels need (0: never merge)",
       at(&O::mergeCells),
       must<O, double>(
           &O::mergeCells, [](double v) { return v >= 0 && finite(v); },
           "must be a number of voxels >= 0 (0: never merge)")},
      {"smooth-noise", "smooth_noise_voxels", R::Result, false, G::Field,
       "where a depth camera frame's measured noise exceeds this many voxels (its far walls), "
       "average its depths along rows and columns until it is about this (0: never)",
       at(&O::smoothNoise),
       must<O, double>(
           &O::smoothNoise, [](double v) { return v >= 0 && finite(v); },
           "must be a number of voxels >= 0 (0: never smooth)")},
      {"join-flat", "join_flat_voxels", R::Result, false, G::Field,
       "describe a block of 2 x 2 range-grid cells by two triangles where the surface is flat: "
       "where the chord departs from it by at most this many voxels (0: never join)",
       at(&O::joinFlat),
       must<O, double>(
           &O::joinFlat, [](double v) { return v >= 0 && finite(v); },
           "must be a number of voxels >= 0 (0: never join)")},
      {"band-cells", "band_cells", R::Result, false, G::Field,
       "PTX scans of more cells than this are read and prepared in bands of columns, each by "
       "any rank, so no rank holds a whole station (0: never split)",
       at(&O::bandCells),
       must<O, double>(
           &O::bandCells, [](double v) { return v >= 0 && v < 9e18; },
           "must be a number of cells >= 0 (0: never split)")},
      {"normal-passes", "normal_passes", R::Result, false, G::Field,
       "neighbour-averaging passes over vertex normals",
       [](O& o) -> SettingValue { return &o.surface.normalPasses; },
       [](const O& o) { return o.surface.normalPasses >= 0 ? "" : "must be >= 0"; }},
      {"depth-normal-passes", "depth_normal_passes", R::Result, false, G::Field,
       "the same for a depth camera's frames fused at known poses, whose noisier normals twist "
       "their prisms; frames being registered or tracked take --normal-passes (-1: as "
       "--normal-passes)",
       [](O& o) -> SettingValue { return &o.surface.depthNormalPasses; },
       [](const O& o) { return o.surface.depthNormalPasses >= -1 ? "" : "must be >= -1"; }},
      {"max-edge", "max_edge", R::Result, false, G::Field,
       "drop scan triangles with an edge longer than this x grid spacing",
       [](O& o) -> SettingValue { return &o.surface.maxEdgeFactor; },
       [](const O& o) {
         const double v = o.surface.maxEdgeFactor;
         return v > 0 && std::isfinite(v) ? "" : "must be positive and finite";
       }},
      {"min-cosine", "min_cosine", R::Result, false, G::Field,
       "drop scan triangles whose normal makes a cosine below this with the view ray",
       [](O& o) -> SettingValue { return &o.surface.minCosine; },
       [](const O& o) {
         const double v = o.surface.minCosine;
         return v >= -1 && v <= 1 ? "" : "must be in [-1, 1]";
       }},
      {"scan-memory", "", R::No, false, G::Resources,
       "MiB of prepared scans a rank keeps between reading and fusing; scans past it are read "
       "again (prism fields without registration stream their scans)",
       at(&O::scanMemory),
       must<O, double>(
           &O::scanMemory, [](double v) { return v >= 0 && finite(v); },
           "must be a finite number of MiB >= 0")},
      {"normals", "", R::No, false, G::Output, "write vertex normals", at(&O::normals), nullptr},
      {"quiet", "", R::No, false, G::Output,
       "print nothing but warnings and errors (standard error)", at(&O::quiet), nullptr, "true"},
      {"verbose", "", R::No, false, G::Output,
       "print every registration fit and every tracked frame (by default: a line a stage, "
       "registration rounds, a tracked frame a second and every lost one)",
       at(&O::verbose),
       [](const O& o) -> std::string {
         return o.quiet && o.verbose ? "cannot be given with --quiet" : "";
       },
       "true"}};
}

std::vector<FuseParameter> fuseTable() {
  std::vector<FuseParameter> table = {
      {"scans", "scans", Recorded::CheckpointOnly, true, OptionGroup::Input,
       "scan list: a .conf (Stanford bmesh lines; FILE.ptx#K and FILE.e57#K name a file's scan "
       "K), a Leica .ptx or an ASTM E57 file, or a folder holding a TUM RGB-D or Redwood "
       "depth-image sequence",
       at(&O::scans), [](const O& o) {
         return o.scans.empty() ? "is required (a .conf, a .ptx or .e57 file or a sequence folder)"
                                : "";
       }}};
  append(table, lift(io::ScanSourceOptions::settings(), &O::source));
  append(table, lift(FieldSettings::settings(), &O::field));
  append(table, commandOptions());
  append(table, lift(RegistrationSettings::settings(), &O::registration));
  append(table, lift(StreamSettings::settings(), &O::stream));
  append(table, lift(OutputSettings::settings(), &O::outputs));
  alsoCheck(table, "preview-every", [](const O& o) -> std::string {
    return o.stream.previewEvery > 0 && o.outputs.preview.empty() ? "needs --preview FILE.png" : "";
  });
  return table;
}

}  // namespace

const std::vector<FuseParameter>& fuseParameters() {
  static const std::vector<FuseParameter> table = fuseTable();
  return table;
}

nlohmann::json parameterJson(const FuseParameter& p, const FuseOptions& o) {
  FuseOptions& mutableOptions = const_cast<FuseOptions&>(o);  // read only: value() is shared
  return std::visit(Overloaded{[](auto* v) -> nlohmann::json { return *v; },
                               [](const EnumValue& v) -> nlohmann::json { return v.name(); }},
                    p.value(mutableOptions));
}

void setParameter(const FuseParameter& p, FuseOptions& o, const nlohmann::json& value) {
  try {
    std::visit(Overloaded{[&](auto* v) { *v = value.get<std::remove_pointer_t<decltype(v)>>(); },
                          [&](double* v) {  // JSON has no infinity: it is written as null
                            *v = value.is_null() ? INFINITY : value.get<double>();
                          },
                          [&](const EnumValue& v) { v.set(p.option, value.get<std::string>()); }},
               p.value(o));
  } catch (const nlohmann::json::exception&) {
    throw InputError("--" + p.option + ": " + value.dump() + " is not a value of this option");
  }
}

void parseParameter(const FuseParameter& p, FuseOptions& o, const std::string& text) {
  parseSetting(p.option, p.value(o), text);
}

std::string parameterText(const FuseParameter& p, const FuseOptions& o) {
  return settingText(p.value(const_cast<FuseOptions&>(o)));  // read only
}

void validateFuseOptions(const FuseOptions& o) {
  validateSettings(fuseParameters(), o);
}

nlohmann::json resultParameters(const FuseOptions& o) {
  nlohmann::json out = nlohmann::json::object();
  for (const FuseParameter& p : fuseParameters())
    if (p.recorded == Recorded::Result) out[p.key] = parameterJson(p, o);
  return out;
}

const char* groupTitle(OptionGroup group) {
  switch (group) {
    case OptionGroup::Input:
      return "Input";
    case OptionGroup::Field:
      return "Field";
    case OptionGroup::Output:
      return "Output";
    case OptionGroup::Registration:
      return "Registration (--register)";
    case OptionGroup::Tracking:
      return "Depth streams without poses (tracking)";
    case OptionGroup::Checkpoint:
      return "Checkpoints";
    case OptionGroup::Resources:
      return "Resources";
  }
  return "";
}

bool buildsField(OptionGroup group) {
  return group == OptionGroup::Input || group == OptionGroup::Field ||
         group == OptionGroup::Resources;
}

}  // namespace rangefuse
