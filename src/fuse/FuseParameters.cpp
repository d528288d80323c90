#include "rangefuse/fuse/FuseParameters.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "rangefuse/core/Error.h"
#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

template <class T>
std::function<OptionValue(FuseOptions&)> at(T FuseOptions::*member) {
  return [member](FuseOptions& o) -> OptionValue { return &(o.*member); };
}

/// A check from a condition on the option's own value and the message when it fails.
template <class T>
std::function<std::string(const FuseOptions&)> must(T FuseOptions::*member, bool (*ok)(T),
                                                    const char* what) {
  return [member, ok, what](const FuseOptions& o) { return ok(o.*member) ? "" : what; };
}

bool finite(double v) {
  return std::isfinite(v);
}

std::string shortest(double v) {
  char text[64];
  // Whole numbers as users write them (4000000, not 4e+06), up to 2^53.
  if (v == std::floor(v) && std::fabs(v) < 9007199254740992.0) {
    std::snprintf(text, sizeof text, "%.0f", v);
    return text;
  }
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

double number(const FuseParameter& p, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE)
    throw InputError("--" + p.option + ": '" + text + "' is not a number");
  return v;
}

int integer(const FuseParameter& p, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < INT32_MIN || v > INT32_MAX)
    throw InputError("--" + p.option + ": '" + text + "' is not a whole number");
  return static_cast<int>(v);
}

bool truth(const FuseParameter& p, const std::string& text) {
  for (const char* yes : {"true", "1", "yes", "on"})
    if (text == yes) return true;
  for (const char* no : {"false", "0", "no", "off"})
    if (text == no) return false;
  throw InputError("--" + p.option + ": '" + text + "' is not true or false");
}

template <class... F>
struct Visit : F... {
  using F::operator()...;
};
template <class... F>
Visit(F...) -> Visit<F...>;

/// Every registered method with its summary.
std::string methodHelp() {
  std::string help = "field:";
  for (const MethodInfo& m : methodRegistry())
    help += std::string(" ") + m.name + ": " + m.summary + ";";
  help.back() = '.';
  return help;
}

