#include "rangefuse/options/OutputSettings.h"

#include <cmath>

#include "rangefuse/render/Render.h"

namespace rangefuse {
namespace {

using Out = OutputSettings;

std::string checkPreviewView(const Out& s) {
  if (s.previewView.empty()) return "";
  if (s.preview.empty()) return "needs --preview FILE.png";
  ViewSettings v;
  try {
    parseView(s.previewView, v);
  } catch (const std::exception&) {
    return "must be AZIMUTH,ELEVATION in degrees, not '" + s.previewView + "'";
  }
  return "";
}

std::vector<Setting<Out>> outputTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"out", "", R::No, false, G::Output,
       "output mesh: .ply (binary), or .xdmf (HDF5 data in the same name .h5, for ParaView)",
       at(&Out::out), nullptr},
      {"report", "", R::No, false, G::Output,
       "write a JSON run report (stage times, counts, memory)", at(&Out::report), nullptr},
      {"preview", "", R::No, false, G::Output,
       "write a PNG picture of the mesh: around an object, from the first sensor inside a scene "
       "(stations, depth frames)",
       at(&Out::preview), nullptr},
      {"preview-view", "", R::No, false, G::Output,
       "AZIMUTH,ELEVATION in degrees of the --preview (azimuth about +y, 0 = from +z; default: "
       "0,20, or the first sensor's view)",
       at(&Out::previewView), checkPreviewView},
      {"up", "", R::No, false, G::Output,
       "the world's up axis of --preview-view: y, z (azimuth about +z, 0 = from -y), or auto (z "
       "for scanner stations, PTX and E57, else y)",
       at(&Out::up),
       [](const Out& s) -> std::string {
         return s.up == "auto" || s.up == "y" || s.up == "z" ? "" : "must be y, z or auto";
       }},
      {"poses-out", "", R::No, false, G::Output, "write the refined poses (.conf)",
       at(&Out::posesOut), nullptr},
      {"trajectory-out", "", R::No, false, G::Output,
       "write the camera trajectory: TUM text (timestamp tx ty tz qx qy qz qw), or a Redwood "
       ".log by extension",
       at(&Out::trajectoryOut), nullptr},
      {"checkpoint", "", R::No, false, G::Checkpoint, "write an HDF5 checkpoint of the field (.h5)",
       at(&Out::checkpoint), nullptr},
      {"checkpoint-every", "", R::No, false, G::Checkpoint,
       "seconds between registration or tracking checkpoints (0: after every scan, iteration "
       "or frame)",
       at(&Out::checkpointEvery),
       must<Out, double>(
           &Out::checkpointEvery, [](double v) { return v >= 0 && std::isfinite(v); },
           "must be a finite number of seconds >= 0")},
      {"overwrite", "", R::No, false, G::Checkpoint,
       "replace an existing --checkpoint that is not the one resumed (else the run is refused)",
       at(&Out::overwrite), nullptr, "true"},
      {"resume", "", R::No, false, G::Checkpoint,
       "continue from a checkpoint; options left out come from it, given ones must match",
       at(&Out::resume), nullptr}};
}

}  // namespace

const std::vector<Setting<OutputSettings>>& OutputSettings::settings() {
  static const std::vector<Setting<OutputSettings>> table = outputTable();
  return table;
}

}  // namespace rangefuse
