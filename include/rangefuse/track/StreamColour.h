// The colour a tracking field fuses: decided once for a stream, by the command for a folder and
// by the library for frames given one at a time.
#pragma once

#include <string>
#include <vector>

#include "rangefuse/core/Colour.h"
#include "rangefuse/options/FieldSettings.h"

namespace rangefuse {

/// A stream's frames as far as they are known: each one's name and whether it has a colour
/// image. Frames that arrive later are unseen: `--colour auto` fuses depth alone then.
struct StreamFrames {
  std::vector<std::string> names;
  std::vector<bool> coloured;
  bool moreLater = false;  ///< frames arrive while the stream runs (--follow, the library)
};

/// RGB when every known frame has a colour image and `--colour` is auto or rgb, else none;
/// none for methods other than prism. Throws InputError naming `stream` for --colour
/// intensity (depth frames carry RGB), and naming the frame for --colour rgb on a frame
/// without colour.
ColourKind streamColour(const FieldSettings& field, const StreamFrames& frames,
                        const std::string& stream);

}  // namespace rangefuse