std::vector<FuseParameter> makeTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"scans", "scans", R::CheckpointOnly, true, G::Input,
       "scan list: a .conf (Stanford bmesh lines; FILE.ptx#K and FILE.e57#K name a file's scan "
       "K), a Leica .ptx or an ASTM E57 file, or a folder holding a TUM RGB-D or Redwood "
       "depth-image sequence",
       at(&FuseOptions::scans),
       [](const FuseOptions& o) {
         return o.scans.empty() ? "is required (a .conf, a .ptx or .e57 file or a sequence folder)"
                                : "";
       }},
      {"scan-format", "scan_format", R::CheckpointOnly, false, G::Input,
       "how to read --scans: auto (from the name: folder, .ptx, .e57, else .conf), conf, ptx, "
       "e57, tum or redwood",
       [](FuseOptions& o) -> OptionValue { return &o.source.format; },
       [](const FuseOptions& o) {
         for (const char* f : {"auto", "conf", "ptx", "e57", "tum", "redwood"})
           if (o.source.format == f) return "";
         return "must be auto, conf, ptx, e57, tum or redwood";
       }},
      {"intrinsics", "intrinsics", R::Result, false, G::Input,
       "depth images: camera intrinsics 'fx,fy,cx,cy' in pixels or an Open3D "
       "camera_intrinsic.json (default: the sequence folder's camera_intrinsic.json)",
       [](FuseOptions& o) -> OptionValue { return &o.source.intrinsics; }, nullptr},
      {"depth-max", "depth_max", R::Result, false, G::Input,
       "depth images: measurements farther than this from the camera are dropped, in the scans' "
       "units (0: keep all)",
       [](FuseOptions& o) -> OptionValue { return &o.source.maxDepth; },
       [](const FuseOptions& o) {
         const double v = o.source.maxDepth;
         return v >= 0 && std::isfinite(v) ? "" : "must be a finite distance >= 0 (0: keep all)";
       }},
      {"depth-scale", "depth_scale", R::Result, false, G::Input,
       "depth images: counts per metre (0: the layout's own, 5000 for TUM, 1000 for Redwood and "
       "Open3D's recorder)",
       [](FuseOptions& o) -> OptionValue { return &o.source.depthScale; },
       [](const FuseOptions& o) {
         const double v = o.source.depthScale;
         return v >= 0 && std::isfinite(v) ? "" : "must be a finite number of counts >= 0";
       }},
      {"voxel", "voxel", R::Result, true, G::Field, "voxel size, in the scans' units",
       at(&FuseOptions::voxel),
       [](const FuseOptions& o) -> std::string {
         if (o.voxel == 0)  // the default: not given
           return "is required: the voxel size in the scans' units (e.g. --voxel 0.001 for 1 mm "
                  "voxels on scans in metres)";
         return o.voxel > 0 && std::isfinite(o.voxel) ? ""
                                                      : "must be positive and finite (in the "
                                                        "scans' units)";
       }},
      {"method", "method", R::Result, false, G::Field, methodHelp(), at(&FuseOptions::method),
       nullptr},
      {"colour", "colour", R::Result, false, G::Field,
       "colour of the mesh: auto (what every scan carries: red green blue, or intensity), rgb, "
       "intensity or none; fused by --method prism and robust",
       at(&FuseOptions::colour),
       [](const FuseOptions& o) -> std::string {
         if (o.colour != "auto" && o.colour != "rgb" && o.colour != "intensity" &&
             o.colour != "none")
           return "must be auto, rgb, intensity or none";
         if ((o.colour == "rgb" || o.colour == "intensity") && methodInfo(o.method).closestSurface)
           return "needs --method prism or robust (the others fuse depth only)";
         return "";
       }},
      {"envelope", "envelope_voxels", R::Result, false, G::Field, "prism half-thickness, voxels",
       at(&FuseOptions::envelope),
       must<double>(
           &FuseOptions::envelope, [](double v) { return v > 0 && v <= 1000; },
           "must be in (0, 1000] voxels")},
      {"quorum", "quorum", R::Result, false, G::Field,
       "consensus: summed confidence a consensus surface needs (-1: 2.25 x views / 48)",
       at(&FuseOptions::quorum),
       must<double>(
           &FuseOptions::quorum, [](double v) { return std::isfinite(v) && (v >= 0 || v == -1); },
           "must not be negative (or -1: scaled to the number of views)")},
      {"min-views", "min_views", R::Result, false, G::Field,
       "consensus and robust: views a surface needs besides the quorum, so that one view alone "
       "never passes where few views make the quorum small (1: the quorum alone)",
       at(&FuseOptions::minViews),
       must<int>(
           &FuseOptions::minViews, [](int v) { return v >= 1; }, "must be at least 1")},
      {"edge-angle", "edge_angle_deg", R::Result, false, G::Field,
       "consensus: a point whose offset from its surface point is more than this many degrees "
       "from the normal lies beside an open edge and stays unobserved (90: off)",
       at(&FuseOptions::edgeAngle),
       must<double>(
           &FuseOptions::edgeAngle, [](double v) { return v >= 0 && v <= 90; },
           "must be in [0, 90] degrees")},
      {"same-distance", "same_distance_voxels", R::Result, false, G::Field,
       "consensus and robust: observations within this many voxels may be the same surface",
       at(&FuseOptions::sameDistance),
       must<double>(
           &FuseOptions::sameDistance, [](double v) { return v > 0 && v <= 1000; },
           "must be in (0, 1000] voxels")},
      {"same-angle", "same_angle_deg", R::Result, false, G::Field,
       "consensus and robust: ... if their normals differ by at most this many degrees",
       at(&FuseOptions::sameAngle),
       must<double>(
           &FuseOptions::sameAngle, [](double v) { return v > 0 && v <= 180; },
           "must be in (0, 180] degrees")},
      {"free-margin", "free_margin_voxels", R::Result, false, G::Field,
       "robust: an image looked through a point lying more than this many voxels before what it "
       "saw along its line of sight (-1: the envelope; inf: free space off, so a surface fewer "
       "than --min-views images saw never stands)",
       at(&FuseOptions::freeMargin),
       must<double>(
           &FuseOptions::freeMargin, [](double v) { return v >= 0 || v == -1; },
           "must be a number of voxels >= 0 (-1: the envelope; inf: off)")},
      {"fill-holes", "fill_holes", R::Result, false, G::Field,
       "close the mesh: space behind what the scans saw that none looked through (by more than "
       "--free-margin) counts as inside, so holes close; vertices of the fill are marked "
       "(PLY property and XDMF attribute 'filled')",
       at(&FuseOptions::fillHoles), nullptr, "true"},
      {"brick", "brick", R::Result, false, G::Field, "voxels per brick edge",
       at(&FuseOptions::brick),
       must<int>(
           &FuseOptions::brick, [](int v) { return v >= 2 && v <= 64; },
           "must be between 2 and 64")},
      {"min-weight", "min_weight", R::Result, false, G::Field,
       "voxels whose summed confidence is not above this are unobserved",
       at(&FuseOptions::minWeight),
       must<float>(
           &FuseOptions::minWeight, [](float v) { return std::isfinite(v); }, "must be finite")},
      {"merge-cells", "merge_cells_voxels", R::Result, false, G::Field,
       "merge blocks of k x k range-grid cells while k cells span at most this many voxels, so "
       "dense scans cost what the voxels need (0: never merge)",
       at(&FuseOptions::mergeCells),
       must<double>(
           &FuseOptions::mergeCells, [](double v) { return v >= 0 && finite(v); },
           "must be a number of voxels >= 0 (0: never merge)")},
      {"smooth-noise", "smooth_noise_voxels", R::Result, false, G::Field,
       "where a scan's measured depth noise exceeds this many voxels (a depth camera's far "
       "walls), average its depths along rows and columns until it is about this (0: never)",
       at(&FuseOptions::smoothNoise),
       must<double>(
           &FuseOptions::smoothNoise, [](double v) { return v >= 0 && finite(v); },
           "must be a number of voxels >= 0 (0: never smooth)")},
      {"band-cells", "band_cells", R::Result, false, G::Field,
       "PTX scans of more cells than this are read and prepared in bands of columns, each by "
       "any rank, so no rank holds a whole station (0: never split)",
       at(&FuseOptions::bandCells),
       must<double>(
           &FuseOptions::bandCells, [](double v) { return v >= 0 && v < 9e18; },
           "must be a number of cells >= 0 (0: never split)")},
      {"normal-passes", "normal_passes", R::Result, false, G::Field,
       "neighbour-averaging passes over vertex normals",
       [](FuseOptions& o) -> OptionValue { return &o.surface.normalPasses; },
       [](const FuseOptions& o) { return o.surface.normalPasses >= 0 ? "" : "must be >= 0"; }},
      {"max-edge", "max_edge", R::Result, false, G::Field,
       "drop scan triangles with an edge longer than this x grid spacing",
       [](FuseOptions& o) -> OptionValue { return &o.surface.maxEdgeFactor; },
       [](const FuseOptions& o) {
         const double v = o.surface.maxEdgeFactor;
         return v > 0 && std::isfinite(v) ? "" : "must be positive and finite";
       }},
      {"min-cosine", "min_cosine", R::Result, false, G::Field,
       "drop scan triangles whose normal makes a cosine below this with the view ray",
       [](FuseOptions& o) -> OptionValue { return &o.surface.minCosine; },
       [](const FuseOptions& o) {
         const double v = o.surface.minCosine;
         return v >= -1 && v <= 1 ? "" : "must be in [-1, 1]";
       }},
      {"scan-memory", "", R::No, false, G::Resources,
       "MiB of prepared scans a rank keeps between reading and fusing; scans past it are read "
       "again (prism fields without registration stream their scans)",
       at(&FuseOptions::scanMemory),
       must<double>(
           &FuseOptions::scanMemory, [](double v) { return v >= 0 && finite(v); },
           "must be a finite number of MiB >= 0")},
      {"threads", "", R::No, false, G::Resources,
       "threads per rank for reading scans and adding them to the field (0: the CPUs the rank "
       "may run on, shared among the ranks on its node); any count gives the same bits",
       at(&FuseOptions::threads),
       must<int>(
           &FuseOptions::threads, [](int v) { return v >= 0; },
           "must be >= 0 (0: the rank's share of its CPUs)")},
      {"out", "", R::No, false, G::Output,
       "output mesh: .ply (binary), or .xdmf (HDF5 data in the same name .h5, for ParaView)",
       at(&FuseOptions::out), nullptr},
      {"report", "", R::No, false, G::Output,
       "write a JSON run report (stage times, counts, memory)", at(&FuseOptions::report), nullptr},
      {"preview", "", R::No, false, G::Output,
       "write a PNG picture of the mesh: around an object, from the first sensor inside a scene "
       "(stations, depth frames)",
       at(&FuseOptions::preview), nullptr},
      {"preview-view", "", R::No, false, G::Output,
       "AZIMUTH,ELEVATION in degrees of the --preview (azimuth about +y, 0 = from +z; default: "
       "0,20, or the first sensor's view)",
       at(&FuseOptions::previewView),
       [](const FuseOptions& o) -> std::string {
         if (o.previewView.empty()) return "";
         if (o.preview.empty()) return "needs --preview FILE.png";
         ViewSettings v;
         try {
           parseView(o.previewView, v);
         } catch (const std::exception& e) {
           return "must be AZIMUTH,ELEVATION in degrees, not '" + o.previewView + "'";
         }
         return "";
       }},
      {"up", "", R::No, false, G::Output,
       "the world's up axis of --preview-view: y, z (azimuth about +z, 0 = from -y), or auto (z "
       "for scanner stations, PTX and E57, else y)",
       at(&FuseOptions::up),
       [](const FuseOptions& o) -> std::string {
         return o.up == "auto" || o.up == "y" || o.up == "z" ? "" : "must be y, z or auto";
       }},
      {"normals", "", R::No, false, G::Output, "write vertex normals", at(&FuseOptions::normals),
       nullptr},
      {"quiet", "", R::No, false, G::Output,
       "print nothing but warnings and errors (standard error)", at(&FuseOptions::quiet), nullptr,
       "true"},
      {"verbose", "", R::No, false, G::Output,
       "print every registration fit and every tracked frame (by default: a line a stage, "
       "registration rounds, a tracked frame a second and every lost one)",
       at(&FuseOptions::verbose),
       [](const FuseOptions& o) -> std::string {
         return o.quiet && o.verbose ? "cannot be given with --quiet" : "";
       },
       "true"},
      {"register", "register", R::Result, false, G::Registration,
       "refine poses against the field: none, incremental (Algorithm 1), simultaneous "
       "(Algorithm 2) or both (1 then 2)",
       at(&FuseOptions::registration), nullptr},
      {"anchor", "anchor", R::Result, false, G::Registration,
       "registration: scan name that stays fixed (default: first)", at(&FuseOptions::anchor),
       nullptr},
      {"control-stride", "control_stride", R::Result, false, G::Registration,
       "registration: every k-th scan vertex is a control point", at(&FuseOptions::controlStride),
       must<int>(
           &FuseOptions::controlStride, [](int v) { return v >= 1; }, "must be at least 1")},
      {"max-iterations", "max_iterations", R::Result, false, G::Registration,
       "registration: fits per scan (Algorithm 1) or per field rebuild (Algorithm 2)",
       at(&FuseOptions::maxIterations),
       must<int>(
           &FuseOptions::maxIterations, [](int v) { return v >= 1; }, "must be at least 1")},
      {"max-rounds", "max_rounds", R::Result, false, G::Registration,
       "registration: field rebuilds in Algorithm 2", at(&FuseOptions::maxRounds),
       must<int>(
           &FuseOptions::maxRounds, [](int v) { return v >= 1; }, "must be at least 1")},
      {"round-tolerance", "round_tolerance_voxels", R::Result, false, G::Registration,
       "registration: Algorithm 2 ends after a round that moves no scan's vertices this far on "
       "average, voxels",
       at(&FuseOptions::roundTolerance),
       must<double>(
           &FuseOptions::roundTolerance, [](double v) { return v >= 0 && v <= 1000; },
           "must be in [0, 1000] voxels")},
      {"register-field", "register_field", R::Result, false, G::Registration,
       "registration: grow (Algorithm 1 adds each scan to one field; prism only) or rebuild (a "
       "new field for every scan: the simple method, for comparison)",
       at(&FuseOptions::registerField), nullptr},
      {"register-solve", "register_solve", R::Result, false, G::Registration,
       "registration: joint (Algorithm 2 solves all poses at once, the anchor fixing the frame) "
       "or per-scan (each scan fitted to the field on its own, as in the paper)",
       at(&FuseOptions::registerSolve), nullptr},
      {"poses-out", "", R::No, false, G::Output, "write the refined poses (.conf)",
       at(&FuseOptions::posesOut), nullptr},
      {"track", "track", R::Result, false, G::Tracking,
       "depth streams: track every frame against the field of the frames before it (on), use "
       "the given trajectory (off), or track only when there is none (auto); with a trajectory, "
       "tracking takes its motion as each frame's first guess",
       at(&FuseOptions::track),
       [](const FuseOptions& o) {
         return o.track == "on" || o.track == "off" || o.track == "auto"
                    ? ""
                    : "must be on, off or auto";
       },
       "on"},
      {"first-pose", "first_pose", R::Result, false, G::Tracking,
       "tracking: the first camera's pose in the world, 'tx,ty,tz,qx,qy,qz,qw' (camera to "
       "world, as TUM writes it; default: the identity)",
       at(&FuseOptions::firstPose), nullptr},
      {"min-inliers", "min_inliers", R::Result, false, G::Tracking,
       "tracking: a frame is lost when fewer of its points than this share find the field",
       at(&FuseOptions::minInliers),
       must<double>(
           &FuseOptions::minInliers, [](double v) { return v >= 0 && v <= 1; },
           "must be a share in [0, 1]")},
      {"max-step", "max_step_voxels", R::Result, false, G::Tracking,
       "tracking: a frame is lost when its fit puts the camera more than this many voxels from "
       "where its motion so far predicted (a slide along a wall, not a motion)",
       at(&FuseOptions::maxStep),
       must<double>(
           &FuseOptions::maxStep, [](double v) { return v > 0; }, "must be positive voxels")},
      {"skip-lost", "skip_lost", R::Result, false, G::Tracking,
       "tracking: leave frames that lost tracking out and go on (else the run stops at the first "
       "with an error)",
       at(&FuseOptions::skipLost), nullptr, "true"},
      {"preview-every", "", R::No, false, G::Tracking,
       "tracking: every N frames, write --preview as the partial model seen from the current "
       "camera (the last picture is the finished field's)",
       at(&FuseOptions::previewEvery),
       [](const FuseOptions& o) {
         if (o.previewEvery < 0) return "must be a number of frames >= 0 (0: never)";
         return o.previewEvery > 0 && o.preview.empty() ? "needs --preview FILE.png" : "";
       }},
      {"follow", "", R::No, false, G::Tracking,
       "tracking: the folder is still being recorded: frames that appear in it join the stream "
       "until a file named STOP appears there or --follow-timeout passes with no new frame",
       at(&FuseOptions::follow), nullptr, "true"},
      {"follow-timeout", "", R::No, false, G::Tracking,
       "tracking: with --follow, seconds without a new frame after which the stream ends",
       at(&FuseOptions::followTimeout),
       must<double>(
           &FuseOptions::followTimeout, [](double v) { return v > 0 && finite(v); },
           "must be a positive number of seconds")},
      {"trajectory-out", "", R::No, false, G::Output,
       "write the camera trajectory: TUM text (timestamp tx ty tz qx qy qz qw), or a Redwood "
       ".log by extension",
       at(&FuseOptions::trajectoryOut), nullptr},
      {"checkpoint", "", R::No, false, G::Checkpoint, "write an HDF5 checkpoint of the field (.h5)",
       at(&FuseOptions::checkpoint), nullptr},
      {"checkpoint-every", "", R::No, false, G::Checkpoint,
       "seconds between registration or tracking checkpoints (0: after every scan, iteration "
       "or frame)",
       at(&FuseOptions::checkpointEvery),
       must<double>(
           &FuseOptions::checkpointEvery, [](double v) { return v >= 0 && finite(v); },
           "must be a finite number of seconds >= 0")},
      {"overwrite", "", R::No, false, G::Checkpoint,
       "replace an existing --checkpoint that is not the one resumed (else the run is refused)",
       at(&FuseOptions::overwrite), nullptr, "true"},
      {"resume", "", R::No, false, G::Checkpoint,
       "continue from a checkpoint; options left out come from it, given ones must match",
       at(&FuseOptions::resume), nullptr}};
}

}  // namespace

