#include "rangefuse/core/Colour.h"

#include "rangefuse/core/Error.h"

namespace rangefuse {

std::string colourKindName(ColourKind kind) {
  switch (kind) {
    case ColourKind::rgb:
      return "rgb";
    case ColourKind::intensity:
      return "intensity";
    default:
      return "none";
  }
}

ColourKind parseColourKind(const std::string& text, ColourKind given) {
  if (text == "auto") return given;
  if (text == "rgb") return ColourKind::rgb;
  if (text == "intensity") return ColourKind::intensity;
  if (text == "none") return ColourKind::none;
  throw InputError("--colour must be auto, rgb, intensity or none, not '" + text + "'");
}

}  // namespace rangefuse
