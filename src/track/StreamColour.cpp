#include "rangefuse/track/StreamColour.h"

#include "rangefuse/core/Error.h"

namespace rangefuse {

ColourKind streamColour(const FieldSettings& field, const StreamFrames& frames,
                        const std::string& stream) {
  if (field.colour == "none" || field.method != FieldMethod::Prism) return ColourKind::none;
  if (field.colour == "intensity")
    throw InputError(stream + ": --colour intensity: depth streams carry colour images (rgb)");
  const bool rgb = field.colour == "rgb";
  if (frames.moreLater && !rgb) return ColourKind::none;
  for (size_t i = 0; i < frames.names.size(); ++i)
    if (!frames.coloured[i]) {
      if (rgb)
        throw InputError(frames.names[i] +
                         ": has no colour image, but --colour rgb asks every frame");
      return ColourKind::none;
    }
  return frames.names.empty() ? ColourKind::none : ColourKind::rgb;
}

}  // namespace rangefuse