const std::vector<FuseParameter>& fuseParameters() {
  static const std::vector<FuseParameter> table = makeTable();
  return table;
}

nlohmann::json parameterJson(const FuseParameter& p, const FuseOptions& o) {
  FuseOptions& mutableOptions = const_cast<FuseOptions&>(o);  // read only: value() is shared
  return std::visit(Visit{[](auto* v) -> nlohmann::json { return *v; },
                          [](FieldMethod* v) -> nlohmann::json { return toString(*v); },
                          [](RegistrationMode* v) -> nlohmann::json { return toString(*v); },
                          [](RegistrationFieldMode* v) -> nlohmann::json { return toString(*v); },
                          [](RegistrationSolve* v) -> nlohmann::json { return toString(*v); }},
                    p.value(mutableOptions));
}

void setParameter(const FuseParameter& p, FuseOptions& o, const nlohmann::json& value) {
  try {
    std::visit(
        Visit{[&](auto* v) { *v = value.get<std::remove_pointer_t<decltype(v)>>(); },
              [&](double* v) {  // JSON has no infinity: it is written as null
                *v = value.is_null() ? INFINITY : value.get<double>();
              },
              [&](FieldMethod* v) { *v = parseFieldMethod(p.option, value.get<std::string>()); },
              [&](RegistrationMode* v) {
                *v = parseRegistrationMode(p.option, value.get<std::string>());
              },
              [&](RegistrationFieldMode* v) {
                *v = parseRegistrationFieldMode(p.option, value.get<std::string>());
              },
              [&](RegistrationSolve* v) {
                *v = parseRegistrationSolve(p.option, value.get<std::string>());
              }},
        p.value(o));
  } catch (const nlohmann::json::exception&) {
    throw InputError("--" + p.option + ": " + value.dump() + " is not a value of this option");
  }
}

