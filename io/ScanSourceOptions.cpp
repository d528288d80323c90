#include "rangefuse/io/ScanSourceOptions.h"

#include <cmath>

namespace rangefuse::io {
namespace {

using Source = ScanSourceOptions;

std::vector<Setting<Source>> sourceTable() {
  using R = Recorded;
  using G = OptionGroup;
  return {
      {"scan-format", "scan_format", R::CheckpointOnly, false, G::Input,
       "how to read --scans: " + scanFormatWords() +
           " (auto: from the name: a folder by its files, .ptx, .e57, else .conf)",
       at(&Source::format),
       [](const Source& s) -> std::string {
         for (const char* f : kScanFormats)
           if (s.format == f) return "";
         return "'" + s.format + "': must be " + scanFormatWords();
       }},
      {"intrinsics", "intrinsics", R::Result, false, G::Input,
       "depth images: camera intrinsics 'fx,fy,cx,cy' in pixels or an Open3D "
       "camera_intrinsic.json (default: the sequence folder's camera_intrinsic.json)",
       at(&Source::intrinsics), nullptr},
      {"depth-max", "depth_max", R::Result, false, G::Input,
       "depth images: measurements farther than this from the camera are dropped, in the scans' "
       "units (0: keep all)",
       at(&Source::depthMax),
       must<Source, double>(
           &Source::depthMax, [](double v) { return v >= 0 && std::isfinite(v); },
           "must be a finite distance >= 0 (0: keep all)")},
      {"depth-scale", "depth_scale", R::Result, false, G::Input,
       "depth images: counts per metre (0: the layout's own, 5000 for TUM, 1000 for Redwood and "
       "Open3D's recorder)",
       at(&Source::depthScale),
       must<Source, double>(
           &Source::depthScale, [](double v) { return v >= 0 && std::isfinite(v); },
           "must be a finite number of counts >= 0")}};
}

}  // namespace

std::string scanFormatWords() {
  std::string words;
  for (size_t k = 0; k < kScanFormats.size(); ++k)
    words += (k == 0                         ? ""
              : k + 1 == kScanFormats.size() ? " or "
                                             : ", ") +
             std::string(kScanFormats[k]);
  return words;
}

const std::vector<Setting<ScanSourceOptions>>& ScanSourceOptions::settings() {
  static const std::vector<Setting<ScanSourceOptions>> table = sourceTable();
  return table;
}

}  // namespace rangefuse::io