void parseParameter(const FuseParameter& p, FuseOptions& o, const std::string& text) {
  std::visit(
      Visit{[&](double* v) { *v = number(p, text); },
            [&](float* v) { *v = static_cast<float>(number(p, text)); },
            [&](int* v) { *v = integer(p, text); }, [&](bool* v) { *v = truth(p, text); },
            [&](std::string* v) { *v = text; },
            [&](FieldMethod* v) { *v = parseFieldMethod(p.option, text); },
            [&](RegistrationMode* v) { *v = parseRegistrationMode(p.option, text); },
            [&](RegistrationFieldMode* v) { *v = parseRegistrationFieldMode(p.option, text); },
            [&](RegistrationSolve* v) { *v = parseRegistrationSolve(p.option, text); }},
      p.value(o));
}

std::string parameterText(const FuseParameter& p, const FuseOptions& o) {
  const nlohmann::json j = parameterJson(p, o);
  if (j.is_string()) return j.get<std::string>();
  if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
  if (j.is_number_integer()) return std::to_string(j.get<long long>());
  return shortest(j.get<double>());
}

void validateFuseOptions(const FuseOptions& o) {
  for (const FuseParameter& p : fuseParameters()) {
    const std::string wrong = p.check ? p.check(o) : "";
    if (!wrong.empty()) throw InputError("--" + p.option + " " + wrong);
  }
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
